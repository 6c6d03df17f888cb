"""A ball at the own goal line beside the goal: cleared along the line toward the side line.

A ball within ``clear_line.depth_m`` of the own goal line, beside the goal (farther from the goal's
axis than the posts by ``clear_line.beside_post_m``: nearer them it is held off,
:mod:`agents.behavior.tactics.goal_line`) and within ``clear_line.outer_y_m`` of the field's long
axis, has no spot behind it on the way to the opponent goal but beyond the end line: a robot that
walks round it there, or pushes it from the field, plays it along the line into the goal mouth. It is
played away from the goal instead: the striker (or the goalkeeper clearing it) comes between the ball
and the goal, faces the side line, turned ``clear_line.turn_deg`` from the goal line into the field,
and pushes the ball that way, with the striker's own cards (:class:`~..striker.open_play.GoBehind`,
:class:`~..striker.open_play.Chase`) on a clearing aim that is pushed, never kicked. On with
``clear_line.enabled = true``; shipped off, since it is not shown to let in fewer goals than the
clearing out to the side of :mod:`agents.behavior.tactics.aim` that it replaces
(``robotstadium drill goal-line`` plays the two against the same attacks).

Computed in the frame where the own goal is at x = -3 (``attack`` = +1 when the robot defends the blue
goal, -1 otherwise) and mirrored; field frame, m and rad.
"""

from __future__ import annotations

import dataclasses
import math

from agents.behavior.tactics.aim import AIM_DISTANCE_M, Aim
from agents.team.behavior.geometry import heading_error
from agents.team.behavior.requests import MotionRequest
from agents.team.behavior.set_plays.throw_in import ThrowInTouch
from agents.team.behavior.striker.context import StrikeContext
from agents.team.behavior.striker.open_play import Chase, GoBehind
from agents.team.params import ClearLineParams, TeamParams
from world.field import FIELD


def line_clearing(ball_xy: tuple[float, float], attack: float, p: ClearLineParams) -> Aim | None:
    """The aim that clears a ball at ``ball_xy`` along the own goal line toward the nearer side line
    (pushed), or None when the ball does not lie beside the own goal at its line."""
    bx, by = ball_xy
    depth = attack * bx + FIELD.half_length  # from the own goal line into the field
    if not (depth < p.depth_m and FIELD.goal_post_y + p.beside_post_m <= abs(by) <= p.outer_y_m):
        return None
    side = math.copysign(1.0, by)
    return Aim(bx + attack * AIM_DISTANCE_M * math.sin(p.turn_rad), by + side * AIM_DISTANCE_M * math.cos(p.turn_rad),
               clearing=True, push=True)


class ClearLine:
    """The card: for its own ball in that place, the striker's way behind the ball and its push, on the
    clearing's aim."""

    def __init__(self, params: TeamParams, touch: ThrowInTouch):
        self.params = params
        self.go_behind = GoBehind(params)
        self.chase = Chase(params, touch)

    def play(self, c: StrikeContext) -> MotionRequest | None:
        p = self.params.clear_line
        if not p.enabled or c.ball_rel is None or c.quick:
            return None
        aim = line_clearing(c.ball_xy, c.attack, p)
        if aim is None:
            return None
        clearing = dataclasses.replace(c, aim=aim, goal_aim=aim, shot=None, goal_line=False,
                                       heading_error=heading_error(c.pose, c.ball_xy, aim.xy))
        return self.go_behind.play(clearing) or self.chase.play(clearing)
