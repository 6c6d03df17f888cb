"""Localization samples: one method's estimate at one localization event against the true pose.

The harness (:mod:`scenarios.localization.run`), not the agent, reads the robot's true pose
from the world, the thesis' GPS, after each localization event of a measured robot and
makes one :class:`LocalizationSample` per method. Units: metres, radians, seconds.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from world.field import normalize_angle


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
