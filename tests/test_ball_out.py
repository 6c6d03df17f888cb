"""Foreseeing where a ball going out comes back (agents.modelling.ball_out)."""

from __future__ import annotations

import pytest

from agents.modelling.ball_model import ROLL_DECAY_S, BallEstimate
from agents.modelling.ball_out import (
    ANTICIPATE_MIN_SPEED_MPS,
    BallOut,
    expected_spot,
    leaving_point,
    out_of_field,
)
from match.protocol import THROW_IN_INSET_M, GoalColor, throw_in_spot
from world.field import FIELD

HW, HL = FIELD.half_width, FIELD.half_length


def ball(x: float, y: float, vx: float = 0.0, vy: float = 0.0, sigma: float = 0.05) -> BallEstimate:
    return BallEstimate(x, y, vx, vy, sigma, 0.0)


def test_a_ball_rolling_over_a_side_line_leaves_where_its_path_crosses_it() -> None:
    # rests 0.5 m beyond the side line: from (0, 1.5) at (0.5, 0.5) m/s, the path crosses y = 2 half way
    rolling = ball(0.0, HW - 0.5, 0.5 / ROLL_DECAY_S * 2, 0.5 / ROLL_DECAY_S * 2)
    out = leaving_point(rolling)
    assert out == BallOut(pytest.approx(0.5), pytest.approx(HW), False)


def test_a_ball_whose_roll_ends_inside_or_that_rolls_slowly_is_not_foreseen_out() -> None:
    assert leaving_point(ball(0.0, HW - 0.5, 0.0, 0.2)) is None  # rests 0.1 m inside
    assert leaving_point(ball(0.0, HW - 0.1, 0.0, 0.1)) is None  # rests beyond, but slower than a kick
    assert leaving_point(ball(0.0, HW - 0.1, 0.0, ANTICIPATE_MIN_SPEED_MPS * 1.01)) is not None
    assert leaving_point(ball(0.0, HW - 0.5, 0.0, 1.0, sigma=0.8)) is None  # too unsure
    assert leaving_point(ball(1.0, -HW + 0.5, 0.0, 1.0)) is None  # rolling away from the line it is near


def test_a_ball_into_the_goal_is_not_out_and_one_beside_it_is() -> None:
    assert leaving_point(ball(HL - 0.5, 0.0, 1.0, 0.0)) is None
    assert leaving_point(ball(HL + 0.2, 0.1)) is None  # in the goal already
    beside = leaving_point(ball(HL - 0.5, 1.2, 1.0, 0.0))
    assert beside == BallOut(pytest.approx(HL), pytest.approx(1.2), True)
    assert leaving_point(ball(-HL - 0.2, -1.5)) == BallOut(-HL, -1.5, True)


def test_a_ball_believed_out_left_the_field_on_the_line_nearest_it() -> None:
    assert out_of_field((0.3, HW + 0.11)) and not out_of_field((0.3, HW + 0.09))
    assert leaving_point(ball(0.3, HW + 0.3)) == BallOut(0.3, HW, False)
    assert leaving_point(ball(HL + 0.05, -HW - 0.4)) == BallOut(HL, -HW, False)  # nearer the side line


@pytest.mark.parametrize("defended", [GoalColor.BLUE, GoalColor.YELLOW])
def test_the_spot_is_the_rule_s_for_the_team_guessed_to_have_touched_last(defended: GoalColor) -> None:
    side_out = BallOut(0.5, HW, False)
    line_y = HW - THROW_IN_INSET_M
    own = expected_spot(side_out, True, defended)
    other = expected_spot(side_out, False, defended)
    assert own == throw_in_spot(0.5, HW, False, defended)
    assert own == pytest.approx((0.5 + defended.sign * 1.0, line_y))  # 1 m toward the own goal
    assert other == pytest.approx((0.5 - defended.sign * 1.0, line_y))
    end_out = BallOut(defended.sign * HL, -1.5, True)  # over the own end line
    assert expected_spot(end_out, True, defended) == throw_in_spot(end_out.x, end_out.y, True, defended)
    assert expected_spot(end_out, False, defended) == pytest.approx((0.0, -line_y))
