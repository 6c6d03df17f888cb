"""Checking corners and junctions against the picture around them (not in the thesis).

FindCorner and Find Junction (thesis 4.5.4) look only at the ends of the lines they pair.
On our rendered field most of their false landmarks are real crossings of painted lines
that are not landmarks (the centre circle crossing the middle line, the middle line's and the
goal areas' T junctions), and a T junction whose bar was seen on one side only is called an
L corner (docs/results.md, "False corners and junctions"). The checks, with distances
measured on the ground through the camera model:

- paint: each arm, as a straight segment, lies on white (lines merged across a crossing
  do not); for a T junction the whole bar too;
- square: the arms meet at a right angle on the ground, as at every corner and junction
  of the field;
- circle: no sighting on the line of a centre circle accepted in the same frame;
- continuation: an arm *continues* when white goes on beyond the vertex, between
  ``CONTINUATION_NEAR_M`` and ``CONTINUATION_FAR_M`` from it (clear of the other line's
  paint). At an L neither arm continues; if one does the sighting is a T junction on that
  line; if both do it is a crossing. A T junction's stem must not continue beyond its bar;
- goal area: a T junction with a goal colour (a post base) on its bar within
  ``GOAL_AREA_POST_WINDOW_M`` is where a goal-area line meets the goal line, not a landmark.

Where the frame does not show the place a check looks at (out of the image, beyond the
field border), the sighting is dropped: an L corner at the image edge may be a T junction
or a crossing. The one exception: a T junction whose bar is cut off before a post could
show stands when its stem is longer than a goal-area line.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

import numpy as np

from agents.vision.border import FieldBorder
from agents.vision.camera_models import CameraModel
from agents.vision.colors import ColorClass
from agents.vision.frame import CameraFrame
from agents.vision.lines.landmarks import CircleSighting, CornerSighting, JunctionSighting, distinct_sightings
from world.field import FIELD

# The painted lines are 0.05 m wide, so 0.08 m from the vertex is 0.055 m clear of the
# other line's paint; 0.25 m is short enough that the centre circle (radius 0.6 m) bends
# away from its tangent by under 0.03 m, still on its paint.
CONTINUATION_NEAR_M = 0.08
CONTINUATION_FAR_M = 0.25
# A circle arc's direction a few scan columns from the vertex is some degrees off its
# tangent, and the vertex pixel a few pixels off; the other arm of an L, at 90 degrees,
# covers only 90 +- 17 degrees at 0.08 m.
CONTINUATION_HALF_ANGLE_RAD = math.radians(30.0)
CONTINUATION_BINS = 4  # the stretch split by distance from the vertex
# Bins that must show white for the line to go on: far lines render as dashes.
CONTINUATION_MIN_WHITE_BINS = 2
WINDOW_PX = 40  # half-size of the image window searched around the vertex
SIDE_PX = 2  # pixels either side of a segment searched for its paint (midpoints are a pixel or two off)
PAINTED_FRACTION = 0.8  # share of an arm's pixels that must be on paint
SQUARE_TOLERANCE_RAD = math.radians(25.0)  # how far from 90 degrees the arms may meet on the ground
SAMPLE_MAX_PX = 120  # farthest pixel from the vertex sampled along a bar
# Goal posts stand on the goal line 0.4 m from the goal-area T junctions (posts at y = 0.7 m,
# goal-area lines at 1.1 m); their bases are the only goal colour near any line junction.
GOAL_AREA_POST_WINDOW_M = 0.6
# A post's near edge is 0.35 m from a goal-area T junction. A bar seen less than this far on
# a side leaves the question open. 0.3 m, not 0.35: measured on 1000 views (seed 0), 0.45 m
# gave T junction precision 0.96 and recall 0.12, 0.3 m 0.94 and 0.14.
POST_WINDOW_MIN_REACH_M = 0.3
# A goal-area side line is 0.6 m long; a T junction's stem seen longer is the middle line,
# which settles it when the bar is cut off by the frame before a post could show.
GOAL_AREA_STEM_MAX_M = FIELD.goal_area_depth + 0.15
POST_ROWS_ABOVE_PX = 6  # rows above the bar searched for a post base
POST_ROWS_BELOW_PX = 2
IS_GOAL_CLASS = np.isin(np.arange(256), [int(ColorClass.BLUE), int(ColorClass.YELLOW)])  # lookup over labels
WHITE = int(ColorClass.WHITE)
# Where the centre circle, when seen in the same frame, crosses the middle line: within this
# of its painted line (the nearest landmark, a middle-line T junction, is 1.4 m from it).
CIRCLE_RING_TOLERANCE_M = 0.25


class Verdict(enum.Enum):
    """What the checks make of a sighting."""

    L_CORNER = "l_corner"
    T_JUNCTION = "t_junction"
    REJECTED = "rejected"


def _ray_pixels(shape: tuple[int, ...], vertex: tuple[float, float], toward: tuple[float, float]) -> tuple[np.ndarray, np.ndarray]:
    """Pixels (u, v) on the ray from ``vertex`` toward ``toward``, up to SAMPLE_MAX_PX, inside an image of ``shape``."""
    d = np.subtract(toward, vertex).astype(float)
    norm = float(np.hypot(*d))
    if norm < 1e-9:
        return np.zeros(0), np.zeros(0)
    t = np.arange(1, SAMPLE_MAX_PX + 1, dtype=float)
    u = vertex[0] + t * d[0] / norm
    v = vertex[1] + t * d[1] / norm
    h, w = shape[:2]
    inside = (u >= 0) & (u <= w - 1) & (v >= 0) & (v <= h - 1)
    return u[inside], v[inside]


def _ground_gaps(
    frame: CameraFrame, model: CameraModel, vertex: tuple[float, float], u: np.ndarray, v: np.ndarray
) -> np.ndarray:
    """Ground distance (m) from the vertex's ground point to each pixel's (u, v); NaN off the ground."""
    ground = model.locate(frame, np.append(u, vertex[0]), np.append(v, vertex[1]))
    xy = ground.xy()
    return np.hypot(xy[:-1, 0] - xy[-1, 0], xy[:-1, 1] - xy[-1, 1])


@dataclass(frozen=True, eq=False)
class GroundWindow:
    """The pixels (u, v) within WINDOW_PX of a vertex and below the field border, and their ground
    points ``xy`` (N, 2; torso frame, m; NaN off the ground, ``valid`` False)."""

    u: np.ndarray
    v: np.ndarray
    xy: np.ndarray
    valid: np.ndarray


def ground_window(
    labels: np.ndarray, border: FieldBorder, frame: CameraFrame, model: CameraModel, vertex: tuple[float, float]
) -> GroundWindow:
    """The :class:`GroundWindow` around ``vertex`` (pixels); empty when the vertex is far out of the image."""
    h, w = labels.shape
    u0, v0 = int(round(vertex[0])), int(round(vertex[1]))
    rows = np.arange(max(0, v0 - WINDOW_PX), min(h, v0 + WINDOW_PX + 1))
    cols = np.arange(max(0, u0 - WINDOW_PX), min(w, u0 + WINDOW_PX + 1))
    below = np.flatnonzero(rows[:, None] > border.row_at(cols)[None, :])  # row-major over the window
    vv, uu = rows[below // len(cols)], cols[below % len(cols)]
    ground = model.locate(frame, uu, vv)
    return GroundWindow(uu, vv, ground.xy(), ground.valid)


def arm_continues(
    labels: np.ndarray,
    window: GroundWindow,
    frame: CameraFrame,
    model: CameraModel,
    vertex: tuple[float, float],
    arm_end: tuple[float, float],
) -> bool | None:
    """Whether the line from ``arm_end`` to ``vertex`` goes on beyond the vertex; None when the image cannot tell.

    On the ground, the pixels of ``window`` (around ``vertex``) between CONTINUATION_NEAR_M and
    CONTINUATION_FAR_M beyond the vertex and within CONTINUATION_HALF_ANGLE_RAD of the arm's
    direction are split into CONTINUATION_BINS by distance: the line goes on when white is in
    at least CONTINUATION_MIN_WHITE_BINS of them. A sector rather than a ray, because the
    vertex pixel is a few pixels off and a curved arm's chord is not its tangent at the vertex.
    """
    ends = model.locate(frame, np.array([vertex[0], arm_end[0]]), np.array([vertex[1], arm_end[1]]))
    if not ends.valid.all():
        return None
    origin, far = ends.xy()
    ahead = origin - far  # the arm's direction, continued beyond the vertex
    length = float(np.hypot(*ahead))
    if length < 1e-6:
        return None
    ahead /= length
    offset = window.xy - origin
    along = offset @ ahead
    across = offset @ np.array([-ahead[1], ahead[0]])
    r = np.hypot(along, across)
    ring = np.flatnonzero(window.valid & (r >= CONTINUATION_NEAR_M) & (r <= CONTINUATION_FAR_M))
    sector = ring[np.abs(np.arctan2(across[ring], along[ring])) <= CONTINUATION_HALF_ANGLE_RAD]
    stretch = (r[sector] - CONTINUATION_NEAR_M) / (CONTINUATION_FAR_M - CONTINUATION_NEAR_M)
    bins = np.minimum((stretch * CONTINUATION_BINS).astype(int), CONTINUATION_BINS - 1)
    if int(np.count_nonzero(np.bincount(bins, minlength=CONTINUATION_BINS))) < CONTINUATION_BINS:
        return None  # part of the stretch is out of the image or beyond the field border
    white = labels[window.v[sector], window.u[sector]] == WHITE
    return int(np.count_nonzero(np.bincount(bins[white], minlength=CONTINUATION_BINS))) >= CONTINUATION_MIN_WHITE_BINS


def post_on_bar(labels: np.ndarray, frame: CameraFrame, model: CameraModel, junction: JunctionSighting) -> bool | None:
    """Whether a goal colour touches the junction's bar within GOAL_AREA_POST_WINDOW_M of the vertex.

    None when no post is seen but the image shows less than POST_WINDOW_MIN_REACH_M of the
    bar on a side: a post may stand just out of the frame.
    """
    h, w = labels.shape
    cut_off = False
    for end in junction.bar_ends:
        u, v = _ray_pixels(labels.shape, junction.pixel, end)
        gaps = _ground_gaps(frame, model, junction.pixel, u, v) if len(u) else np.zeros(0)
        band = gaps <= GOAL_AREA_POST_WINDOW_M  # NaN compares False
        cut_off |= not bool((gaps >= POST_WINDOW_MIN_REACH_M).any())
        # The rows from POST_ROWS_ABOVE_PX above to POST_ROWS_BELOW_PX below each band pixel.
        rows = np.rint(v[band]).astype(int)[:, None] + np.arange(-POST_ROWS_ABOVE_PX, POST_ROWS_BELOW_PX + 1)
        columns = np.minimum(np.rint(u[band]).astype(int), w - 1)[:, None]
        in_image = (rows >= 0) & (rows < h)
        if (IS_GOAL_CLASS[labels[np.minimum(np.maximum(rows, 0), h - 1), columns]] & in_image).any():
            return True
    return None if cut_off else False


def segment_painted(labels: np.ndarray, start: tuple[float, float], end: tuple[float, float]) -> bool:
    """Whether the straight segment from ``start`` to ``end`` (pixels) runs on white paint.

    At least PAINTED_FRACTION of its pixels must have white within SIDE_PX across it.
    """
    h, w = labels.shape
    d = np.subtract(end, start).astype(float)
    length = float(np.hypot(*d))
    if length < 1.0:
        return True
    t = np.linspace(0.0, 1.0, int(np.ceil(length)) + 1)
    u = start[0] + t * d[0]
    v = start[1] + t * d[1]
    normal = np.array([-d[1], d[0]]) / length
    across = np.arange(-SIDE_PX, SIDE_PX + 1)[:, None]  # one row of samples per offset across the segment
    cu = np.minimum(np.maximum(np.rint(u + across * normal[0]).astype(int), 0), w - 1)
    cv = np.minimum(np.maximum(np.rint(v + across * normal[1]).astype(int), 0), h - 1)
    white = (labels[cv, cu] == WHITE).any(axis=0)
    return int(np.count_nonzero(white)) / len(t) >= PAINTED_FRACTION


def ground_angle_rad(
    frame: CameraFrame, model: CameraModel, vertex: tuple[float, float], a: tuple[float, float], b: tuple[float, float]
) -> float | None:
    """Angle (rad, 0..pi) on the ground between the directions vertex->a and vertex->b; None if not all are on the ground."""
    ground = model.locate(frame, np.array([vertex[0], a[0], b[0]]), np.array([vertex[1], a[1], b[1]]))
    if not ground.valid.all():
        return None
    o, p, q = ground.xy()
    da, db = p - o, q - o
    na, nb = float(np.hypot(*da)), float(np.hypot(*db))
    if na < 1e-6 or nb < 1e-6:
        return None
    return math.acos(float(np.clip(da @ db / (na * nb), -1.0, 1.0)))


def square_on_ground(
    frame: CameraFrame, model: CameraModel, vertex: tuple[float, float], a: tuple[float, float], b: tuple[float, float]
) -> bool:
    """Whether vertex->a and vertex->b meet at a right angle on the ground, within SQUARE_TOLERANCE_RAD."""
    angle = ground_angle_rad(frame, model, vertex, a, b)
    return angle is not None and abs(angle - math.pi / 2.0) <= SQUARE_TOLERANCE_RAD


def on_circle_ring(
    frame: CameraFrame, model: CameraModel, pixels: list[tuple[float, float]], circle: CircleSighting
) -> list[bool]:
    """Whether each pixel lies on the ground within CIRCLE_RING_TOLERANCE_M of the seen centre circle's line."""
    if not pixels:
        return []
    u, v = np.array(pixels, float).T
    ground = model.locate(frame, u, v)
    on_ring = []
    for (x, y), valid in zip(ground.xy().tolist(), ground.valid.tolist()):
        gap = math.hypot(x - circle.center_m[0], y - circle.center_m[1]) - FIELD.center_circle_radius
        on_ring.append(valid and abs(gap) <= CIRCLE_RING_TOLERANCE_M)
    return on_ring


