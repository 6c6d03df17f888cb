"""Kicking past a robot in the way: the open direction nearest the goal, inside the field, never back."""

from __future__ import annotations

import math

import pytest

from agents.behavior.skills import KICK_ROLL_M, SIDELINE_MARGIN_M
from agents.behavior.tactics.kick_past import (
    AWAY_FROM_OWN_GOAL_RAD,
    PAST_MARGIN_RAD,
    PAST_SPAN_RAD,
    PAST_TOLERANCE_RAD,
    PAST_WITHIN_M,
    kick_past,
)
from agents.behavior.tactics.shot_window import BLOCKER_RADIUS_M, ShotWindowError
from world.field import FIELD


def _clearance(ball: tuple[float, float], direction: float, point: tuple[float, float]) -> float:
    """How far ``point`` lies from the ray out of ``ball`` along ``direction`` (m; inf behind the ball)."""
    dx, dy = point[0] - ball[0], point[1] - ball[1]
    if math.cos(direction) * dx + math.sin(direction) * dy <= 0.0:
        return math.inf
    return abs(-math.sin(direction) * dx + math.cos(direction) * dy)


def _toward_goal(ball: tuple[float, float], goal_x: float) -> float:
    return math.atan2(-ball[1], goal_x - ball[0])


@pytest.mark.parametrize("goal_x", [FIELD.half_length, -FIELD.half_length])
def test_nothing_changes_while_the_way_at_the_goal_is_open(goal_x: float) -> None:
    attack = math.copysign(1.0, goal_x)
    ball = (-attack * 1.0, 0.3)
    assert kick_past(ball, goal_x) is None
    beside = (ball[0] + attack * 0.5, ball[1] + 0.45)  # near, but well off the line to the goal
    behind = (ball[0] - attack * 0.5, ball[1])
    far = (ball[0] + attack * (PAST_WITHIN_M + 0.3), ball[1] - 0.3 * (PAST_WITHIN_M + 0.3) / (goal_x - ball[0]))
    assert kick_past(ball, goal_x, [beside, behind, far]) is None


@pytest.mark.parametrize("goal_x", [FIELD.half_length, -FIELD.half_length])
@pytest.mark.parametrize("offset_m", [-0.08, 0.0, 0.08])
def test_a_robot_in_the_way_is_passed_on_the_nearer_side_with_a_margin(goal_x: float, offset_m: float) -> None:
    attack = math.copysign(1.0, goal_x)
    ball = (-attack * 1.0, 0.0)
    robot = (ball[0] + attack * 0.5, offset_m)
    past = kick_past(ball, goal_x, [robot])
    assert past is not None
    half = math.asin(BLOCKER_RADIUS_M / 0.5)
    margin = min(PAST_MARGIN_RAD, past.half_width_rad)  # a gap narrower than two margins: its middle
    assert margin > 0.0
    assert _clearance(ball, past.direction_rad, robot) >= 0.5 * math.sin(half + margin - 1e-6)
    turn = math.remainder(past.direction_rad - _toward_goal(ball, goal_x), math.tau)
    if offset_m != 0.0:  # the robot stands to one side of the line: the kick passes it on the other
        assert turn * attack * offset_m < 0.0
    assert abs(turn) <= half + abs(math.atan2(offset_m, 0.5)) + PAST_MARGIN_RAD + 1e-6
    assert past.tolerance_rad == pytest.approx(PAST_TOLERANCE_RAD)
    assert past.allows(past.direction_rad) and not past.allows(past.direction_rad + 2 * PAST_TOLERANCE_RAD)
    aim_dx, aim_dy = past.aim_xy[0] - ball[0], past.aim_xy[1] - ball[1]
    assert math.atan2(aim_dy, aim_dx) == pytest.approx(past.direction_rad)


def test_a_robot_at_the_ball_or_a_wall_of_robots_leaves_the_kick_at_the_goal() -> None:
    goal_x, ball = FIELD.half_length, (0.0, 0.0)
    assert kick_past(ball, goal_x, [(BLOCKER_RADIUS_M * 0.9, 0.0)]) is None
    wall = [(0.35, y) for y in (-0.6, -0.3, 0.0, 0.3, 0.6)]
    assert kick_past(ball, goal_x, wall) is None


def test_near_a_side_line_the_kick_goes_past_on_the_field_side_and_stays_in() -> None:
    goal_x = FIELD.half_length
    ball = (0.0, FIELD.half_width - 0.4)
    robot = (0.45, ball[1] - 0.1)  # a little toward the middle: the outer side would be the nearer way
    past = kick_past(ball, goal_x, [robot])
    assert past is not None
    roll_y = ball[1] + KICK_ROLL_M * math.sin(past.direction_rad)
    assert roll_y <= FIELD.half_width - SIDELINE_MARGIN_M + 1e-9
    assert _clearance(ball, past.direction_rad, robot) > BLOCKER_RADIUS_M


def test_the_kick_never_turns_back_toward_the_own_goal_nor_beyond_the_span() -> None:
    goal_x = FIELD.half_length
    ball = (0.0, -0.5)
    for robot in [(0.4, -0.5), (0.3, -0.2), (0.3, -0.8), (0.25, -0.35)]:
        past = kick_past(ball, goal_x, [robot])
        if past is None:
            continue
        assert abs(past.direction_rad) <= AWAY_FROM_OWN_GOAL_RAD + 1e-9
        turn = math.remainder(past.direction_rad - _toward_goal(ball, goal_x), math.tau)
        assert abs(turn) <= PAST_SPAN_RAD + 1e-9


def test_the_side_passed_last_is_kept_while_it_is_open() -> None:
    goal_x, ball = FIELD.half_length, (0.0, 0.0)
    robot = (0.5, 0.03)  # a little left: the right is the nearer way past
    fresh = kick_past(ball, goal_x, [robot])
    assert fresh is not None and fresh.direction_rad < 0.0
    kept = kick_past(ball, goal_x, [robot], previous_direction_rad=math.radians(35.0))
    assert kept is not None and kept.direction_rad > 0.0
    assert _clearance(ball, kept.direction_rad, robot) > BLOCKER_RADIUS_M


@pytest.mark.parametrize(
    "args",
    [((math.nan, 0.0), 3.0, []), ((0.0, 0.0), 0.0, []), ((0.0, 0.0), 3.0, [(1.0,)]), ((0.0, 0.0), math.inf, [])],
)
def test_bad_input_is_refused_by_name(args: tuple) -> None:
    with pytest.raises(ShotWindowError):
        kick_past(*args)
