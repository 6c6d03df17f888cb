"""Field geometry and the 17 landmarks against the facts of docs/design/world.md section 4."""

from __future__ import annotations

import math
from collections import Counter

import pytest
from hypothesis import given
from hypothesis import strategies as st

from world.field import (
    FIELD,
    FieldGeometry,
    GoalColor,
    Landmark,
    LandmarkId,
    LandmarkKind,
    LineSegment,
    normalize_angle,
)

TOL = 1e-9

# (x, y) of each landmark in metres, field frame (docs/design/index.md section 3 and docs/design/world.md).
EXPECTED_POSITIONS: dict[LandmarkId, tuple[float, float]] = {
    LandmarkId.BLUE_GOAL_LEFT_POST: (-3.0, -0.75),
    LandmarkId.BLUE_GOAL_RIGHT_POST: (-3.0, 0.75),
    LandmarkId.YELLOW_GOAL_LEFT_POST: (3.0, 0.75),
    LandmarkId.YELLOW_GOAL_RIGHT_POST: (3.0, -0.75),
    LandmarkId.BLUE_GOAL_CENTER: (-3.0, 0.0),
    LandmarkId.YELLOW_GOAL_CENTER: (3.0, 0.0),
    LandmarkId.CENTER_CIRCLE: (0.0, 0.0),
    LandmarkId.FIELD_CORNER_BLUE_LEFT: (-3.0, -2.0),
    LandmarkId.FIELD_CORNER_BLUE_RIGHT: (-3.0, 2.0),
    LandmarkId.FIELD_CORNER_YELLOW_LEFT: (3.0, 2.0),
    LandmarkId.FIELD_CORNER_YELLOW_RIGHT: (3.0, -2.0),
    LandmarkId.GOAL_AREA_CORNER_BLUE_LEFT: (-2.4, -1.1),
    LandmarkId.GOAL_AREA_CORNER_BLUE_RIGHT: (-2.4, 1.1),
    LandmarkId.GOAL_AREA_CORNER_YELLOW_LEFT: (2.4, 1.1),
    LandmarkId.GOAL_AREA_CORNER_YELLOW_RIGHT: (2.4, -1.1),
    LandmarkId.T_JUNCTION_LEFT: (0.0, 2.0),
    LandmarkId.T_JUNCTION_RIGHT: (0.0, -2.0),
}


def _close(a: float, b: float) -> bool:
    return math.isclose(a, b, abs_tol=TOL)


def _same_point(p: tuple[float, float], q: tuple[float, float]) -> bool:
    return _close(p[0], q[0]) and _close(p[1], q[1])


def _endpoints(segment: LineSegment) -> tuple[tuple[float, float], tuple[float, float]]:
    return (segment.x0, segment.y0), (segment.x1, segment.y1)


def _inside_segment(point: tuple[float, float], segment: LineSegment) -> bool:
    """Whether ``point`` lies on ``segment`` strictly between its endpoints."""
    (x0, y0), (x1, y1) = _endpoints(segment)
    px, py = point
    cross = (x1 - x0) * (py - y0) - (y1 - y0) * (px - x0)
    t = ((px - x0) * (x1 - x0) + (py - y0) * (y1 - y0)) / segment.length**2
    return _close(cross, 0.0) and TOL < t < 1.0 - TOL


def _mirrored_id(landmark: Landmark) -> LandmarkId:
    """Id of the landmark at the place ``landmark`` goes to when the field turns 180 degrees."""
    name = landmark.id.name
    if landmark.kind is LandmarkKind.T_JUNCTION:
        swapped = {"LEFT": "RIGHT", "RIGHT": "LEFT"}
        return LandmarkId["_".join(swapped.get(part, part) for part in name.split("_"))]
    swapped = {"BLUE": "YELLOW", "YELLOW": "BLUE"}
    return LandmarkId["_".join(swapped.get(part, part) for part in name.split("_"))]


# --- landmarks ----------------------------------------------------------------------------


@pytest.mark.parametrize("landmark_id", list(LandmarkId), ids=lambda i: i.name)
def test_landmark_position(landmark_id: LandmarkId) -> None:
    landmark = FIELD.landmark(landmark_id)
    assert landmark.id is landmark_id
    assert (landmark.x, landmark.y) == pytest.approx(EXPECTED_POSITIONS[landmark_id], abs=TOL)


def test_seventeen_unique_landmarks() -> None:
    ids = [landmark.id for landmark in FIELD.landmarks]
    assert len(ids) == 17
    assert set(ids) == set(LandmarkId)


