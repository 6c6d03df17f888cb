"""Scenario 1 of thesis chapter 6 on the bare world: one robot alone, move-scan-localize.

The measured robot runs :class:`agents.behavior.scan_localize.ScanLocalizeAgent` on the
observations it would get in a match (camera image only while its camera is on), with
every localization method side by side; :mod:`scenarios.scenario_run` simulates it. After
each of its localization events, the harness (not the agent) reads the robot's true pose
from the world, the thesis' GPS, and makes one :class:`LocalizationSample` per method.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from world.field import Pose2D, normalize_angle

log = logging.getLogger(__name__)

ROBOT = "home_1"
DEFAULT_START = Pose2D(-1.0, 0.0, 0.0)


@dataclass(frozen=True)
class LocalizationSample:
    """One method's estimate at one localization event, against the true pose (m, rad).

    ``est_*`` are NaN when the method had no estimate; the errors are NaN then too.
    """

    run: int
    robot: str
    method: str
    event: int
    sim_time_s: float
    true_x: float
    true_y: float
    true_theta: float
    est_x: float
    est_y: float
    est_theta: float
    landmarks_used: int
    percepts: int
    # Wall time of the method's localize(): a measurement of the machine, not of the match,
    # so it is left out of comparisons.
    compute_ms: float = field(default=math.nan, compare=False, repr=False)

    @property
    def position_error_m(self) -> float:
        return math.hypot(self.est_x - self.true_x, self.est_y - self.true_y)

    @property
    def orientation_error_deg(self) -> float:
        if math.isnan(self.est_theta):
            return math.nan
        return abs(math.degrees(normalize_angle(self.est_theta - self.true_theta)))


@dataclass(frozen=True)
class RunResult:
    samples: tuple[LocalizationSample, ...]
    sim_seconds: float
    wall_seconds: float


def run_alone(
    samples: int,
    seed: int,
    methods: Sequence[str],
    run: int = 0,
    start: Pose2D = DEFAULT_START,
    camera_model: str = "exact",
) -> RunResult:
    """Scenario 1: ``samples`` localization events of one robot alone on the field, from ``start``."""
    from scenarios.scenario_run import RunTask, simulate_run  # it builds on the samples defined here
    from scenarios.scenario_spec import Policy, RobotEntry, ScenarioSpec

    robot = RobotEntry(ROBOT, Policy.SCAN_LOCALIZE, measured=True, start=start)
    spec = ScenarioSpec("scenario 1", "", samples, 1, seed, tuple(methods), camera_model, False, (robot,))
    outcome = simulate_run(RunTask(spec, run, seed, samples))
    if not outcome.complete:
        raise RuntimeError(f"run {run}: {outcome.events} of {samples} samples")
    return RunResult(outcome.samples, outcome.sim_seconds, outcome.wall_seconds)


def summarize(samples: Sequence[LocalizationSample]) -> dict[str, dict[str, float]]:
    """Per method: mean and median position (cm) and orientation (deg) errors, counts, median localize() ms."""
    out: dict[str, dict[str, float]] = {}
    for method in dict.fromkeys(s.method for s in samples):
        rows = [s for s in samples if s.method == method]
        pos = np.array([s.position_error_m for s in rows])
        ori = np.array([s.orientation_error_deg for s in rows])
        ok = np.isfinite(pos)
        out[method] = {
            "samples": len(rows),
            "with_estimate": int(ok.sum()),
            "position_mean_cm": float(np.mean(pos[ok]) * 100.0) if ok.any() else math.nan,
            "position_median_cm": float(np.median(pos[ok]) * 100.0) if ok.any() else math.nan,
            "orientation_mean_deg": float(np.mean(ori[ok])) if ok.any() else math.nan,
            "orientation_median_deg": float(np.median(ori[ok])) if ok.any() else math.nan,
            "localize_ms_median": float(np.nanmedian([s.compute_ms for s in rows])) if rows else math.nan,
        }
    return out
