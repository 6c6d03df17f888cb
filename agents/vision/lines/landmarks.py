"""Corners, junctions and the centre circle from classified lines (thesis section 4.5.4).

- FindCorner: two side lines of different directions whose closest ends (end-start: up or
  down corner; end-end: right corner; start-start: left corner) are at most 10 px apart in
  width and 5 px in height. A line that ProcessLine itself called a corner is one too.
- Find Junction: an end of one side line lies inside the other line's span, within 5 px
  in height of it.
- Centre circle: the first, middle and last points of a verified half-circle are located
  on the ground, and the circle through them (section 2.3.2) gives the centre.

Pixels are (u, v) = (column, row); ground points are in the torso frame (x forward,
y left), metres.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from agents.vision.camera_models import CameraModel
from agents.vision.frame import CameraFrame
from agents.vision.lines.classification import ClassifiedLine, LineKind
from agents.vision.lines.scan_lines import DIST
from agents.vision.lines.split_merge import Direction
from agents.vision.percepts import CornerShape
from world.field import FIELD

CORNER_MAX_WIDTH_PX = 10  # thesis 4.5.4 FindCorner: ends "no more than 10 pixels in width"
CORNER_MAX_HEIGHT_PX = 5  # thesis 4.5.4 FindCorner: "and no more than 5 pixels in height"
JUNCTION_MAX_HEIGHT_PX = 5  # thesis 4.5.4 Find Junction: "no more than 5 pixels in height"
# Not in the thesis: how far inside the other line's span an end must be to make a T rather
# than an L (at an L the other line ends there too). One scan column.
JUNCTION_END_MARGIN_PX = DIST
# Not in the thesis: the corner/junction pixel is where the two lines' straight fits cross,
# when that point is this close to the ends that were matched; else the ends' midpoint.
INTERSECTION_MAX_SHIFT_PX = 2 * DIST
# Sanity checks of a located half-circle, not in the thesis. On 150 rendered views of the
# field (exact camera model) true arcs gave radii 0.53-0.71 m and an RMS residual of all
# their located midpoints <= 0.02 m (one 0.04), while arcs that were really two merged
# parallel lines or a bent corner gave radii anywhere and residuals of 0.035-0.07 m (a few
# had radii of 0.4-0.7 m by chance). A radius within 0.15 m (25%) of 0.6 m and a residual
# of at most 3 cm keep the true arcs and drop those.
CIRCLE_RADIUS_TOLERANCE_M = 0.15
CIRCLE_MAX_RESIDUAL_M = 0.03
# Not in the thesis: "the directions of the two side lines can form a corner" also needs
# their straight fits to cross at an angle of at least this in the image. Collinear pieces
# of one line classified on either side of Table 4.3's |b| = 0.07 are otherwise a "corner".
CORNER_MIN_ANGLE_RAD = math.radians(15.0)
# Not in the thesis: a line that ProcessLine calls a corner must have its highest (up) or
# lowest (down) point inside, rising this much above both ends (Algorithm 3's 2 px step).
# A parabola through a few noisy points of a straight line easily passes Table 4.3's
# |a| >= 5.2, but its extreme point is then one of its ends.
LINE_CORNER_MIN_RISE_PX = 2.0

# Not in the thesis: an arm's direction at a vertex is taken to its midpoint this many scan
# columns away (a curved arm's far end is off its tangent).
TANGENT_COLUMNS = 3

_RANK = {Direction.UP: 1, Direction.STRAIGHT: 0, Direction.DOWN: -1}


@dataclass(frozen=True)
class CornerSighting:
    """An L corner in the image: its pixel (u, v) and how it appears.

    ``arm_ends``: the far end of each arm; ``arm_near``: a point of each arm
    TANGENT_COLUMNS scan columns from the vertex, giving its direction there (pixels).
    """

    pixel: tuple[float, float]
    shape: CornerShape
    arm_ends: tuple[tuple[float, float], tuple[float, float]]
    arm_near: tuple[tuple[float, float], tuple[float, float]]


@dataclass(frozen=True)
class JunctionSighting:
    """A T junction in the image: its pixel (u, v), its stem's far end and near point (as for corners), and its bar's ends."""

    pixel: tuple[float, float]
    stem_end: tuple[float, float]
    stem_near: tuple[float, float]
    bar_ends: tuple[tuple[float, float], tuple[float, float]]


@dataclass(frozen=True)
class CircleSighting:
    """A verified half-circle located on the ground.

    ``pixels``: its first, middle and last midpoints (u, v); ``points_m``: those on the
    ground (torso frame, metres); ``center_m``/``radius_m``: the circle through them;
    ``residual_m``: RMS distance of all the line's located midpoints from that circle;
    ``accepted``: the radius is within CIRCLE_RADIUS_TOLERANCE_M of the field's and the
    residual at most CIRCLE_MAX_RESIDUAL_M.
    """

    pixels: tuple[tuple[float, float], ...]
    points_m: tuple[tuple[float, float], ...]
    center_m: tuple[float, float]
    radius_m: float
    residual_m: float
    accepted: bool


def _midpoint(line: ClassifiedLine, index: int) -> tuple[float, float]:
    """The line's midpoint ``index`` (clipped to the line), as (u, v) floats."""
    i = min(max(index, 0), len(line.u) - 1)
    return float(line.u[i]), float(line.v[i])


