"""The striker's view of its ball in one step, computed once and read by its cards."""

from __future__ import annotations

from dataclasses import dataclass

from agents.behavior.tactics.aim import Aim
from agents.behavior.tactics.shot_window import ShotWindow
from agents.modelling.ball_model import BallEstimate
from agents.team.modelling.representations import WorldModel
from match.protocol import Pose2D


@dataclass(frozen=True)
class StrikeContext:
    """``ball_rel``: its own ball (torso frame; None: only the team's); ``ball_xy``: the ball it plays
    (field frame, inside the lines); ``aim``: where it plays it, ``goal_aim``: where a kick at the goal
    goes (the shot window's or the kick past a robot's aim, else the goal's); ``shot``: that window;
    ``goal_line``: the ball lies on their goal line; ``quick``: a throw-in's first touch is due, ``near``:
    the ball is near enough for it to go the way the robot faces; ``heading_error``: the direction from
    the ball to the aim minus the robot's heading (rad)."""

    world: WorldModel
    pose: Pose2D
    ball_rel: BallEstimate | None
    ball_xy: tuple[float, float]
    attack: float
    goal_x: float
    aim: Aim
    goal_aim: Aim
    shot: ShotWindow | None
    goal_line: bool
    quick: bool
    near: bool
    heading_error: float
