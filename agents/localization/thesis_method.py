"""The thesis' localizer (chapter 5): disambiguation, candidates, Algorithm 4 and the odometer rules.

After each scan (thesis 5.5) the odometer's pose is the answer when fewer than two
landmarks were placed, when every candidate fell outside the field, or when the best
candidate is more than 0.5 m from the odometer; the second such jump in a row is accepted.
An accepted landmark pose resets the odometer.

Where the thesis is silent (ours): before the odometer was ever set (no kick-off pose given)
the first landmark pose is accepted as it is; a scan that gives no candidate neither counts
as a jump nor breaks a run of jumps.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Sequence
from dataclasses import dataclass

from agents.localization.constraint import FIELD_MARGIN_M, ORIENTATIONS, ConstraintSolution, solve
from agents.localization.disambiguation import CORNER_POST_MAX_ANGLE_RAD, disambiguate
from agents.localization.errors import LocalizationConfigError
from agents.localization.estimate import EstimateSource, PoseEstimate
from agents.localization.odometry import Odometer
from agents.localization.validation import usable_percepts
from agents.vision.percepts import LandmarkPercept
from match.protocol import Displacement
from world.field import FIELD, FieldGeometry, Pose2D

LOG = logging.getLogger(__name__)

JUMP_THRESHOLD_M = 0.5  # thesis 5.5: a best candidate "more than half meter away" from the odometer is not used ...
JUMPS_TO_ACCEPT = 2  # thesis 5.5: ... unless this occurs "for a second consecutive time"
MIN_LANDMARKS = 2  # thesis 5.3: one landmark gives no candidate position

REASON_FEW_LANDMARKS = "fewer than two landmarks"
REASON_ALL_REJECTED = "all candidates rejected"
REASON_JUMP = "jump from the odometer"


@dataclass(frozen=True)
class ThesisConfig:
    """Settings of :class:`ThesisLocalizer`; the defaults are the thesis' (margin and separation check: ours)."""

    field_margin_m: float = FIELD_MARGIN_M
    orientation: str = "first"  # thesis Algorithm 4; "mean": circular mean of the implied orientations
    max_corner_angle_rad: float = CORNER_POST_MAX_ANGLE_RAD
    check_separation: bool = True
    jump_threshold_m: float = JUMP_THRESHOLD_M
    jumps_to_accept: int = JUMPS_TO_ACCEPT
    use_odometer: bool = True  # False: every landmark pose is accepted (no jump rule)

    def __post_init__(self) -> None:
        if self.orientation not in ORIENTATIONS:
            raise LocalizationConfigError(f"orientation {self.orientation!r} unknown; expected one of {ORIENTATIONS}")
        for name in ("field_margin_m", "max_corner_angle_rad", "jump_threshold_m"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value >= 0):
                raise LocalizationConfigError(f"{name} must be a finite number >= 0; got {value!r}")
        if not (isinstance(self.jumps_to_accept, int) and self.jumps_to_accept >= 1):
            raise LocalizationConfigError(f"jumps_to_accept must be an int >= 1; got {self.jumps_to_accept!r}")


class ThesisLocalizer:
    """Constraint-based localization with the thesis' odometer rules."""

    name = "thesis"

    def __init__(self, config: ThesisConfig | None = None, field: FieldGeometry = FIELD, initial_pose: Pose2D | None = None):
        self.config = config or ThesisConfig()
        self.field = field
        self.odometer = Odometer(initial_pose)
        self._jumps = 0
        self.last_solution: ConstraintSolution | None = None

    @property
    def pose(self) -> Pose2D | None:
        """The current belief: the odometer's pose (None until known)."""
        return self.odometer.pose

    def reset(self, pose: Pose2D) -> None:
        self.odometer.reset(pose)
        self._jumps = 0

    def move(self, displacement: Displacement) -> None:
        self.odometer.move(displacement)

    def localize(self, percepts: Sequence[LandmarkPercept]) -> PoseEstimate | None:
        percepts = usable_percepts(percepts)
        if not percepts:
            return None
        cfg = self.config
        observations = disambiguate(percepts, self.field, cfg.max_corner_angle_rad, cfg.check_separation)
        if len(observations) < MIN_LANDMARKS:
            return self._odometer_estimate(REASON_FEW_LANDMARKS)
        solution = solve(observations, self.field, cfg.field_margin_m, cfg.orientation)
        self.last_solution = solution
        best = solution.best
        points = tuple((c.x_m, c.y_m) for c in solution.candidates)
        if best is None:
            return self._odometer_estimate(REASON_ALL_REJECTED)
        odometer = self.odometer.pose
        if cfg.use_odometer and odometer is not None:
            jump = math.hypot(best.x_m - odometer.x, best.y_m - odometer.y)
            if jump > cfg.jump_threshold_m:
                self._jumps += 1
                if self._jumps < cfg.jumps_to_accept:
                    LOG.debug("best candidate %.2f m from the odometer: jump %d not accepted", jump, self._jumps)
                    return self._odometer_estimate(REASON_JUMP, points)
        self._jumps = 0
        self.odometer.reset(Pose2D(best.x_m, best.y_m, best.theta_rad))
        return PoseEstimate(
            best.x_m,
            best.y_m,
            best.theta_rad,
            self.name,
            EstimateSource.LANDMARKS,
            tuple(o.landmark_id for o in observations),
            points,
        )

    def _odometer_estimate(self, reason: str, candidates: tuple[tuple[float, float], ...] = ()) -> PoseEstimate | None:
        pose = self.odometer.pose
        if pose is None:
            return None
        return PoseEstimate(
            pose.x, pose.y, pose.theta, self.name, EstimateSource.ODOMETER, (), candidates, None, reason
        )
