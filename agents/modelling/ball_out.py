"""Where a ball that is going out will come back: the point where it leaves the field and
the throw-in rule's spot for it.

A ball believed beyond a side or end line (by :data:`OUT_MARGIN_M`) left the field there. A
ball still inside that rolls fast enough (:data:`ANTICIPATE_MIN_SPEED_MPS`) and whose roll
ends beyond a line (by :data:`ANTICIPATE_BEYOND_M`) will leave it where its path crosses the
line: it rolls on ``velocity * ROLL_DECAY_S`` to rest, the ball model's decay
(:mod:`agents.modelling.ball_model`). A ball that crosses an end line between the posts is a
goal, not out. All in the field frame (m, m/s).

The spot (:func:`expected_spot`) is the rule's (:func:`match.protocol.throw_in_spot`) for the
team the robot believes touched the ball last: its own if it or a teammate kicked it within
the roll's time (:data:`OWN_TOUCH_MEMORY_S`), else the other one. When both teams guess so, a
kick's throw-in is foreseen alike by both; a deflection is guessed as the other team's by
each, so one of the two guesses is right.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from agents.modelling.ball_model import ROLL_DECAY_S, BallEstimate
from match.protocol import GoalColor, throw_in_spot
from world.field import FIELD, FieldGeometry

OUT_MARGIN_M = 0.1  # a ball believed this far beyond a line is out
ANTICIPATE_MIN_SPEED_MPS = 0.3  # slower balls are dribbled or about to stop: not foreseen out (a push is 0.2 m/s)
ANTICIPATE_BEYOND_M = 0.2  # ... and a roll must end this far beyond a line to be foreseen out
ANTICIPATE_MAX_SIGMA_M = 0.5  # ... by a belief this sure at least
OWN_TOUCH_MEMORY_S = 4.0  # a kick by the own team this recent put the ball out (a kicked ball rolls 1-3 s)


@dataclass(frozen=True)
class BallOut:
    """Where the ball leaves (or left) the field, on the line it crosses (field frame, m)."""

    x: float
    y: float
    over_end_line: bool


def out_of_field(ball_xy: tuple[float, float], field: FieldGeometry = FIELD) -> bool:
    """Whether a ball believed at ``ball_xy`` (field frame) is over a side or end line (by :data:`OUT_MARGIN_M`)."""
    return abs(ball_xy[0]) > field.half_length + OUT_MARGIN_M or abs(ball_xy[1]) > field.half_width + OUT_MARGIN_M


def leaving_point(ball: BallEstimate, field: FieldGeometry = FIELD) -> BallOut | None:
    """Where ``ball`` (field frame, with its velocity) leaves or left the field; None when it stays
    in, goes into a goal, or its belief is too unsure to foresee (module docstring)."""
    if out_of_field((ball.x, ball.y), field):
        over_end = abs(ball.x) - field.half_length > abs(ball.y) - field.half_width
        x = min(max(ball.x, -field.half_length), field.half_length)
        y = min(max(ball.y, -field.half_width), field.half_width)
        return None if over_end and abs(y) < field.goal_post_y else BallOut(x, y, over_end)
    if ball.sigma_m > ANTICIPATE_MAX_SIGMA_M or ball.vx**2 + ball.vy**2 < ANTICIPATE_MIN_SPEED_MPS**2:
        return None
    rest_x, rest_y = ball.x + ball.vx * ROLL_DECAY_S, ball.y + ball.vy * ROLL_DECAY_S
    over_side = abs(rest_y) > field.half_width + ANTICIPATE_BEYOND_M
    over_end = abs(rest_x) > field.half_length + ANTICIPATE_BEYOND_M
    if not (over_side or over_end):
        return None
    # the fraction of the way to rest at which the path crosses each line it goes over
    to_side = (math.copysign(field.half_width, rest_y) - ball.y) / (rest_y - ball.y) if over_side else math.inf
    to_end = (math.copysign(field.half_length, rest_x) - ball.x) / (rest_x - ball.x) if over_end else math.inf
    fraction = max(min(to_side, to_end), 0.0)
    x, y = ball.x + fraction * (rest_x - ball.x), ball.y + fraction * (rest_y - ball.y)
    over_end_line = to_end < to_side
    if over_end_line and abs(y) < field.goal_post_y:
        return None
    return BallOut(min(max(x, -field.half_length), field.half_length),
                   min(max(y, -field.half_width), field.half_width), over_end_line)


def expected_spot(out: BallOut, own_touched: bool, defended: GoalColor) -> tuple[float, float]:
    """Where the referee will put the ball that leaves at ``out`` (field frame, m), if the own team
    (defending ``defended``) touched it last (``own_touched``) or the other team did."""
    toucher_defends = defended if own_touched else defended.other
    return throw_in_spot(out.x, out.y, out.over_end_line, toucher_defends)
