"""The match log: every control step, the true poses of the robots and the ball.

Kept in memory as compact float32 rows and written as one compressed ``.npz``: a full
match of 8 robots (about 32 000 steps) takes a few megabytes. Agents' own pose estimates
are logged beside the truth when their policy reports one (NaN otherwise), and so is what
an :class:`~match.protocol.policy.AgentReporter` reports (its ball, the team ball, its role
and the landmarks it saw; NaN where it reports nothing), in the per-robot extras that
``scenarios.replay.record`` reads; so are the actions each robot's policy asked for (its
motion and walk command), which tell a robot that stands on purpose from one that is stuck.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from match.game import Match
from match.protocol.actions import Action
from match.protocol.policy import AgentReport
from world.motions import Motion

MAX_ROLES = 64  # distinct role names kept; a report with a role beyond them logs no role
MOTIONS = tuple(Motion)  # a logged motion is its index here
_MOTION_INDEX = {motion: index for index, motion in enumerate(MOTIONS)}
NO_ACTION = -1  # the logged motion of a robot without an action that step (a fault, or the first row)

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
        self._reports: list[np.ndarray] = []  # (N, 6): ball x, y, team ball x, y, role index, landmark bits
        self._motions: list[np.ndarray] = []  # (N,): index into MOTIONS, NO_ACTION without an action
        self._walks: list[np.ndarray] = []  # (N, 3): vx m/s, vy m/s, omega rad/s (robot frame)
        self.role_names: list[str] = []  # the roles reported, in the order they first appeared
        self._role_index: dict[str, int] = {}

    def __len__(self) -> int:
        return len(self._time)

    def record(self, match: Match, estimates: Mapping[str, tuple[float, float, float] | None] | None = None,
               reports: Mapping[str, AgentReport | None] | None = None,
               actions: Mapping[str, Action | None] | None = None) -> None:
        """One step: the truth now, what the policies reported (``estimates``: checked
        (x, y, theta) tuples; ``reports``: checked reports; missing or None: nothing) and the
        actions that led here (``actions``: the step's checked actions; missing or None: none)."""
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
        self._reports.append(self._report_row(reports or {}))
        motions = np.full(len(self.agents), NO_ACTION, dtype=np.int8)
        walks = np.zeros((len(self.agents), 3), dtype=np.float32)
        for i, agent in enumerate(self.agents):
            action = (actions or {}).get(agent)
            if action is not None:
                motions[i] = _MOTION_INDEX[action.motion]
                walks[i] = action.walk
        self._motions.append(motions)
        self._walks.append(walks)

    def _report_row(self, reports: Mapping[str, AgentReport | None]) -> np.ndarray:
        row = np.full((len(self.agents), 6), np.nan, dtype=np.float32)
        for i, agent in enumerate(self.agents):
            report = reports.get(agent)
            if report is None:
                continue
            if report.ball_xy is not None:
                row[i, 0:2] = report.ball_xy
            if report.team_ball_xy is not None:
                row[i, 2:4] = report.team_ball_xy
            if report.role is not None:
                if report.role not in self._role_index and len(self.role_names) < MAX_ROLES:
                    self._role_index[report.role] = len(self.role_names)
                    self.role_names.append(report.role)
                row[i, 4] = self._role_index.get(report.role, np.nan)
            row[i, 5] = sum(1 << index for index in report.landmarks_seen)  # < 2**17: exact in float32
        return row

    def save(self, path: Path) -> Path:
        """Write ``path`` (``.npz``): arrays time_s (T), state (T), half (T), ball (T, 3),
        robots (T, N, 3: x, y, theta), fallen (T, N), estimates (T, N, 3) and agents (N); the
        reports' ball_estimates (T, N, 2: x, y), team_ball (T, N, 2), roles (T, N: index into
        role_names, float), role_names (R) and landmarks_seen (T, N: bit i for
        ``FIELD.landmarks[i]``, float); NaN where a robot reported nothing; the actions that
        led to each row: motions (T, N: index into motion_names (M), -1 without an action) and
        walks (T, N, 3: the walk command, vx m/s, vy m/s, omega rad/s)."""
        n = len(self.agents)
        reports = np.array(self._reports, dtype=np.float32).reshape(-1, n, 6)
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
            ball_estimates=reports[:, :, 0:2],
            team_ball=reports[:, :, 2:4],
            roles=reports[:, :, 4],
            role_names=np.array(self.role_names, dtype=str),
            landmarks_seen=reports[:, :, 5],
            motions=np.array(self._motions, dtype=np.int8).reshape(-1, n),
            walks=np.array(self._walks, dtype=np.float32).reshape(-1, n, 3),
            motion_names=np.array([m.value for m in MOTIONS], dtype=str),
        )
        return path