def _near_point(line: ClassifiedLine, at_end: bool) -> tuple[float, float]:
    """The midpoint of ``line`` TANGENT_COLUMNS from its end (``at_end``) or its start, or its other end if shorter."""
    return _midpoint(line, len(line.u) - 1 - TANGENT_COLUMNS if at_end else TANGENT_COLUMNS)


def _crossing(l1: ClassifiedLine, l2: ClassifiedLine, near: tuple[float, float]) -> tuple[float, float]:
    """Where the straight fits of two lines cross, if close to ``near``; else ``near``."""
    s1, c1 = l1.straight_fit
    s2, c2 = l2.straight_fit
    if abs(s1 - s2) > 1e-6:
        u = (c2 - c1) / (s1 - s2)
        v = s1 * u + c1
        if math.hypot(u - near[0], v - near[1]) <= INTERSECTION_MAX_SHIFT_PX:
            return u, v
    return near


def find_corner(l1: ClassifiedLine, l2: ClassifiedLine) -> CornerSighting | None:
    """FindCorner on two side lines, ``l1`` starting left of ``l2``.

    The thesis' up corner is (up, down) at end1-start2 and its down corner (down, up). It
    only says that equal directions cannot form a corner; we also accept a straight line
    with a sloped one (the common view of an L with one side across the image), ranking
    up > straight > down: at end1-start2 the vertex is an up corner when line 1 rises more.
    """
    d1, d2 = l1.kind.side_direction, l2.kind.side_direction
    if d1 is None or d2 is None or d1 is d2:
        return None
    angle = abs(math.atan(l1.straight_fit[0]) - math.atan(l2.straight_fit[0]))
    if min(angle, math.pi - angle) < CORNER_MIN_ANGLE_RAD:
        return None
    # (which ends meet, l1's meeting end, l2's meeting end, l1's far end, l2's far end, whether
    # l1 meets at its end, whether l2 does)
    pairs = (
        ("end_start", l1.end, l2.start, l1.start, l2.end, True, False),
        ("end_end", l1.end, l2.end, l1.start, l2.start, True, True),
        ("start_start", l1.start, l2.start, l1.end, l2.end, False, False),
    )
    which, p, q, far1, far2, at1, at2 = min(
        pairs, key=lambda item: math.hypot(item[1][0] - item[2][0], item[1][1] - item[2][1])
    )
    if abs(p[0] - q[0]) > CORNER_MAX_WIDTH_PX or abs(p[1] - q[1]) > CORNER_MAX_HEIGHT_PX:
        return None
    if which == "end_start":
        shape = CornerShape.UP if _RANK[d1] > _RANK[d2] else CornerShape.DOWN
    else:
        shape = CornerShape.RIGHT if which == "end_end" else CornerShape.LEFT
    vertex = _crossing(l1, l2, ((p[0] + q[0]) / 2.0, (p[1] + q[1]) / 2.0))
    return CornerSighting(vertex, shape, (far1, far2), (_near_point(l1, at1), _near_point(l2, at2)))


def find_junction(stem: ClassifiedLine, bar: ClassifiedLine) -> JunctionSighting | None:
    """Find Junction: where an end of ``stem`` meets ``bar`` inside its span, or None."""
    for end, far, at_end in ((stem.start, stem.end, False), (stem.end, stem.start, True)):
        if not bar.start[0] + JUNCTION_END_MARGIN_PX <= end[0] <= bar.end[0] - JUNCTION_END_MARGIN_PX:
            continue
        bar_v = float(np.interp(end[0], bar.u, bar.v))
        if abs(end[1] - bar_v) <= JUNCTION_MAX_HEIGHT_PX:
            vertex = _crossing(stem, bar, (end[0], bar_v))
            return JunctionSighting(vertex, far, _near_point(stem, at_end), (bar.start, bar.end))
    return None


