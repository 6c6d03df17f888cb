"""Policies as a user would write them in their own module, chosen by ``tests.user_policies:Name``."""

from __future__ import annotations

import os

import numpy as np

from agents.team.messages import TeamMessage
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


class RadioFuzzer(Spinner):
    """Stands and sends garbage to its teammates: random bytes, truncated and future-version packets."""

    def reset(self, agent_id: str, seed: int) -> None:
        super().reset(agent_id, seed)
        self.rng = np.random.default_rng(seed)
        self.good = TeamMessage(int(agent_id[-1]), 1, (0.0, 0.0, 0.0), ball_xy=(1.0, 1.0)).encode()

    def act(self, observation: dict) -> dict:
        self.steps += 1
        kind = self.steps % 4
        if kind == 0:
            data = self.rng.integers(0, 256, int(self.rng.integers(1, 129)), dtype=np.uint8).tobytes()
        elif kind == 1:
            data = self.good[: int(self.rng.integers(1, len(self.good)))]
        elif kind == 2:
            data = self.good[:2] + bytes([99]) + self.good[3:]
        else:
            data = b"RS" + bytes(125)
        return make_action(Motion.STAND, camera=CameraChoice.OFF, radio=data)


class ExitsAtHome(Spinner):
    """Kills its own process (``os._exit(3)``) on its 50th act when it plays for the home team."""

    def act(self, observation: dict) -> dict:
        self.steps += 1
        if self.steps == 50 and self.agent_id.startswith("home"):
            os._exit(3)
        return make_action(Motion.STAND, camera=CameraChoice.OFF)


class RaisesEveryTenth(Spinner):
    """Raises on every 10th act; stands otherwise."""

    def act(self, observation: dict) -> dict:
        self.steps += 1
        if self.steps % 10 == 0:
            raise RuntimeError(f"act {self.steps} of {self.agent_id} fails")
        return make_action(Motion.STAND, camera=CameraChoice.OFF)
