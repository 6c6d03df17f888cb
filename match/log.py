"""The match log: every control step, the true poses of the robots and the ball.

Kept in memory as compact float32 rows and written as one compressed ``.npz``: a full
match of 8 robots (about 32 000 steps) takes a few megabytes. Agents' own pose estimates
are logged beside the truth when their policy reports one (NaN otherwise).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from match.game import Match


class MatchLog:
    def __init__(self, agents: Sequence[str]):
        self.agents = tuple(agents)
        self._time: list[float] = []
        self._state: list[int] = []
        self._half: list[int] = []
        self._ball: list[tuple[float, float, float]] = []
        self._robots: list[np.ndarray] = []
        self._fallen: list[np.ndarray] = []
        self._estimates: list[np.ndarray] = []

    def __len__(self) -> int:
        return len(self._time)

    def record(self, match: Match, estimates: Mapping[str, tuple[float, float, float] | None] | None = None) -> None:
        truth = match.truth()
        robots = np.empty((len(self.agents), 3), dtype=np.float32)
        fallen = np.empty(len(self.agents), dtype=bool)
        guesses = np.full((len(self.agents), 3), np.nan, dtype=np.float32)
        for i, agent in enumerate(self.agents):
            robot = truth["robots"][agent]
            robots[i] = robot["pose"]
            fallen[i] = robot["fallen"]
            if estimates and estimates.get(agent) is not None:
                guesses[i] = estimates[agent]
        self._time.append(truth["time_s"])
        self._state.append(int(match.state))
        self._half.append(match.referee.half)
        self._ball.append(truth["ball"]["position"])
        self._robots.append(robots)
        self._fallen.append(fallen)
        self._estimates.append(guesses)

    def save(self, path: Path) -> Path:
        """Write ``path`` (``.npz``): arrays time_s (T), state (T), half (T), ball (T, 3),
        robots (T, N, 3: x, y, theta), fallen (T, N), estimates (T, N, 3) and agents (N)."""
        n = len(self.agents)
        np.savez_compressed(
            path,
            agents=np.array(self.agents),
            time_s=np.array(self._time, dtype=np.float64),
            state=np.array(self._state, dtype=np.int8),
            half=np.array(self._half, dtype=np.int8),
            ball=np.array(self._ball, dtype=np.float32).reshape(-1, 3),
            robots=np.array(self._robots, dtype=np.float32).reshape(-1, n, 3),
            fallen=np.array(self._fallen, dtype=bool).reshape(-1, n),
            estimates=np.array(self._estimates, dtype=np.float32).reshape(-1, n, 3),
        )
        return path
