"""Corners, junctions and the centre circle from classified lines (thesis section 4.5.4).

An L corner is a line classified as a corner (its highest pixel for an up corner, its
lowest for a down corner) or two side lines whose nearest ends meet (FindCorner: up, down,
left or right corner; ends at most 10 px apart in width and 5 px in height). A T junction
is a line end lying on another line's interior (at most 5 px from it in height). The
centre circle's centre is fitted through three points of a curved line (first, middle,
last) located on the ground (thesis 2.3.2).
"""

from __future__ import annotations

import itertools
import math

import numpy as np

from agents.vision.camera_models import CameraModel
from agents.vision.frame import CameraFrame
from agents.vision.lines.shapes import DOWN, UP, FieldLine, LineType
from agents.vision.percepts import CornerShape, LandmarkPercept
from world.field import FIELD, LandmarkId, LandmarkKind

CORNER_MAX_DW_PX = 10  # thesis 4.5.4 FindCorner: ends at most 10 px apart in width ...
CORNER_MAX_DH_PX = 5  # ... and 5 px in height
JUNCTION_MAX_DH_PX = 5  # thesis 4.5.4 Find Junction: an end within 5 px (height) of the other line
JUNCTION_END_CLEARANCE_PX = 10  # ours: the end must meet the other line away from its ends (else a corner)
MIN_MEETING_ANGLE_RAD = math.radians(25.0)  # ours: two lines meeting at a corner or junction differ
# in image direction by at least this; pieces of one line broken into dashes differ by less
VERTEX_INTERIOR = (0.2, 0.8)  # ours: a corner-shaped line's vertex lies inside this span of the line
CIRCLE_RADIUS_TOLERANCE_M = 0.25  # ours: a fitted circle's radius must be 0.6 m within this
SIDE_TYPES = (LineType.SIDE_UP, LineType.SIDE_DOWN, LineType.STRAIGHT)


def circle_through(p1: np.ndarray, p2: np.ndarray, p3: np.ndarray) -> tuple[float, float, float] | None:
    """Centre (x, y) and radius of the circle through three points; None when they are collinear.

    Thesis 2.3.2 intersects two perpendicular bisectors through slopes, which fails on a
    vertical chord; this is the same circle from the determinant form.
    """
    (ax, ay), (bx, by), (cx, cy) = p1, p2, p3
    d = 2.0 * (ax * (by - cy) + bx * (cy - ay) + cx * (ay - by))
    if abs(d) < 1e-9:
        return None
    a2, b2, c2 = ax * ax + ay * ay, bx * bx + by * by, cx * cx + cy * cy
    ux = (a2 * (by - cy) + b2 * (cy - ay) + c2 * (ay - by)) / d
    uy = (a2 * (cx - bx) + b2 * (ax - cx) + c2 * (bx - ax)) / d
    return ux, uy, math.hypot(ax - ux, ay - uy)


def _direction(line: FieldLine) -> str:
    return UP if line.fit[1] < 0 else DOWN


def _meeting_angle(first: FieldLine, second: FieldLine) -> float:
    """Angle (rad, 0..pi/2) between the straight fits of two lines in the image."""
    k1, k2 = np.polyfit(first.w, first.h, 1)[0], np.polyfit(second.w, second.h, 1)[0]
    angle = abs(math.atan(k1) - math.atan(k2))
    return min(angle, math.pi - angle)


def find_corner(first: FieldLine, second: FieldLine) -> tuple[CornerShape, tuple[float, float]] | None:
    """FindCorner on two side lines, ``first`` starting left of ``second``."""
    if first.line_type == second.line_type and first.line_type != LineType.STRAIGHT:
        return None  # two lines rising (or falling) alike do not make a corner
    if _meeting_angle(first, second) < MIN_MEETING_ANGLE_RAD:
        return None
    pairs = {
        ("end", "start"): (first.end, second.start),
        ("end", "end"): (first.end, second.end),
        ("start", "start"): (first.start, second.start),
        ("start", "end"): (first.start, second.end),
    }
    key, (p, q) = min(pairs.items(), key=lambda kv: math.dist(*kv[1]))
    if abs(p[0] - q[0]) > CORNER_MAX_DW_PX or abs(p[1] - q[1]) > CORNER_MAX_DH_PX:
        return None
    if key == ("end", "start"):
        d1, d2 = _direction(first), _direction(second)
        if (d1, d2) == (UP, DOWN):
            shape = CornerShape.UP
        elif (d1, d2) == (DOWN, UP):
            shape = CornerShape.DOWN
        else:
            return None
    elif key == ("end", "end"):
        shape = CornerShape.RIGHT
    elif key == ("start", "start"):
        shape = CornerShape.LEFT
    else:
        return None
    return shape, _intersection(first, second, p, q)