def _stem_longer_than_goal_area(frame: CameraFrame, model: CameraModel, junction: JunctionSighting) -> bool:
    """Whether the stem seen is longer on the ground than a goal-area side line (then it is the middle line)."""
    gaps = _ground_gaps(frame, model, junction.pixel, np.array([junction.stem_end[0]]), np.array([junction.stem_end[1]]))
    return bool(gaps[0] >= GOAL_AREA_STEM_MAX_M)  # NaN compares False


def _junction_verdict(
    labels: np.ndarray,
    border: FieldBorder,
    frame: CameraFrame,
    model: CameraModel,
    junction: JunctionSighting,
    check_paint: bool = True,
    window: GroundWindow | None = None,
) -> Verdict:
    """The checks of a T junction; ``window``: its vertex's :class:`GroundWindow` if already made."""
    if check_paint and not (
        segment_painted(labels, junction.pixel, junction.stem_end) and segment_painted(labels, *junction.bar_ends)
    ):
        return Verdict.REJECTED
    if not square_on_ground(frame, model, junction.pixel, junction.stem_end, junction.bar_ends[0]):
        return Verdict.REJECTED
    if window is None:
        window = ground_window(labels, border, frame, model, junction.pixel)
    if arm_continues(labels, window, frame, model, junction.pixel, junction.stem_near) is not False:
        return Verdict.REJECTED
    post = post_on_bar(labels, frame, model, junction)
    if post or (post is None and not _stem_longer_than_goal_area(frame, model, junction)):
        return Verdict.REJECTED
    return Verdict.T_JUNCTION


