"""A throw-in's first touch: its state, whether the ball still waits for it, and which way it goes.

After the referee puts the ball back, the striker takes the quickest first touch that sends the ball
neither back toward the own goal nor out (:func:`agents.behavior.tactics.aim.restart_aim`): for
``throw_in.quick_touch_s``, or up to ``throw_in.quick_untouched_s`` while the ball still lies where the
striker first saw it after the put-back (within ``throw_in.quick_untouched_m``: its field position
flickers with the pose estimate), and while the ball is near the throw-in line
(``throw_in.quick_touch_band_m``). Once touched, the touch goes on for ``throw_in.quick_push_s``; then the
striker plays on as in open play (pushing on drifts the ball out over the line). The time allowed grows
while nobody has touched the ball, so that a striker lined up for its touch when the first span ends
does not turn away to play it as in open play.
"""

from __future__ import annotations

import enum
import math

from agents.behavior.tactics.aim import Aim, restart_aim
from agents.modelling.ball_model import BallEstimate
from agents.team.behavior.framework import Option
from agents.team.modelling.representations import WorldModel
from agents.team.params import TeamParams
from match.protocol import THROW_IN_INSET_M, Pose2D
from world.field import FIELD


class FirstTouch(enum.Enum):
    PENDING = "pending"
    TOUCHED = "touched"  # since the touch began (a touch from before the last put-back counts for nothing)


class ThrowInTouch:
    """The first touch of the last throw-in: its state, where the striker first saw the ball after the
    put-back (field frame), and the direction of the touch's last aim (field frame, rad)."""

    def __init__(self, params: TeamParams):
        self.params = params
        self.touch = Option(FirstTouch.PENDING)
        self.seen_xy: tuple[float, float] | None = None
        self.aim_rad: float | None = None
        self._for_drop_in_at_s: float | None = None  # the put-back the two above belong to

    def follow(self, world: WorldModel) -> None:
        """A new put-back: where the ball was seen and where the touch aimed are forgotten."""
        if world.game.drop_in_at_s != self._for_drop_in_at_s:
            self._for_drop_in_at_s = world.game.drop_in_at_s
            self.seen_xy = self.aim_rad = None

    def touched(self, world: WorldModel) -> bool:
        """The touch began after the last put-back."""
        return self.touch.is_in(FirstTouch.TOUCHED) and self.touch.since_s >= world.game.drop_in_at_s

    def begin_touch(self, world: WorldModel) -> None:
        if not self.touched(world):
            self.touch.enter(FirstTouch.TOUCHED, world.now_s)

    def note_ball(self, world: WorldModel, ball_rel: BallEstimate | None, ball_xy: tuple[float, float]) -> None:
        """Where the striker first saw the ball after the put-back (its own sighting)."""
        if (ball_rel is not None and self.seen_xy is None
                and world.now_s - world.game.drop_in_at_s < self.params.throw_in.quick_touch_s):
            self.seen_xy = ball_xy

    def waits(self, world: WorldModel, ball_xy: tuple[float, float]) -> bool:
        """Whether the ball, believed at ``ball_xy``, still waits for the quick first touch."""
        p = self.params.throw_in
        if self.touched(world) and self.touch.for_s(world.now_s) >= p.quick_push_s:
            return False  # its first touch is taken
        since_s = world.now_s - world.game.drop_in_at_s
        if since_s >= p.quick_touch_s:
            untouched = self.seen_xy is not None and math.dist(self.seen_xy, ball_xy) <= p.quick_untouched_m
            if since_s >= p.quick_untouched_s or not untouched:
                return False
        line_y = FIELD.half_width - THROW_IN_INSET_M
        return abs(abs(ball_xy[1]) - line_y) < p.quick_touch_band_m

    def aim(self, pose: Pose2D, ball_xy: tuple[float, float], near: bool, attack: float) -> Aim:
        """The touch's aim: the way the robot faces near the ball (``near``), else the way it comes at it,
        kept from the last aim where the rule allows (:func:`agents.behavior.tactics.aim.restart_aim`)."""
        way = pose.theta if near else math.atan2(ball_xy[1] - pose.y, ball_xy[0] - pose.x)
        aim = restart_aim(ball_xy, way, attack, self.aim_rad)
        self.aim_rad = math.atan2(aim.y - ball_xy[1], aim.x - ball_xy[0])
        return aim
