"""What localization produces: observations of known landmarks and pose estimates.

Field frame (thesis 5.1, :mod:`world.field`): metres, +x toward the yellow goal, +y left
when facing +x; ``theta`` counter-clockwise from +x, in (-pi, pi]. Bearings are
counter-clockwise positive in the torso frame.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass

from world.field import LandmarkId, Pose2D

Covariance = tuple[tuple[float, float, float], tuple[float, float, float], tuple[float, float, float]]


class EstimateSource(enum.StrEnum):
    """What fixed a :class:`PoseEstimate` (compares and serializes as its plain value)."""

    LANDMARKS = "landmarks"  # the scan's landmarks fixed the pose
    ODOMETER = "odometer"  # the odometer's pose, the scan did not (thesis 5.5)
    PARTICLES = "particles"  # the particle cloud's belief


@dataclass(frozen=True)
class LandmarkObservation:
    """A percept resolved to one landmark: where the landmark is on the field and how it was seen.

    ``x_m``/``y_m``: the landmark's field position; ``distance_m``: measured ground distance
    from the robot; ``bearing_rad``: measured bearing, CCW positive in the torso frame.
    """

    landmark_id: LandmarkId
    x_m: float
    y_m: float
    distance_m: float
    bearing_rad: float


@dataclass(frozen=True)
class PoseEstimate:
    """A localizer's answer for one scan: the robot's pose ``x_m``, ``y_m``, ``theta_rad`` in the field frame.

    ``method``: the localizer that produced it (``thesis``, ``particle``, ...);
    ``source``: what fixed the pose; ``landmarks_used``: the landmarks the pose rests on;
    ``candidates``: field points (x, y) considered (thesis 5.3/5.4), empty when none;
    ``covariance``: 3x3 over (x m, y m, theta rad) when the method has one; ``reason``: why
    the odometer was used instead of the landmarks, empty otherwise.
    """

    x_m: float
    y_m: float
    theta_rad: float
    method: str
    source: EstimateSource
    landmarks_used: tuple[LandmarkId, ...] = ()
    candidates: tuple[tuple[float, float], ...] = ()
    covariance: Covariance | None = None
    reason: str = ""

    @property
    def pose(self) -> Pose2D:
        return Pose2D(self.x_m, self.y_m, self.theta_rad)
