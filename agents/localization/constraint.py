"""Constraint-based pose from landmark observations (thesis 5.3 and 5.4, Algorithm 4).

Every pair of observed landmarks gives candidate positions (circle intersections,
:mod:`agents.localization.circles`); candidates outside the field are rejected. For each
candidate and each landmark, the robot orientation that landmark implies is
``theta = atan2(ly - y, lx - x) - bearing`` (the thesis adds its clockwise-positive
bearing; ours is counter-clockwise positive). The candidate whose implied orientations
differ least (smallest maximum pairwise difference) wins; its orientation is that of the
first observation (thesis Algorithm 4: ``Orientations(0)``), or with ``orientation="mean"``
their circular mean.

Field margin (ours, the thesis rejects candidates "outside the field's borders"): a robot's
position is its torso centre, which stands up to about a footprint beyond a line while the
robot still plays (walking along a side line, chasing a ball that rolls out for two seconds
before the throw-in), so candidates up to ``FIELD_MARGIN_M`` beyond the lines are kept;
the carpet ends 0.7 m beyond them, and a wider margin keeps more mirror-image candidates.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from agents.localization.circles import intersect_circles
from agents.localization.errors import LocalizationConfigError
from agents.localization.estimate import LandmarkObservation
from world.field import FIELD, FieldGeometry, LandmarkId

FIELD_MARGIN_M = 0.3  # ours (module docstring)
ORIENTATIONS = ("first", "mean")


@dataclass(frozen=True)
class Candidate:
    """A candidate position (m), the orientation it implies (rad) and its maximum pairwise orientation difference (rad)."""

    x_m: float
    y_m: float
    theta_rad: float
    max_diff_rad: float
    pair: tuple[LandmarkId, LandmarkId]


@dataclass(frozen=True)
class ConstraintSolution:
    """All candidates inside the field, ranked by ``max_diff_rad``, and the rejected points (m)."""

    candidates: tuple[Candidate, ...]
    rejected: tuple[tuple[float, float], ...]

    @property
    def best(self) -> Candidate | None:
        return self.candidates[0] if self.candidates else None


def in_field(x: float, y: float, field: FieldGeometry = FIELD, margin_m: float = FIELD_MARGIN_M) -> bool:
    return abs(x) <= field.half_length + margin_m and abs(y) <= field.half_width + margin_m


def implied_orientations(xs: np.ndarray, ys: np.ndarray, observations: Sequence[LandmarkObservation]) -> np.ndarray:
    """(K, M) robot orientations (rad, normalized) that M observations imply at K positions."""
    lx = np.array([o.x_m for o in observations])
    ly = np.array([o.y_m for o in observations])
    bearing = np.array([o.bearing_rad for o in observations])
    field_direction = np.arctan2(ly[None, :] - ys[:, None], lx[None, :] - xs[:, None])
    return wrap(field_direction - bearing[None, :])


def wrap(angle: np.ndarray) -> np.ndarray:
    """Angles wrapped into (-pi, pi] (vectorized :func:`world.field.normalize_angle`)."""
    return np.pi - np.mod(np.pi - angle, 2.0 * np.pi)


def max_pairwise_difference(theta: np.ndarray) -> np.ndarray:
    """(K,) largest |normalized difference| between any two of each row's M angles."""
    return np.abs(wrap(theta[:, :, None] - theta[:, None, :])).max(axis=(1, 2))


def solve(
    observations: Sequence[LandmarkObservation],
    field: FieldGeometry = FIELD,
    margin_m: float = FIELD_MARGIN_M,
    orientation: str = "first",
) -> ConstraintSolution:
    """Candidates of all observation pairs, filtered and ranked by thesis Algorithm 4."""
    if orientation not in ORIENTATIONS:
        raise LocalizationConfigError(f"orientation {orientation!r} unknown; expected one of {ORIENTATIONS}")
    points: list[tuple[float, float]] = []
    pairs: list[tuple[LandmarkId, LandmarkId]] = []
    rejected: list[tuple[float, float]] = []
    for a, b in itertools.combinations(observations, 2):
        for point in intersect_circles((a.x_m, a.y_m), a.distance_m, (b.x_m, b.y_m), b.distance_m).points:
            if in_field(point[0], point[1], field, margin_m):
                points.append(point)
                pairs.append((a.landmark_id, b.landmark_id))
            else:
                rejected.append(point)
    if not points:
        return ConstraintSolution((), tuple(rejected))
    xy = np.array(points)
    theta = implied_orientations(xy[:, 0], xy[:, 1], observations)
    spread = max_pairwise_difference(theta)
    if orientation == "first":
        chosen = theta[:, 0]
    else:
        chosen = np.arctan2(np.sin(theta).sum(axis=1), np.cos(theta).sum(axis=1))
    order = np.argsort(spread, kind="stable")
    candidates = tuple(
        Candidate(float(xy[k, 0]), float(xy[k, 1]), float(wrap(chosen[k])), float(spread[k]), pairs[k]) for k in order
    )
    return ConstraintSolution(candidates, tuple(rejected))
