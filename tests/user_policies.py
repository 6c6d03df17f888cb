"""Policies as a user would write them in their own module, chosen by ``tests.user_policies:Name``."""

from __future__ import annotations

from match.protocol import CameraChoice, Motion, make_action


class Spinner:
    """Turns in place with the walk, camera off; remembers who it plays."""

    def __init__(self) -> None:
        self.agent_id = ""
        self.seed = -1
        self.steps = 0

    def reset(self, agent_id: str, seed: int) -> None:
        self.agent_id, self.seed, self.steps = agent_id, seed, 0

    def act(self, observation: dict) -> dict:
        self.steps += 1
        return make_action(Motion.WALK, walk=(0.0, 0.0, 0.5), camera=CameraChoice.OFF)


class WalkForward(Spinner):
    """Walks straight ahead at 0.15 m/s."""

    def act(self, observation: dict) -> dict:
        self.steps += 1
        return make_action(Motion.WALK, walk=(0.15, 0.0, 0.0), camera=CameraChoice.OFF)


class NoReset:
    """Not a policy: it has no reset()."""

    def act(self, observation: dict) -> dict:
        return make_action(Motion.STAND)


NOT_A_CLASS = 3
