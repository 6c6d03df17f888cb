"""When the striker may kick: the rules every kick obeys, whatever option plays it."""

from __future__ import annotations

import math

from agents.behavior import skills
from agents.behavior.tactics.aim import POST_CLEARANCE_M
from agents.behavior.tactics.shot_window import ShotWindow
from agents.team.behavior.geometry import on_target
from agents.team.modelling.representations import WorldModel
from agents.team.params import TeamParams
from match.protocol import Pose2D
from world.field import FIELD


def own_goal_seen_lately(world: WorldModel, params: TeamParams) -> bool:
    """A frame showed the own goal near straight ahead within ``kick.own_goal_memory_s``."""
    return world.now_s - world.game.own_goal_ahead_s < params.kick.own_goal_memory_s


def may_kick(world: WorldModel, params: TeamParams, pose: Pose2D, ball_xy: tuple[float, float], goal_x: float,
             heading_error: float, clearing: bool = False, shot: ShotWindow | None = None,
             goal_line: bool = False) -> bool:
    """Facing the opponent goal by the pose (in shooting range, ``shot``: within the open part of
    its mouth, :mod:`agents.behavior.tactics.shot_window`; the kick goes where the robot faces), not the
    own goal by the eyes, not out over a side line within a kick's roll; a clearing from the own
    goal mouth (:mod:`agents.behavior.tactics.aim`) only faces its aim (``heading_error``) and may go
    out: a throw-in there is no goal. On their goal line (``goal_line``) the push in need only
    pass the posts by :data:`agents.behavior.tactics.aim.POST_CLEARANCE_M`, and the push back out in
    front of their goal (a clearing there) is no danger to the own goal, 6 m away, whatever
    the eyes see."""
    k = params.kick
    if clearing:
        aligned = abs(heading_error) <= k.align_rad
        return aligned and (goal_line or not own_goal_seen_lately(world, params))
    hits = on_target(pose.theta, ball_xy, goal_x, POST_CLEARANCE_M if goal_line else k.post_margin_m)
    if shot is not None:
        if not shot.allows(pose.theta):
            return False
    elif math.hypot(goal_x - ball_xy[0], ball_xy[1]) < k.shooting_range_m:
        if not hits:  # at the goal line: between the posts at least
            return False
    elif abs(heading_error) > k.align_rad:
        return False
    if own_goal_seen_lately(world, params):
        return False
    roll_y = ball_xy[1] + math.sin(pose.theta) * skills.KICK_ROLL_M
    if not hits and abs(roll_y) > FIELD.half_width - skills.SIDELINE_MARGIN_M and roll_y * math.sin(pose.theta) > 0:
        return False
    return True
