"""The shot window: the widest part of the goal mouth no robot covers, seen from the ball."""

from __future__ import annotations

import math

import pytest

from agents.behavior.tactics.shot_window import (
    BLOCKER_RADIUS_M,
    KEEP_SHARE,
    MIN_TOLERANCE_RAD,
    POST_MARGIN_M,
    TOLERANCE_SHARE,
    ShotWindowError,
    shot_window,
)
from world.field import FIELD

MOUTH_Y = FIELD.goal_inner_width / 2 - POST_MARGIN_M


def _y_at_line(ball: tuple[float, float], direction: float, goal_x: float) -> float:
    return ball[1] + math.tan(direction) * (goal_x - ball[0])


def _passes_clear_of(ball: tuple[float, float], direction: float, point: tuple[float, float]) -> float:
    """The distance of ``point`` from the ray out of ``ball`` along ``direction`` (m)."""
    dx, dy = point[0] - ball[0], point[1] - ball[1]
    return abs(-math.sin(direction) * dx + math.cos(direction) * dy)


@pytest.mark.parametrize("goal_x", [FIELD.half_length, -FIELD.half_length])
def test_an_open_goal_is_aimed_at_its_centre_with_half_its_half_width_to_spare(goal_x: float) -> None:
    ball = (goal_x * (1 / 3), 0.0)  # 2 m out, on the axis
    window = shot_window(ball, goal_x)
    assert not window.covered
    assert window.aim_xy == pytest.approx((goal_x, 0.0), abs=1e-9)
    assert window.half_width_rad == pytest.approx(math.atan2(MOUTH_Y, 2.0))
    assert window.tolerance_rad == pytest.approx(TOLERANCE_SHARE * window.half_width_rad)
    assert window.allows(window.direction_rad + 0.9 * window.tolerance_rad)
    assert not window.allows(window.direction_rad + 1.1 * window.tolerance_rad)


@pytest.mark.parametrize("goal_x", [FIELD.half_length, -FIELD.half_length])
def test_a_goalkeeper_in_the_middle_leaves_a_side_and_the_aim_passes_it_by_its_width(goal_x: float) -> None:
    ball = (goal_x * 0.6, 0.1)
    keeper = (goal_x * 0.95, 0.0)
    window = shot_window(ball, goal_x, [keeper])
    assert abs(_y_at_line(ball, window.direction_rad, goal_x)) < MOUTH_Y
    assert _passes_clear_of(ball, window.direction_rad, keeper) > BLOCKER_RADIUS_M
    for edge in (-1.0, 1.0):  # the whole tolerance passes the keeper too
        assert _passes_clear_of(ball, window.direction_rad + edge * window.tolerance_rad, keeper) > BLOCKER_RADIUS_M


def test_a_goalkeeper_off_to_one_side_leaves_the_other_side_to_aim_at() -> None:
    goal_x = FIELD.half_length
    window = shot_window((1.0, 0.0), goal_x, [(2.85, 0.3)])
    assert _y_at_line((1.0, 0.0), window.direction_rad, goal_x) < -0.1
    window = shot_window((1.0, 0.0), goal_x, [(2.85, -0.3)])
    assert _y_at_line((1.0, 0.0), window.direction_rad, goal_x) > 0.1


def test_the_side_aimed_at_last_is_kept_while_it_is_open_and_wide_enough() -> None:
    goal_x, ball = FIELD.half_length, (1.0, 0.0)
    keeper = (2.85, 0.03)  # a little left of the middle: the right side is the wider one
    fresh = shot_window(ball, goal_x, [keeper])
    assert _y_at_line(ball, fresh.direction_rad, goal_x) < 0.0
    left = shot_window(ball, goal_x, [keeper], previous_direction_rad=math.atan2(0.45, 2.0))
    assert _y_at_line(ball, left.direction_rad, goal_x) > 0.0  # kept: nearly as wide
    assert left.half_width_rad >= KEEP_SHARE * fresh.half_width_rad
    far_off = (2.85, 0.3)  # the left side nearly closed: the aim goes right
    switched = shot_window(ball, goal_x, [far_off], previous_direction_rad=math.atan2(0.6, 2.0))
    assert _y_at_line(ball, switched.direction_rad, goal_x) < 0.0


def test_robots_behind_the_ball_or_well_behind_the_goal_line_do_not_cover_it() -> None:
    goal_x, ball = FIELD.half_length, (1.0, 0.0)
    open_goal = shot_window(ball, goal_x)
    assert shot_window(ball, goal_x, [(0.7, 0.0), (goal_x + 0.5, 0.0), (1.5, 1.5)]) == open_goal


def test_a_mouth_covered_all_over_leaves_all_of_it_and_says_so() -> None:
    window = shot_window((1.0, 0.0), FIELD.half_length, [(1.3, 0.0)])  # a robot right in front of the ball
    assert window.covered
    assert window.aim_xy == pytest.approx((FIELD.half_length, 0.0), abs=1e-9)


def test_a_tight_angle_keeps_the_least_tolerance() -> None:
    window = shot_window((2.8, -1.9), FIELD.half_length)
    assert window.tolerance_rad == MIN_TOLERANCE_RAD


@pytest.mark.parametrize("ball, goal_x, blockers", [
    ((math.nan, 0.0), 3.0, ()),
    ((1.0,), 3.0, ()),
    ("ab", 3.0, ()),
    ((3.0, 0.0), 3.0, ()),  # on the goal line
    ((-2.99, 0.0), -3.0, ()),
    ((1.0, 0.0), math.inf, ()),
    ((1.0, 0.0), 0.0, ()),
    ((1.0, 0.0), 3.0, [(2.0, math.nan)]),
    ((1.0, 0.0), 3.0, [None]),
])
def test_bad_input_is_refused_by_name(ball, goal_x, blockers) -> None:
    with pytest.raises(ShotWindowError, match="ball_xy|goal_x|blocker"):
        shot_window(ball, goal_x, blockers)
