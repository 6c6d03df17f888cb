"""A throw-in's first touch from the field side of the ball: a side-step along the line.

A striker on the field side of the ball that comes at it about square to the side line or faces the
line (``side_tap.approach_deg``) stands facing the line with the ball beside a foot and side-steps into
it, tapping it along the line: toward the opponent goal in its own half, or back from past the ball when
the ball lies ``side_tap.back_tap_clear_m`` or more from the own goal line; in the opponent half away
from the robot's side. Walking round the ball to play it along the line took seconds. Not when the
robot comes at the ball otherwise, or stands past it the way the tap goes (``side_tap.beyond_m``).
Chosen once per throw-in, the way included, from the ball's sighting and the robot's heading: a jump of
the position estimate that carries the ball over the centre line must not turn the tap round.
"""

from __future__ import annotations

import enum
import math

from agents.behavior import skills
from agents.radio import Intention
from agents.team.behavior.framework import Option
from agents.team.behavior.geometry import in_field
from agents.team.behavior.requests import MotionRequest
from agents.team.behavior.set_plays.throw_in import ThrowInTouch
from agents.team.behavior.striker.context import StrikeContext
from agents.team.params import TeamParams
from match.protocol import Motion, Pose2D
from world.field import FIELD


class Tap(enum.Enum):
    APPROACH = "approach"
    TAPPING = "tapping"  # entered again each step it side-steps into the ball; kept for side_tap.keep_s


class SideTap:
    """The card (:meth:`play`, for a due first touch the robot does not step into); ``along``: the way
    (field x: +1 or -1) the tap of the throw-in chosen for it (``chosen_for_s``, its put-back) goes."""

    def __init__(self, params: TeamParams, touch: ThrowInTouch):
        self.params, self.touch = params, touch
        self.tap = Option(Tap.APPROACH)
        self.chosen_for_s = -math.inf
        self.along = 1.0

    def play(self, c: StrikeContext) -> MotionRequest | None:
        steps = c.quick and c.near and abs(c.heading_error) <= self.params.throw_in.quick_step_rad
        if not c.quick or steps:
            return None
        return self.walk(c)

    def walk(self, c: StrikeContext) -> MotionRequest | None:
        """The side tap's walk (its intention KICK while it side-steps into the ball), or None when the robot
        does not come at the ball for one."""
        p, now, ball_rel, pose = self.params.side_tap, c.world.now_s, c.ball_rel, c.pose
        side = 1.0 if c.ball_xy[1] >= 0.0 else -1.0
        tapping = self.tap.is_in(Tap.TAPPING) and self.tap.for_s(now) < p.keep_s
        if self.chosen_for_s != c.world.game.drop_in_at_s and not self._choose(c, side):
            return None
        left_of_face = -self.along * side  # +1: the tap goes to the robot's left when it faces the line
        face = side * math.pi / 2
        face_error = math.remainder(face - pose.theta, math.tau)
        ball_side = left_of_face * p.side_m
        if tapping or (abs(ball_rel.x - p.forward_m) < p.within_m
                       and abs(ball_rel.y - ball_side) < p.within_m and abs(face_error) < p.face_rad):
            self.tap.enter(Tap.TAPPING, now)
            if abs(ball_rel.y) < p.touch_m:
                self.touch.begin_touch(c.world)
            return MotionRequest(Motion.WALK, skills.walk_command(
                p.gain_per_s * (ball_rel.x - p.forward_m), left_of_face * skills.WALK_HIGH[1],
                skills.TURN_GAIN_PER_S * face_error), Intention.KICK)
        if ball_rel.distance_m < p.near_m:  # beside the ball first, then up to it: never walk into it
            lined_up = abs(ball_rel.y - ball_side) < p.lined_up_m
            forward = p.forward_m if lined_up else p.clear_m
            return _go(skills.walk_command(p.gain_per_s * (ball_rel.x - forward),
                                           p.gain_per_s * (ball_rel.y - ball_side),
                                           skills.TURN_GAIN_PER_S * face_error))
        spot = Pose2D(c.ball_xy[0] - self.along * p.side_m, c.ball_xy[1] - side * p.forward_m, face)
        return _go(skills.walk_to(pose, spot)[1])

    def _choose(self, c: StrikeContext, side: float) -> bool:
        """Whether this throw-in's first touch is a side tap, and which way (:attr:`along`)."""
        p, attack, pose = self.params.side_tap, c.attack, c.pose
        dx, dy = in_field(Pose2D(0.0, 0.0, pose.theta), c.ball_rel)  # the ball from the robot by its sighting
        if attack * c.ball_xy[0] < 0.0:  # own half: toward the opponent goal, or back from past the ball
            along = attack
            if attack * dx < -p.beyond_m and FIELD.half_length + attack * c.ball_xy[0] >= p.back_tap_clear_m:
                along = -attack
        else:  # away from the robot's side
            along = attack if abs(dx) < 1e-6 else math.copysign(1.0, dx)
        inside = side * dy
        square = math.atan2(abs(dx), inside) <= p.approach_rad
        facing = abs(math.remainder(side * math.pi / 2 - pose.theta, math.tau)) <= p.approach_rad
        beyond = -along * dx  # how far the robot is past the ball the way the tap goes
        if inside < p.forward_m / 2 or not (square or facing) or beyond > p.beyond_m:
            return False
        self.chosen_for_s, self.along = c.world.game.drop_in_at_s, along
        return True


def _go(walk: tuple[float, float, float]) -> MotionRequest:
    return MotionRequest(Motion.WALK, walk, Intention.GO_TO_BALL)