def test_landmark_kind_counts() -> None:
    counts = Counter(landmark.kind for landmark in FIELD.landmarks)
    assert counts == {
        LandmarkKind.GOAL_POST: 4,
        LandmarkKind.GOAL_CENTER: 2,
        LandmarkKind.CENTER_CIRCLE: 1,
        LandmarkKind.L_CORNER: 8,
        LandmarkKind.T_JUNCTION: 2,
    }


def test_landmark_goal_colour_matches_side() -> None:
    for landmark in FIELD.landmarks:
        if landmark.goal is None:
            assert landmark.kind in (LandmarkKind.CENTER_CIRCLE, LandmarkKind.T_JUNCTION)
            assert _close(landmark.x, 0.0)
        else:
            assert landmark.goal.name in landmark.id.name
            assert math.copysign(1.0, landmark.x) == landmark.goal.sign


def test_left_post_is_on_the_left_facing_the_goal() -> None:
    for color in GoalColor:
        left = FIELD.landmark(LandmarkId[f"{color.name}_GOAL_LEFT_POST"])
        right = FIELD.landmark(LandmarkId[f"{color.name}_GOAL_RIGHT_POST"])
        # Facing the goal is facing (sign, 0); the left of that is (0, sign).
        assert color.sign * (left.y - right.y) > 0.0


@pytest.mark.parametrize(
    "field",
    [FIELD, FieldGeometry(length=9.0, width=6.0, goal_area_depth=1.0, goal_inner_width=1.5)],
    ids=["default", "larger"],
)
def test_landmarks_mirror_onto_themselves(field: FieldGeometry) -> None:
    """A 180 degree turn about the centre spot swaps goal colours and keeps left/right of goals."""
    for landmark in field.landmarks:
        image = field.landmark(_mirrored_id(landmark))
        assert image.kind is landmark.kind
        assert image.goal is (None if landmark.goal is None else landmark.goal.other)
        assert _same_point((image.x, image.y), (-landmark.x, -landmark.y))


# --- lines --------------------------------------------------------------------------------


def test_line_segments_lie_inside_the_field() -> None:
    for segment in FIELD.line_segments:
        assert segment.length > 0.0
        for x, y in _endpoints(segment):
            assert abs(x) <= FIELD.half_length + TOL
            assert abs(y) <= FIELD.half_width + TOL
            assert FIELD.is_on_carpet(x, y)


def test_l_corners_are_where_two_lines_end() -> None:
    for landmark in FIELD.landmarks:
        if landmark.kind is not LandmarkKind.L_CORNER:
            continue
        point = (landmark.x, landmark.y)
        ending = [s for s in FIELD.line_segments if any(_same_point(point, e) for e in _endpoints(s))]
        assert len(ending) == 2, landmark.id
        (a0, a1), (b0, b1) = (_endpoints(s) for s in ending)
        dot = (a1[0] - a0[0]) * (b1[0] - b0[0]) + (a1[1] - a0[1]) * (b1[1] - b0[1])
        assert _close(dot, 0.0), f"{landmark.id}: lines not perpendicular"


def test_t_junctions_are_where_the_middle_line_meets_a_side_line() -> None:
    for landmark_id in (LandmarkId.T_JUNCTION_LEFT, LandmarkId.T_JUNCTION_RIGHT):
        landmark = FIELD.landmark(landmark_id)
        point = (landmark.x, landmark.y)
        ending = [s for s in FIELD.line_segments if any(_same_point(point, e) for e in _endpoints(s))]
        passing = [s for s in FIELD.line_segments if _inside_segment(point, s)]
        assert len(ending) == 1 and _close(ending[0].x0, 0.0) and _close(ending[0].x1, 0.0)
        assert len(passing) == 1 and _close(passing[0].y0, landmark.y) and _close(passing[0].y1, landmark.y)


def test_goal_area_lines_end_at_goal_area_corners_or_goal_line() -> None:
    corners = [
        (lm.x, lm.y)
        for lm in FIELD.landmarks
        if lm.id.name.startswith("GOAL_AREA_CORNER")
    ]
    goal_area_segments = [
        s
        for s in FIELD.line_segments
        if any(_same_point(e, c) for e in _endpoints(s) for c in corners)
    ]
    assert len(goal_area_segments) == 6  # a front line and two side lines per goal
    for segment in goal_area_segments:
        for x, y in _endpoints(segment):
            at_corner = any(_same_point((x, y), c) for c in corners)
            on_goal_line = _close(abs(x), FIELD.half_length) and _close(abs(y), FIELD.goal_area_half_width)
            assert at_corner or on_goal_line, (x, y)


