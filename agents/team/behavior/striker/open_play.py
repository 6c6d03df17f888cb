"""The striker's open-play cards, in the order it plays them (after the throw-in's first touches).

* :class:`ApproachTeamBall`: the team's ball (a teammate's, or a throw-in's spot), not its own: come at
  it from behind.
* :class:`StalledPush`: a ball stalled at its feet (:mod:`agents.behavior.tactics.stall`): walk on through it,
  away from the own goal, unless the own goal was seen ahead lately.
* :class:`GoBehind`: the ball off the line from the aim: walk round to the spot behind it (from
  ``throw_in.quick_go_behind_beyond_m`` for a throw-in's first touch, else from
  :data:`agents.behavior.skills.GO_BEHIND_BEYOND_M` on; nearer, it orbits the ball).
* :class:`Chase`: up to the ball, a foot first, and kick where the kick rules allow
  (:mod:`agents.team.behavior.kick_rules`), else orbit; at a goal line a kick gone wrong is a goal or a
  miss: push instead. A throw-in's first touch at the kick spot is :func:`first_touch`'s.
"""

from __future__ import annotations

from agents.behavior import skills
from agents.behavior.tactics.stall import STALL_NEAR_M, StallWatch, push_allowed
from agents.radio import Intention
from agents.team.behavior.kick_rules import may_kick, own_goal_seen_lately
from agents.team.behavior.requests import MotionRequest
from agents.team.behavior.set_plays.first_touch import first_touch
from agents.team.behavior.set_plays.throw_in import ThrowInTouch
from agents.team.behavior.striker.context import StrikeContext
from agents.team.params import TeamParams
from match.protocol import Motion


class ApproachTeamBall:
    def play(self, c: StrikeContext) -> MotionRequest | None:
        if c.ball_rel is not None:
            return None
        target = skills.approach_pose(c.pose, c.ball_xy, c.aim.xy)
        return MotionRequest.of(skills.walk_to(c.pose, target), Intention.GO_TO_BALL)


class StalledPush:
    def __init__(self, params: TeamParams):
        self.params = params
        self.watch = StallWatch()

    def play(self, c: StrikeContext) -> MotionRequest | None:
        stalled = self.watch.pushing(c.world.now_s, c.ball_xy, c.ball_rel.distance_m < STALL_NEAR_M)
        if stalled and push_allowed(c.pose.theta, c.attack) and not own_goal_seen_lately(c.world, self.params):
            return MotionRequest(Motion.WALK, skills.push(c.ball_rel), Intention.KICK)
        return None


class GoBehind:
    def __init__(self, params: TeamParams):
        self.params = params

    def play(self, c: StrikeContext) -> MotionRequest | None:
        beyond_m = self.params.throw_in.quick_go_behind_beyond_m if c.quick else skills.GO_BEHIND_BEYOND_M
        waypoint = skills.behind_ball(c.pose, c.ball_xy, c.aim.xy, beyond_m)
        if waypoint is None:
            return None
        motion, walk = skills.walk_to(c.pose, waypoint)
        if motion is Motion.STAND:  # at the way round (near enough to it): on to the spot behind the ball
            motion, walk = skills.walk_to(c.pose, skills.behind_point(c.ball_xy, c.aim.xy))
        return MotionRequest(motion, walk, Intention.GO_TO_BALL)


class Chase:
    def __init__(self, params: TeamParams, touch: ThrowInTouch):
        self.params, self.touch = params, touch

    def play(self, c: StrikeContext) -> MotionRequest:
        motion, walk = skills.chase(c.ball_rel, c.heading_error, foot_first=True)
        if not motion.is_kick:
            return MotionRequest(motion, walk, Intention.GO_TO_BALL)
        if c.quick:
            return first_touch(c, self.params, self.touch)
        if not may_kick(c.world, self.params, c.pose, c.ball_xy, c.goal_x, c.heading_error, c.aim.clearing, c.shot,
                        c.goal_line):
            return MotionRequest(Motion.WALK, skills.orbit(c.ball_rel, c.heading_error or 0.3), Intention.GO_TO_BALL)
        if c.aim.push:  # at a goal line a kick gone wrong is a goal, or a miss: push the ball
            return MotionRequest(Motion.WALK, skills.push(c.ball_rel), Intention.KICK)
        return MotionRequest(motion, walk, Intention.KICK)
