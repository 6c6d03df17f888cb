"""A throw-in's first touch near the ball, facing about the way it goes: step to it, then touch it.

Nearer the ball than ``throw_in.quick_step_within_m`` and facing the touch's aim within
``throw_in.quick_step_deg``, the striker steps to the ball without turning to it
(:func:`agents.behavior.skills.step_to_ball`); at the kick spot it kicks at the opponent goal if it may,
else pushes the ball when facing the touch's aim within ``throw_in.quick_push_deg``, else orbits to it.
A striker that comes ``throw_in.late_touch_after_s`` late, the ball within
``throw_in.late_touch_bearing_deg`` of straight ahead and facing the touch's aim, walks on through it (a
push: no slowing down, no side-step to a foot, no kick; together about 1.5 s).
"""

from __future__ import annotations

from agents.behavior import skills
from agents.radio import Intention
from agents.team.behavior.geometry import heading_error
from agents.team.behavior.kick_rules import may_kick
from agents.team.behavior.requests import MotionRequest
from agents.team.behavior.set_plays.throw_in import ThrowInTouch
from agents.team.behavior.striker.context import StrikeContext
from agents.team.params import TeamParams
from match.protocol import Motion


class QuickStep:
    """The card: a due first touch near the ball, facing about its way."""

    def __init__(self, params: TeamParams, touch: ThrowInTouch):
        self.params, self.touch = params, touch

    def play(self, c: StrikeContext) -> MotionRequest | None:
        if not (c.quick and c.near and abs(c.heading_error) <= self.params.throw_in.quick_step_rad):
            return None
        if self._late(c):
            return MotionRequest(Motion.WALK, skills.push(c.ball_rel), Intention.KICK)
        if skills.at_kick_spot(c.ball_rel):
            return first_touch(c, self.params, self.touch)
        return MotionRequest(Motion.WALK, skills.step_to_ball(c.ball_rel, c.heading_error), Intention.GO_TO_BALL)

    def _late(self, c: StrikeContext) -> bool:
        """Whether the touch is late and the striker comes at the ball along the touch's aim (from kicking
        distance on, its push is the first touch)."""
        p, ball_rel = self.params.throw_in, c.ball_rel
        if (c.world.now_s - c.world.game.drop_in_at_s < p.late_touch_after_s
                or abs(ball_rel.bearing_rad) >= p.late_touch_bearing_rad or abs(c.heading_error) > p.quick_push_rad):
            return False
        if ball_rel.distance_m < skills.KICK_DISTANCE_M:
            self.touch.begin_touch(c.world)
        return True


def first_touch(c: StrikeContext, params: TeamParams, touch: ThrowInTouch) -> MotionRequest:
    """The first touch at the ball: the kick at the opponent goal if the robot may kick it, else a push
    (for ``throw_in.quick_push_s``) when facing the touch's aim, else the orbit to it."""
    goal_error = heading_error(c.pose, c.ball_xy, c.goal_aim.xy)
    kick = (abs(goal_error) <= skills.KICK_HEADING_TOLERANCE_RAD
            and may_kick(c.world, params, c.pose, c.ball_xy, c.goal_x, goal_error, shot=c.shot))
    if not kick and abs(c.heading_error) > params.throw_in.quick_push_rad:
        return MotionRequest(Motion.WALK, skills.orbit(c.ball_rel, c.heading_error), Intention.GO_TO_BALL)
    touch.begin_touch(c.world)
    if kick:
        return MotionRequest(skills.kick_for(c.ball_rel), skills.STILL, Intention.KICK)
    return MotionRequest(Motion.WALK, skills.push(c.ball_rel), Intention.KICK)