def verify_corner(
    labels: np.ndarray, border: FieldBorder, frame: CameraFrame, model: CameraModel, corner: CornerSighting
) -> tuple[Verdict, JunctionSighting | None]:
    """What an L corner sighting is: an L corner, a T junction (returned as one) or nothing."""
    first, second = corner.arm_ends
    if not (segment_painted(labels, corner.pixel, first) and segment_painted(labels, corner.pixel, second)):
        return Verdict.REJECTED, None
    if not square_on_ground(frame, model, corner.pixel, first, second):
        return Verdict.REJECTED, None
    window = ground_window(labels, border, frame, model, corner.pixel)
    goes_on = [arm_continues(labels, window, frame, model, corner.pixel, near) for near in corner.arm_near]
    if goes_on[0] and goes_on[1]:
        return Verdict.REJECTED, None
    if goes_on[0] is False and goes_on[1] is False:
        return Verdict.L_CORNER, None
    if goes_on[0] is None or goes_on[1] is None:
        return Verdict.REJECTED, None  # the frame cuts it off: an L, a T or a crossing
    bar_end, stem_end = (first, second) if goes_on[0] else (second, first)
    stem_near = corner.arm_near[1] if goes_on[0] else corner.arm_near[0]
    # The bar runs from its seen arm's end through the vertex and on: its other end is the
    # vertex mirrored, which is all the post check needs (a direction along the bar).
    mirrored = (2.0 * corner.pixel[0] - bar_end[0], 2.0 * corner.pixel[1] - bar_end[1])
    junction = JunctionSighting(corner.pixel, stem_end, stem_near, (bar_end, mirrored))
    # The arms were checked for paint above.
    verdict = _junction_verdict(labels, border, frame, model, junction, check_paint=False, window=window)
    return verdict, junction if verdict is Verdict.T_JUNCTION else None


