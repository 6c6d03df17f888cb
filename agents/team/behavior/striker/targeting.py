"""Where the striker plays its ball: the goal, the open part of its mouth, past a robot, or a clearing.

Within ``kick.shooting_range_m`` of the goal, it kicks into the widest part of the mouth no robot it
saw covers (:mod:`agents.behavior.tactics.shot_window`), farther out past a robot it saw in the way
(:mod:`agents.behavior.tactics.kick_past`) once within ``kick.kick_past_near_m`` of its ball; a ball in front of
its own goal is cleared out to the side, and one on their goal line pushed (:mod:`agents.behavior.tactics.aim`).
Each remembers the direction it chose last, so the aim does not flicker between windows. Lining a kick
up with the ball at its feet (the bottom camera), it asks for the top camera's frame now and then: it
sees the robots a kick must pass and the goal's posts.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from agents.behavior import skills
from agents.behavior.tactics.aim import Aim, kick_aim, on_their_goal_line
from agents.behavior.tactics.kick_past import kick_past
from agents.behavior.tactics.shot_window import ShotWindow, shot_window
from agents.modelling.ball_model import BallEstimate
from agents.team.params import TeamParams


@dataclass(frozen=True)
class Target:
    aim: Aim
    shot: ShotWindow | None
    goal_line: bool
    lining_up: bool  # the ball at its feet while it aims at a window or past a robot


class Targeting:
    """Chooses the aim; remembers the shot window's and the kick past's last directions (field frame, rad)."""

    def __init__(self, params: TeamParams):
        self.params = params
        self.shot_direction_rad: float | None = None
        self.past_direction_rad: float | None = None

    def target(self, ball_xy: tuple[float, float], ball_rel: BallEstimate | None, attack: float, robot_y: float,
               goal_x: float, robots_field: tuple[tuple[float, float], ...]) -> Target:
        aim = kick_aim(ball_xy, attack, robot_y)
        goal_line = on_their_goal_line(ball_xy, attack)
        if aim.clearing or goal_line:
            return Target(aim, None, goal_line, False)
        at_feet = ball_rel is not None and ball_rel.distance_m < skills.BOTTOM_CAMERA_BELOW_M
        if math.hypot(goal_x - ball_xy[0], ball_xy[1]) < self.params.kick.shooting_range_m:
            shot = shot_window(ball_xy, goal_x, list(robots_field), self.shot_direction_rad)
            self.shot_direction_rad = shot.direction_rad
            return Target(Aim(*shot.aim_xy, False), shot, goal_line, at_feet)
        if ball_rel is not None and ball_rel.distance_m < self.params.kick.kick_past_near_m:
            past = kick_past(ball_xy, goal_x, list(robots_field), self.past_direction_rad)
            self.past_direction_rad = None if past is None else past.direction_rad
            return Target(aim if past is None else Aim(*past.aim_xy, False), past, goal_line, at_feet)
        return Target(aim, None, goal_line, False)
