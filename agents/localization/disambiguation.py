"""Landmark disambiguation (thesis 5.2): from percepts to observations of known landmarks.

Goal posts whose side is known, goal centres and the centre circle are unique and placed
directly. L corners and T junctions look alike, so each is placed by the goal post nearest
to it in bearing, together with its corner shape; it is rejected when that post is more
than 51 degrees away, and cannot be placed when no post (of known side) was seen. Posts of
unknown side are not used here.

How the (post, shape) -> corner table (:func:`corner_table`, built from the field geometry)
was derived. The thesis' frame (section 5.1: x from the blue to the yellow goal, y along the
middle line "with the blue goal on the left", i.e. +y to the left when facing +x) is ours,
and its example -- an up corner nearest the blue left post is the field corner at (-3, -2)
-- fixes "left" as seen from inside the field facing that goal, which is
:mod:`world.field`'s convention (the blue left post is at y = -0.75; the blue left field
corner at (-3, -2)). Seen from inside the field, a field corner's two lines both come
toward the robot, one to each side: an up corner ("^"). A goal-area corner seen from the
rest of the field has both lines leaving to one side: a left corner ("<", its vertex on the
left) for the goal's left goal-area corner, a right corner (">") for its right one; seen
from beyond the goal area's side line both lines go away from the robot: a down corner
("v"). So, for the post of goal G on side S:

- up corner -> field corner of G on side S;
- down corner -> goal-area corner of G on side S;
- left / right corner -> left / right goal-area corner of G, whatever the post's side;
- T junction -> the junction on the post's side of the field (same sign of y).

Not in the thesis (ours): from inside a goal area its goal-area corners look like up
corners too, so an up corner within reach of such a robot (``hypot(0.6, 2.2)`` m plus the
gate's slack) may also be the goal-area corner of G on side S. Each table
entry lists the possible corners, the thesis' answer first, and the one is taken whose
field distance to the post best matches the distance between the two percepts; a corner
or junction is rejected when even that match is off by more than
``SEPARATION_GATE_M + SEPARATION_GATE_PER_M * (farther distance)``, or when a landmark of
its kind outside the entry matches better. This catches the nearest post being the wrong
one (say only the other post of the goal was seen), where the table would place the
landmark on the wrong side, and a corner seen from an odd angle (a field corner looking
like a left corner from right beside one of its lines). ``check_separation=False`` gives
the thesis' table alone.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Sequence
from functools import lru_cache

from agents.localization.estimate import LandmarkObservation
from agents.vision.percepts import CornerShape, LandmarkPercept
from world.field import FIELD, FieldGeometry, Landmark, LandmarkId, LandmarkKind, normalize_angle

LOG = logging.getLogger(__name__)

CORNER_POST_MAX_ANGLE_RAD = math.radians(51.0)  # thesis 5.2: corner/junction rejected beyond 51 degrees from its post
SEPARATION_GATE_M = 0.3  # ours: post-to-landmark distance may differ from the field's by this ...
SEPARATION_GATE_PER_M = 0.1  # ... plus this per metre of the farther of the two percepts

CornerTable = dict[tuple[LandmarkId, CornerShape], tuple[LandmarkId, ...]]
JunctionTable = dict[LandmarkId, tuple[LandmarkId, ...]]


def _same_side(a: float, b: float) -> bool:
    return (a > 0) == (b > 0)


@lru_cache(maxsize=8)
def corner_table(field: FieldGeometry = FIELD) -> CornerTable:
    """(goal post, corner shape) -> possible L corners, the thesis' answer first (module docstring)."""
    posts = [lm for lm in field.landmarks if lm.kind is LandmarkKind.GOAL_POST]
    corners = [lm for lm in field.landmarks if lm.kind is LandmarkKind.L_CORNER]
    table: CornerTable = {}
    for post in posts:
        own = [c for c in corners if c.goal is post.goal]
        field_corners = [c for c in own if math.isclose(abs(c.x), field.half_length)]
        area_corners = [c for c in own if math.isclose(abs(c.x), field.goal_area_x)]
        left_post = next(p for p in posts if p.goal is post.goal and p.id.name.endswith("_LEFT_POST"))
        side = [c for c in field_corners if _same_side(c.y, post.y)]
        area_side = [c for c in area_corners if _same_side(c.y, post.y)]
        area_left = [c for c in area_corners if _same_side(c.y, left_post.y)]
        area_right = [c for c in area_corners if not _same_side(c.y, left_post.y)]
        table[(post.id, CornerShape.UP)] = (side[0].id, area_side[0].id)
        table[(post.id, CornerShape.DOWN)] = (area_side[0].id,)
        table[(post.id, CornerShape.LEFT)] = (area_left[0].id,)
        table[(post.id, CornerShape.RIGHT)] = (area_right[0].id,)
    return table


@lru_cache(maxsize=8)
def junction_table(field: FieldGeometry = FIELD) -> JunctionTable:
    """Goal post -> the T junction on its side of the field (same sign of y)."""
    junctions = [lm for lm in field.landmarks if lm.kind is LandmarkKind.T_JUNCTION]
    return {
        lm.id: tuple(j.id for j in junctions if _same_side(j.y, lm.y))
        for lm in field.landmarks
        if lm.kind is LandmarkKind.GOAL_POST
    }