def line_corner(line: ClassifiedLine) -> CornerSighting | None:
    """The corner of a line ProcessLine called a corner: its highest (up) or lowest (down) point.

    None when that point does not stand LINE_CORNER_MIN_RISE_PX clear of both ends.
    """
    up = line.kind is LineKind.UP_CORNER
    sign = 1.0 if up else -1.0  # rows grow down: an up corner's vertex has the smallest row
    k = int(np.argmin(sign * line.v))
    rise = min(sign * (line.v[0] - line.v[k]), sign * (line.v[-1] - line.v[k]))
    if rise < LINE_CORNER_MIN_RISE_PX:
        return None
    near = (_midpoint(line, k - TANGENT_COLUMNS), _midpoint(line, k + TANGENT_COLUMNS))
    return CornerSighting(_midpoint(line, k), CornerShape.UP if up else CornerShape.DOWN, (line.start, line.end), near)


def detect_corners_and_junctions(
    lines: tuple[ClassifiedLine, ...],
) -> tuple[tuple[CornerSighting, ...], tuple[JunctionSighting, ...]]:
    """DetectCornersAndJunctions over all pairs of side lines, plus the lines that are corners."""
    corners = [corner for line in lines if line.kind.is_corner and (corner := line_corner(line)) is not None]
    junctions: list[JunctionSighting] = []
    sides = sorted((line for line in lines if line.kind.side_direction is not None), key=lambda line: line.start)
    for i, l1 in enumerate(sides):
        for l2 in sides[i + 1 :]:
            corner = find_corner(l1, l2)
            if corner is not None:
                corners.append(corner)
                continue
            junction = find_junction(l1, l2) or find_junction(l2, l1)
            if junction is not None:
                junctions.append(junction)
    return distinct_sightings(corners), distinct_sightings(junctions)


def distinct_sightings(items: list) -> tuple:
    """The sightings (with a ``pixel``) whose pixels are at least two scan columns from an earlier one's."""
    out: list = []
    for item in items:
        u, v = item.pixel
        if all(math.hypot(u - o.pixel[0], v - o.pixel[1]) >= 2 * DIST for o in out):
            out.append(item)
    return tuple(out)


def circle_through_three_points(
    a: tuple[float, float], b: tuple[float, float], c: tuple[float, float]
) -> tuple[float, float, float] | None:
    """Centre (x, y) and radius of the circle through three points (thesis 2.3.2), or None if collinear.

    The thesis intersects the perpendicular bisectors written with slopes, which divide by
    zero for vertical or horizontal chords; this is the same intersection in the slope-free
    form, computed relative to ``a`` for precision.
    """
    bx, by = b[0] - a[0], b[1] - a[1]
    cx, cy = c[0] - a[0], c[1] - a[1]
    d = 2.0 * (bx * cy - by * cx)
    scale = max(bx * bx + by * by, cx * cx + cy * cy)
    if scale == 0.0 or abs(d) <= 1e-9 * scale:
        return None
    b2, c2 = bx * bx + by * by, cx * cx + cy * cy
    ux = (cy * b2 - by * c2) / d
    uy = (bx * c2 - cx * b2) / d
    return a[0] + ux, a[1] + uy, math.hypot(ux, uy)


def locate_circle(line: ClassifiedLine, frame: CameraFrame, model: CameraModel) -> CircleSighting | None:
    """The centre circle from a verified half-circle: first, middle, last points on the ground.

    Every midpoint of the line is located too, for the sanity check on the fit's residual.
    """
    ground = model.locate(frame, line.u, line.v)
    index = [0, len(line.u) // 2, len(line.u) - 1]
    if not ground.valid[index].all():
        return None
    xy = ground.xy()
    points = tuple(map(tuple, xy[index].tolist()))
    fit = circle_through_three_points(*points)
    if fit is None:
        return None
    cx, cy, radius = fit
    valid = xy[ground.valid]
    residual = float(np.sqrt(np.mean((np.hypot(valid[:, 0] - cx, valid[:, 1] - cy) - radius) ** 2)))
    accepted = abs(radius - FIELD.center_circle_radius) <= CIRCLE_RADIUS_TOLERANCE_M and residual <= CIRCLE_MAX_RESIDUAL_M
    pixels = tuple((float(line.u[k]), float(line.v[k])) for k in index)
    return CircleSighting(pixels, points, (cx, cy), radius, residual, accepted)
