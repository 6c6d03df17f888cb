"""What drives a robot: the policy protocol every controller implements, built-in or the user's.

A policy is built without arguments (or with its own keyword options), then
:meth:`Policy.reset` tells it which robot it plays and seeds it before every match;
:meth:`Policy.act` maps each new observation (:func:`match.protocol.spaces.observation_space`)
to an action (an :class:`~match.protocol.actions.Action` or an action dict). A policy that
also implements :class:`PoseReporter` has its pose estimate recorded in the match log beside
the truth (evaluation only: nothing in the match reads it).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, Protocol, runtime_checkable

PoseTuple = tuple[float, float, float]  # x m, y m, theta rad, in the field frame


@runtime_checkable
class Policy(Protocol):
    """A robot's controller."""

    def reset(self, agent_id: str, seed: int) -> None:
        """Forget the last match; play robot ``agent_id`` (``home_0`` .. ``away_3``) with this seed."""

    def act(self, observation: Mapping[str, Any]) -> Any:
        """The action for this control step (40 ms), from this step's observation only."""


@runtime_checkable
class PoseReporter(Protocol):
    """A policy that can tell where it believes its robot is."""

    def pose_estimate(self) -> PoseTuple | None:
        """The robot's pose as the policy believes it now (field frame), or None when it has none."""
