"""Circle-circle intersection with the five cases of thesis 5.3.

Each observed landmark gives a circle on the field: centred on the landmark, radius the
measured distance. Two circles give the robot's candidate positions:

- separated (d > r0 + r1): none;
- coincident (d = 0, r0 = r1): none (infinitely many);
- tangent (d = r0 + r1 or d = |r0 - r1|): the tangent point, at the larger radius from the
  larger circle's centre toward the other centre;
- contained (d < |r0 - r1|): the larger radius shrunk to d + (smaller radius), making the
  circles internally tangent, then as tangent; concentric circles (d = 0) give none;
- intersecting: both intersection points (thesis 2.3.3).

Equalities hold within ``tolerance_m`` (ours: floating-point slack only).
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

TANGENT_TOLERANCE_M = 1e-9  # ours: |d - (r0 + r1)| or |d - |r0 - r1|| this small counts as tangent

Point = tuple[float, float]


class CircleCase(enum.Enum):
    SEPARATED = "separated"
    COINCIDENT = "coincident"
    TANGENT = "tangent"
    CONTAINED = "contained"
    INTERSECTING = "intersecting"


@dataclass(frozen=True)
class CircleIntersection:
    """Which case two circles are in and the candidate points (m, field frame) it gives."""

    case: CircleCase
    points: tuple[Point, ...]


def _toward(origin: Point, target: Point, length: float) -> Point:
    dx, dy = target[0] - origin[0], target[1] - origin[1]
    norm = math.hypot(dx, dy)
    return origin[0] + length * dx / norm, origin[1] + length * dy / norm


def intersect_circles(c0: Point, r0: float, c1: Point, r1: float, tolerance_m: float = TANGENT_TOLERANCE_M) -> CircleIntersection:
    """Candidate points of circles (``c0``, ``r0``) and (``c1``, ``r1``) (centres and radii in m)."""
    d = math.hypot(c1[0] - c0[0], c1[1] - c0[1])
    tol = tolerance_m * max(1.0, d, r0, r1)
    if d <= tol and abs(r0 - r1) <= tol:
        return CircleIntersection(CircleCase.COINCIDENT, ())
    if d > r0 + r1 + tol:
        return CircleIntersection(CircleCase.SEPARATED, ())
    (big, r_big), (small, r_small) = ((c0, r0), (c1, r1)) if r0 >= r1 else ((c1, r1), (c0, r0))
    if d <= tol:  # concentric, different radii: no direction to a tangent point
        return CircleIntersection(CircleCase.CONTAINED, ())
    if abs(d - (r0 + r1)) <= tol or abs(d - (r_big - r_small)) <= tol:
        return CircleIntersection(CircleCase.TANGENT, (_toward(big, small, r_big),))
    if d < r_big - r_small:
        return CircleIntersection(CircleCase.CONTAINED, (_toward(big, small, d + r_small),))
    a = (r0 * r0 - r1 * r1 + d * d) / (2.0 * d)
    h = math.sqrt(max(r0 * r0 - a * a, 0.0))
    ux, uy = (c1[0] - c0[0]) / d, (c1[1] - c0[1]) / d
    mx, my = c0[0] + a * ux, c0[1] + a * uy
    return CircleIntersection(CircleCase.INTERSECTING, ((mx - h * uy, my + h * ux), (mx + h * uy, my - h * ux)))