def test_penalty_marks_and_circle() -> None:
    assert FIELD.penalty_marks == ((-1.2, 0.0), (1.2, 0.0))
    assert (FIELD.center_circle.cx, FIELD.center_circle.cy, FIELD.center_circle.radius) == (0.0, 0.0, 0.6)


# --- derived geometry ---------------------------------------------------------------------


def test_default_derived_dimensions() -> None:
    assert FIELD.goal_post_y == pytest.approx(0.75)
    assert FIELD.goal_post_radius == pytest.approx(0.05)
    assert FIELD.goal_area_x == pytest.approx(2.4)
    assert FIELD.goal_area_half_width == pytest.approx(1.1)
    assert 2 * FIELD.carpet_half_length == pytest.approx(7.4)
    assert 2 * FIELD.carpet_half_width == pytest.approx(5.4)
    assert FIELD.goal_line_x(GoalColor.BLUE) == -3.0
    assert FIELD.goal_line_x(GoalColor.YELLOW) == 3.0


def test_carpet_bounds() -> None:
    assert FIELD.is_on_carpet(3.7, -2.7)
    assert not FIELD.is_on_carpet(3.71, 0.0)
    assert not FIELD.is_on_carpet(0.0, -2.71)


def test_other_dimensions_derive_consistently() -> None:
    field = FieldGeometry(length=9.0, width=6.0)
    post = field.landmark(LandmarkId.YELLOW_GOAL_LEFT_POST)
    assert (post.x, post.y) == pytest.approx((4.5, 0.75))
    assert field.landmark(LandmarkId.BLUE_GOAL_CENTER).x == pytest.approx(-4.5)
    corner = field.landmark(LandmarkId.FIELD_CORNER_YELLOW_LEFT)
    assert (corner.x, corner.y) == pytest.approx((4.5, 3.0))
    area = field.landmark(LandmarkId.GOAL_AREA_CORNER_BLUE_LEFT)
    assert (area.x, area.y) == pytest.approx((-3.9, -1.1))
    assert field.landmark(LandmarkId.T_JUNCTION_LEFT).y == pytest.approx(3.0)
    assert 2 * field.carpet_half_length == pytest.approx(10.4)
    # The default field is untouched by building another.
    assert FIELD.landmark(LandmarkId.YELLOW_GOAL_LEFT_POST).x == 3.0


@given(
    length=st.floats(min_value=3.0, max_value=20.0),
    width=st.floats(min_value=2.5, max_value=15.0),
)
def test_any_field_has_its_landmarks_on_its_lines(length: float, width: float) -> None:
    field = FieldGeometry(length=length, width=width)
    hl, hw = length / 2.0, width / 2.0
    for landmark in field.landmarks:
        assert abs(landmark.x) <= hl + TOL and abs(landmark.y) <= hw + TOL
        if landmark.kind in (LandmarkKind.GOAL_POST, LandmarkKind.GOAL_CENTER):
            assert math.isclose(abs(landmark.x), hl)
        if landmark.id.name.startswith("FIELD_CORNER"):
            assert math.isclose(abs(landmark.x), hl) and math.isclose(abs(landmark.y), hw)


# --- angles -------------------------------------------------------------------------------

angles = st.floats(min_value=-1e6, max_value=1e6, allow_nan=False, allow_infinity=False)


@given(angles)
def test_normalize_angle_range(angle: float) -> None:
    assert -math.pi < normalize_angle(angle) <= math.pi


@given(angles)
def test_normalize_angle_keeps_the_direction(angle: float) -> None:
    difference = normalize_angle(angle) - angle
    assert math.remainder(difference, 2.0 * math.pi) == pytest.approx(0.0, abs=1e-8)


@given(angles)
def test_normalize_angle_is_idempotent(angle: float) -> None:
    once = normalize_angle(angle)
    assert normalize_angle(once) == once


@given(st.floats(min_value=-math.pi, max_value=math.pi, exclude_min=True))
def test_normalize_angle_leaves_normal_angles_alone(angle: float) -> None:
    assert normalize_angle(angle) == angle


@pytest.mark.parametrize(
    ("angle", "expected"),
    [
        (math.pi, math.pi),
        (-math.pi, math.pi),
        (0.0, 0.0),
        (2.0 * math.pi, 0.0),
        (-2.0 * math.pi, 0.0),
        (1.5 * math.pi, -0.5 * math.pi),
        (-1.5 * math.pi, 0.5 * math.pi),
    ],
)
def test_normalize_angle_examples(angle: float, expected: float) -> None:
    assert normalize_angle(angle) == pytest.approx(expected, abs=1e-12)