def observe(percept: LandmarkPercept, landmark: Landmark) -> LandmarkObservation:
    """The observation of ``landmark`` that ``percept`` makes."""
    return LandmarkObservation(landmark.id, landmark.x, landmark.y, float(percept.distance_m), float(percept.bearing_rad))


def unique_landmark(percept: LandmarkPercept, field: FieldGeometry = FIELD) -> Landmark | None:
    """The landmark a percept names by itself (posts of known side, goal centres, the circle), else None."""
    landmark_id = percept.landmark_id
    if landmark_id is None and percept.kind is LandmarkKind.CENTER_CIRCLE:
        landmark_id = LandmarkId.CENTER_CIRCLE
    if landmark_id is None and percept.kind is LandmarkKind.GOAL_CENTER and percept.goal is not None:
        landmark_id = LandmarkId[f"{percept.goal.name}_GOAL_CENTER"]
    if landmark_id is None:
        return None
    landmark = field.landmark(landmark_id)
    if landmark.kind is not percept.kind:
        LOG.debug("percept of kind %s names landmark %s of kind %s; ignored", percept.kind, landmark_id, landmark.kind)
        return None
    return landmark


def _inside_area_reach_m(field: FieldGeometry) -> float:
    """Farthest a goal-area corner can be from a robot inside that goal area, with the gate's slack."""
    reach = math.hypot(field.goal_area_depth, field.goal_area_width)
    return reach + SEPARATION_GATE_M + SEPARATION_GATE_PER_M * reach


def _separation_gate_m(a: LandmarkPercept, b: LandmarkPercept) -> float:
    return SEPARATION_GATE_M + SEPARATION_GATE_PER_M * max(a.distance_m, b.distance_m)


def resolve(
    percept: LandmarkPercept,
    posts: Sequence[tuple[LandmarkPercept, Landmark]],
    field: FieldGeometry = FIELD,
    max_angle_rad: float = CORNER_POST_MAX_ANGLE_RAD,
    check_separation: bool = True,
) -> Landmark | None:
    """The L corner or T junction ``percept`` shows, placed by the nearest post of ``posts`` (thesis 5.2).

    ``posts``: the scan's goal-post percepts of known side with their landmarks. None when
    no post is within ``max_angle_rad`` in bearing, the corner has no shape, or (with
    ``check_separation``) no table entry fits the post-to-landmark distance.
    """
    if not posts:
        return None
    post, post_landmark = min(posts, key=lambda item: abs(normalize_angle(percept.bearing_rad - item[0].bearing_rad)))
    if abs(normalize_angle(percept.bearing_rad - post.bearing_rad)) > max_angle_rad:
        return None
    if percept.kind is LandmarkKind.L_CORNER:
        if percept.corner is None:
            return None
        choices = corner_table(field)[(post_landmark.id, percept.corner)]
    elif percept.kind is LandmarkKind.T_JUNCTION:
        choices = junction_table(field)[post_landmark.id]
    else:
        return None
    landmarks = [field.landmark(landmark_id) for landmark_id in choices]
    if percept.kind is LandmarkKind.L_CORNER and percept.distance_m > _inside_area_reach_m(field):
        landmarks = landmarks[:1]  # the robot is not inside the goal area: the thesis' answer only
    if not check_separation:
        return landmarks[0]
    seen = math.hypot(percept.x_m - post.x_m, percept.y_m - post.y_m)

    def mismatch(landmark: Landmark) -> float:
        return abs(math.hypot(landmark.x - post_landmark.x, landmark.y - post_landmark.y) - seen)

    best = min(landmarks, key=mismatch)
    rivals = [lm for lm in field.landmarks if lm.kind is percept.kind and lm not in landmarks]
    if mismatch(best) > _separation_gate_m(percept, post) or any(mismatch(lm) < mismatch(best) for lm in rivals):
        return None
    return best


def disambiguate(
    percepts: Sequence[LandmarkPercept],
    field: FieldGeometry = FIELD,
    max_angle_rad: float = CORNER_POST_MAX_ANGLE_RAD,
    check_separation: bool = True,
) -> tuple[LandmarkObservation, ...]:
    """Observations of known landmarks from a scan's percepts (thesis 5.2), in percept order.

    Percepts that cannot be placed (posts of unknown side, corners and junctions without a
    post near enough) are left out.
    """
    unique = [(p, unique_landmark(p, field)) for p in percepts]
    posts = [(p, lm) for p, lm in unique if lm is not None and lm.kind is LandmarkKind.GOAL_POST]
    found: list[LandmarkObservation] = []
    for percept, landmark in unique:
        if landmark is None and percept.kind in (LandmarkKind.L_CORNER, LandmarkKind.T_JUNCTION):
            landmark = resolve(percept, posts, field, max_angle_rad, check_separation)
            if landmark is None:
                LOG.debug("could not place %s percept at bearing %.3f rad", percept.kind.value, percept.bearing_rad)
        if landmark is not None:
            found.append(observe(percept, landmark))
    return tuple(found)