def verify_junction(
    labels: np.ndarray, border: FieldBorder, frame: CameraFrame, model: CameraModel, junction: JunctionSighting
) -> bool:
    """Whether a T junction sighting stands: its stem stops at the bar and no post stands on the bar nearby."""
    return _junction_verdict(labels, border, frame, model, junction) is Verdict.T_JUNCTION


def verify_sightings(
    labels: np.ndarray,
    border: FieldBorder,
    frame: CameraFrame,
    model: CameraModel,
    corners: tuple[CornerSighting, ...],
    junctions: tuple[JunctionSighting, ...],
    circle: CircleSighting | None = None,
) -> tuple[tuple[CornerSighting, ...], tuple[JunctionSighting, ...]]:
    """The corners and junctions that stand after the checks (module docstring); re-typed L corners join the junctions.

    ``circle``: the centre circle accepted in the same frame, if any.
    """
    if circle is not None:
        on_ring = on_circle_ring(frame, model, [s.pixel for s in corners + junctions], circle)
        corners_on_ring, junctions_on_ring = on_ring[: len(corners)], on_ring[len(corners) :]
        corners = tuple(c for c, ring in zip(corners, corners_on_ring) if not ring)
        junctions = tuple(j for j, ring in zip(junctions, junctions_on_ring) if not ring)
    kept_corners: list[CornerSighting] = []
    kept_junctions = [j for j in junctions if verify_junction(labels, border, frame, model, j)]
    for corner in corners:
        verdict, junction = verify_corner(labels, border, frame, model, corner)
        if verdict is Verdict.L_CORNER:
            kept_corners.append(corner)
        elif junction is not None:
            kept_junctions.append(junction)
    return tuple(kept_corners), distinct_sightings(kept_junctions)