def _intersection(first: FieldLine, second: FieldLine, p, q) -> tuple[float, float]:
    """Where the two lines' straight fits cross, if near their meeting ends; else between the ends."""
    k1, m1 = np.polyfit(first.w, first.h, 1)
    k2, m2 = np.polyfit(second.w, second.h, 1)
    mid = ((p[0] + q[0]) / 2.0, (p[1] + q[1]) / 2.0)
    if abs(k1 - k2) < 1e-6:
        return mid
    w = (m2 - m1) / (k1 - k2)
    h = k1 * w + m1
    if math.dist((w, h), mid) > CORNER_MAX_DW_PX:
        return mid
    return float(w), float(h)


def find_junction(stem: FieldLine, bar: FieldLine) -> tuple[float, float] | None:
    """A T junction: an end of ``stem`` on the interior of ``bar``."""
    if _meeting_angle(stem, bar) < MIN_MEETING_ANGLE_RAD:
        return None
    w0, w1 = bar.start[0], bar.end[0]
    for w, h in (stem.start, stem.end):
        if w0 + JUNCTION_END_CLEARANCE_PX <= w <= w1 - JUNCTION_END_CLEARANCE_PX:
            if abs(bar.h_at(w) - h) <= JUNCTION_MAX_DH_PX:
                return w, bar.h_at(w)
    return None


def line_landmarks(
    lines: list[FieldLine], frame: CameraFrame, model: CameraModel
) -> tuple[list[LandmarkPercept], list[tuple[str, tuple[float, float]]]]:
    """Percepts of corners, junctions and the circle, and (name, pixel) of each for debugging."""
    found: list[tuple[LandmarkKind, tuple[float, float], CornerShape | None]] = []
    percepts: list[LandmarkPercept] = []
    marks: list[tuple[str, tuple[float, float]]] = []
    for line in lines:
        if line.line_type in (LineType.UP_CORNER, LineType.DOWN_CORNER):
            up = line.line_type == LineType.UP_CORNER
            i = int(np.argmin(line.h)) if up else int(np.argmax(line.h))
            low, high = VERTEX_INTERIOR
            if low * (len(line.runs) - 1) <= i <= high * (len(line.runs) - 1):
                v = line.runs[i].top if up else line.runs[i].bottom
                found.append((LandmarkKind.L_CORNER, (line.w[i], float(v)), CornerShape.UP if up else CornerShape.DOWN))
        elif line.line_type in (LineType.UPPER_HALF_CIRCLE, LineType.DOWN_HALF_CIRCLE):
            circle = _circle_percept(line, frame, model)
            if circle is not None:
                percepts.append(circle)
                marks.append(("circle", circle.pixel))
    sides = sorted((line for line in lines if line.line_type in SIDE_TYPES), key=lambda line: line.start[0])
    for first, second in itertools.combinations(sides, 2):
        corner = find_corner(first, second)
        if corner is not None:
            found.append((LandmarkKind.L_CORNER, corner[1], corner[0]))
            continue
        for stem, bar in ((first, second), (second, first)):
            junction = find_junction(stem, bar)
            if junction is not None:
                found.append((LandmarkKind.T_JUNCTION, junction, None))
                break
    for kind, (u, v), shape in found:
        ground = model.locate(frame, u, v)
        distance, bearing = float(ground.distance_m), float(ground.bearing_rad)
        if math.isfinite(distance):
            percepts.append(LandmarkPercept(kind, (float(u), float(v)), bearing, distance, model.name, corner=shape))
            marks.append((kind.value if shape is None else f"L {shape.value}", (float(u), float(v))))
    return percepts, marks


def _circle_percept(line: FieldLine, frame: CameraFrame, model: CameraModel) -> LandmarkPercept | None:
    """The centre circle from the first, middle and last points of a curved line."""
    idx = [0, len(line.runs) // 2, len(line.runs) - 1]
    ground = model.locate(frame, line.w[idx], line.h[idx])
    if not ground.valid.all():
        return None
    points = ground.xy()
    fitted = circle_through(points[0], points[1], points[2])
    if fitted is None:
        return None
    cx, cy, radius = fitted
    if abs(radius - FIELD.center_circle_radius) > CIRCLE_RADIUS_TOLERANCE_M:
        return None
    return LandmarkPercept(
        LandmarkKind.CENTER_CIRCLE,
        (float(line.w[idx[1]]), float(line.h[idx[1]])),
        math.atan2(cy, cx),
        math.hypot(cx, cy),
        model.name,
        landmark_id=LandmarkId.CENTER_CIRCLE,
    )
