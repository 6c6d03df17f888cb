"""The ``stand`` policy: the robot stands where it is, head level, camera off."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from match.protocol import CameraChoice, Motion, make_action


class StandPolicy:
    """Stands still every step (:class:`match.protocol.policy.Policy`); reads nothing, draws nothing."""

    def reset(self, agent_id: str, seed: int) -> None:
        """Nothing to forget."""

    def act(self, observation: Mapping[str, Any]) -> dict:
        return make_action(Motion.STAND, camera=CameraChoice.OFF)
