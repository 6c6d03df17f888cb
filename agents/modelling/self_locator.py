"""Self-localization while playing: a localizer fed the robot's odometry and every frame's landmarks.

The thesis localizes after a stop-and-scan; a playing robot cannot stop. Here the odometry of
every step is gathered and handed to the localizer (one of :data:`agents.localization.LOCALIZERS`)
in pieces of about :data:`FLUSH_TRAVEL_M` or :data:`FLUSH_TURN_RAD` (its motion noise is
modelled per motion, not per 40 ms step), and the landmark percepts of each camera frame
update it as they come. The pose is in the field frame with an uncertainty: from the
localizer's covariance after a fix, growing with the distance walked and turned since.

A fix far from the pose the robot tracks (farther than :data:`GATE_M` or :data:`GATE_RAD`,
or three sigmas) is not believed at once: a playing robot sees few landmarks at a time, and
a few symmetric ones (the centre circle, one goal's posts from close by) fit a mirrored pose
as well as the true one. Such a fix is believed when :data:`JUMP_CONFIRMATIONS` fixes in a
row agree on it (the robot really was moved: the localizer, left to itself, keeps finding
it) and one of their frames showed a goal (the field's lines alone repeat: a few of them fit
a pose 2 m to the side as well); meanwhile the pose's sigma is raised to at least
:data:`DOUBT_SIGMA_M`, so that the robot looks for landmarks (it glances at a goal). Only a
far fix whose frame the tracked pose explains clearly worse (by :data:`JUMP_EVIDENCE_NATS`,
in the particle filters' measurement model) counts towards a jump: near a goal, one of its
posts fits a mirrored pose as well as the true one, and enough such frames in a row would move
a robot metres off for as long as it stays there (docs/results.md, "Self-locator: far fixes").
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Protocol, runtime_checkable

import numpy as np

from agents.localization import PoseEstimate, localizer
from agents.localization.estimate import EstimateSource
from agents.localization.measurement import MeasurementConfig, ScanLikelihood
from agents.localization.odometry import compose
from agents.modelling.spread import largest_eigenvalue
from agents.vision.percepts import LandmarkPercept
from match.protocol import Displacement, Pose2D

# The particle filters' settings for updates every frame rather than every scan (a few
# seconds apart): slower likelihood averages, fewer injected particles, no jump to a pose
# that only one or two landmarks support, and no particles drawn from such a frame unless it
# contradicts the cloud: a few landmarks seen while playing fit a wrong pose too often to let one
# frame move the cloud (docs/results.md, "Self-locator: far fixes").
_PER_FRAME = {"alpha_slow": 0.01, "alpha_fast": 0.1, "max_injection": 0.1, "jump_min_percepts": 3,
              "inject_min_percepts": 3, "inject_below_likelihood": 0.1}
PLAYING_OPTIONS: dict[str, dict[str, object]] = {"particle": _PER_FRAME, "hybrid": _PER_FRAME}
FLUSH_TRAVEL_M = 0.25
FLUSH_TURN_RAD = math.radians(20.0)
FIX_SIGMA_M = 0.10  # after a landmark fix without a covariance (the thesis' method)
FIX_SIGMA_RAD = math.radians(4.0)
RESET_SIGMA_M = 0.05  # at a known pose (kick-off)
RESET_SIGMA_RAD = math.radians(3.0)
SIGMA_PER_M = 0.10  # growth of the position sigma per metre walked ...
SIGMA_PER_RAD = 0.03  # ... and per radian turned
SIGMA_RAD_PER_M = math.radians(4.0)  # growth of the heading sigma per metre walked ...
SIGMA_RAD_PER_RAD = 0.08  # ... and per radian turned
MIN_SIGMA_M = 0.02
MIN_SIGMA_RAD = math.radians(1.0)
MAX_SIGMA_M = 5.0
MAX_SIGMA_RAD = math.pi
GATE_M = 0.5  # a fix farther than this (or 3 sigma) from the tracked pose is a candidate jump ...
GATE_RAD = math.radians(35.0)
JUMP_CONFIRMATIONS = 6  # ... believed when this many fixes in a row agree on it ...
AGREE_M = 0.4  # ... within these of the last one
AGREE_RAD = math.radians(30.0)
DOUBT_SIGMA_M = 0.3  # a rejected far fix raises the position sigma to this
JUMP_EVIDENCE_NATS = 2.0  # ours: a far fix counts towards a jump only if its frame fits it this much better


@runtime_checkable
class Widenable(Protocol):
    """A localizer whose belief can be made less certain in place (the particle filters)."""

    def widen(self, sigma_m: float, sigma_rad: float) -> None: ...


class SelfLocator:
    """Where the robot is: ``pose`` (field frame, None until known), ``sigma_m``, ``sigma_rad``."""

    def __init__(self, method: str, seed: int):
        self.method = method
        self.localizer = localizer(method, seed=seed, **PLAYING_OPTIONS.get(method, {}))
        self.sigma_m = MAX_SIGMA_M
        self.sigma_rad = MAX_SIGMA_RAD
        self.last_fix: PoseEstimate | None = None
        self.rejected_fixes = 0  # far fixes not believed (statistics)
        self._tracked: Pose2D | None = self.localizer.pose
        self._candidates: list[Pose2D] = []
        self._candidates_saw_goal = False  # one of the candidates' frames showed a goal
        self._pending = Displacement(0.0, 0.0, 0.0)

    @property
    def pose(self) -> Pose2D | None:
        """The pose as of now, odometry not yet handed to the localizer included."""
        if self._tracked is None:
            return None
        return compose(self._tracked, self._pending)

    @property
    def has_pose(self) -> bool:
        """Whether it holds a pose (:attr:`pose` is not None), without composing it."""
        return self._tracked is not None

    def reset(self, pose: Pose2D) -> None:
        """A known pose (placed at a kick-off position)."""
        self._pending = Displacement(0.0, 0.0, 0.0)
        self.localizer.reset(pose)
        self._tracked = pose
        self._candidates.clear()
        self._candidates_saw_goal = False
        self.sigma_m, self.sigma_rad = RESET_SIGMA_M, RESET_SIGMA_RAD

    def move(self, step: Displacement) -> None:
        """The robot moved by ``step`` (its frame at the step's start) since the last call."""
        p = self._pending
        c, s = math.cos(p.turn_rad), math.sin(p.turn_rad)
        self._pending = Displacement(
            p.forward_m + c * step.forward_m - s * step.left_m,
            p.left_m + s * step.forward_m + c * step.left_m,
            p.turn_rad + step.turn_rad,
        )
        travel, turn = math.hypot(step.forward_m, step.left_m), abs(step.turn_rad)
        self.sigma_m = min(MAX_SIGMA_M, self.sigma_m + SIGMA_PER_M * travel + SIGMA_PER_RAD * turn)
        self.sigma_rad = min(MAX_SIGMA_RAD, self.sigma_rad + SIGMA_RAD_PER_M * travel + SIGMA_RAD_PER_RAD * turn)
        pending = self._pending
        if math.hypot(pending.forward_m, pending.left_m) >= FLUSH_TRAVEL_M or abs(pending.turn_rad) >= FLUSH_TURN_RAD:
            self._flush()

    def fell(self, sigma_m: float, sigma_rad: float) -> None:
        """The robot fell: it may have slid and turned (m, rad of added uncertainty). The localizer's
        belief is widened as much, and so is the gate, so that the next fixes can set the heading right."""
        self._flush()
        self.sigma_m = min(MAX_SIGMA_M, self.sigma_m + sigma_m)
        self.sigma_rad = min(MAX_SIGMA_RAD, self.sigma_rad + sigma_rad)
        if isinstance(self.localizer, Widenable):
            self.localizer.widen(sigma_m, sigma_rad)

    def update(self, percepts: Sequence[LandmarkPercept]) -> PoseEstimate | None:
        """The landmarks of one frame; returns the localizer's estimate when they fixed the pose."""
        if not percepts:
            return None
        self._flush()
        estimate = self.localizer.localize(percepts)
        if estimate is None or estimate.source is EstimateSource.ODOMETER:
            return None
        if not self._believe(estimate.pose, percepts):
            self.rejected_fixes += 1
            self.sigma_m = max(self.sigma_m, DOUBT_SIGMA_M)
            return None
        self._tracked = estimate.pose
        self.last_fix = estimate
        if estimate.covariance is not None:
            cov = np.asarray(estimate.covariance, float)
            sigma_m = math.sqrt(largest_eigenvalue(cov[0, 0], cov[0, 1], cov[1, 1]))
            sigma_rad = math.sqrt(max(float(cov[2, 2]), 0.0))
        else:
            sigma_m, sigma_rad = FIX_SIGMA_M, FIX_SIGMA_RAD
        self.sigma_m, self.sigma_rad = max(sigma_m, MIN_SIGMA_M), max(sigma_rad, MIN_SIGMA_RAD)
        return estimate

    def _believe(self, fix: Pose2D, percepts: Sequence[LandmarkPercept]) -> bool:
        """Whether a fix of ``percepts`` is taken: near the tracked pose, or the last of enough far fixes
        that agree, one of which saw a goal. A far fix whose frame the tracked pose explains about as
        well (within :data:`JUMP_EVIDENCE_NATS`) is no evidence that the robot is elsewhere: a goal's
        post or two fit a mirrored pose too. It is not believed and does not count."""
        tracked = self._tracked
        if tracked is None or _near(fix, tracked, max(GATE_M, 3.0 * self.sigma_m), max(GATE_RAD, 3.0 * self.sigma_rad)):
            self._candidates.clear()
            self._candidates_saw_goal = False
            return True
        if _log_likelihood_ratio(percepts, fix, tracked) < JUMP_EVIDENCE_NATS:
            return False
        saw_goal = any(p.goal is not None for p in percepts)
        if self._candidates and not _near(fix, self._candidates[-1], AGREE_M, AGREE_RAD):
            self._candidates.clear()
            self._candidates_saw_goal = False
        self._candidates.append(fix)
        self._candidates_saw_goal = self._candidates_saw_goal or saw_goal
        if len(self._candidates) >= JUMP_CONFIRMATIONS and self._candidates_saw_goal:
            self._candidates.clear()
            self._candidates_saw_goal = False
            return True
        return False

    def _flush(self) -> None:
        pending = self._pending
        if pending.forward_m or pending.left_m or pending.turn_rad:
            self._pending = Displacement(0.0, 0.0, 0.0)
            moved = Displacement(pending.forward_m, pending.left_m, math.remainder(pending.turn_rad, math.tau))
            if self.localizer.pose is not None:
                self.localizer.move(moved)
            if self._tracked is not None:
                self._tracked = compose(self._tracked, moved)


def _log_likelihood_ratio(percepts: Sequence[LandmarkPercept], a: Pose2D, b: Pose2D) -> float:
    """How much better (nats) the percepts of one frame fit pose ``a`` than pose ``b`` (the measurement
    model of the particle filters: each percept its most likely landmark, mixed with outliers)."""
    scan = ScanLikelihood(percepts, _MEASUREMENT)
    ll = scan.log_likelihood(np.array([a.x, b.x]), np.array([a.y, b.y]), np.array([a.theta, b.theta]))
    return float(ll[0] - ll[1])


_MEASUREMENT = MeasurementConfig()


def _near(a: Pose2D, b: Pose2D, within_m: float, within_rad: float) -> bool:
    return (math.hypot(a.x - b.x, a.y - b.y) <= within_m
            and abs(math.remainder(a.theta - b.theta, math.tau)) <= within_rad)
