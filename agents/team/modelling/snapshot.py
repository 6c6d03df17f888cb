"""A :class:`WorldModel` built by hand: for tests, drills and options tried outside a match.

Every representation gets a plain default (an upright robot in PLAYING, no teammate, no obstacle,
no throw-in); name only what the situation is about.
"""

from __future__ import annotations

import math

from agents.modelling.ball_model import BallEstimate
from agents.modelling.obstacle_model import Obstacle
from agents.modelling.team_model import Teammate
from agents.team.modelling.representations import (
    BallModel,
    GameSituation,
    Obstacles,
    Odometry,
    PlayStatus,
    Posture,
    RobotPose,
    TeamBall,
    TeamState,
    WorldModel,
)
from match.protocol import DropIn, GameState, GoalColor, KickOff, Pose2D

DT_S = 0.04


def snapshot(pose: Pose2D, *, ball_torso: BallEstimate | None = None, team_ball: BallEstimate | None = None,
             attack: float = 1.0, step: int = 1, player: int = 1, state: GameState = GameState.PLAYING,
             kickoff: KickOff = KickOff.OWN_TEAM, shootout: bool = False, drop_in_at_s: float = -math.inf,
             own_goal_ahead_s: float = -math.inf, obstacles: tuple[Obstacle, ...] = (),
             restart: tuple[float, float] | None = None, kickoff_played_s: float = math.inf,
             sigma_m: float = 0.05, sigma_rad: float = 0.05, state_since_s: float = 0.0,
             teammates: tuple[Teammate, ...] = (), silent_for_s: float = 0.0) -> WorldModel:
    """A snapshot at ``step`` of a robot at ``pose`` (field frame) that sees ``ball_torso`` (its torso
    frame, recent) and whose team believes ``team_ball`` (field frame), attacking toward +x when
    ``attack`` is +1."""
    now = step * DT_S
    field = None
    if ball_torso is not None:
        c, s = math.cos(pose.theta), math.sin(pose.theta)
        field = BallEstimate(pose.x + c * ball_torso.x - s * ball_torso.y, pose.y + s * ball_torso.x + c * ball_torso.y,
                             0.0, 0.0, ball_torso.sigma_m, ball_torso.age_s)
    defended = GoalColor.BLUE if attack > 0 else GoalColor.YELLOW
    game = GameSituation(state, state_since_s, kickoff, shootout, defended, DropIn.NONE, drop_in_at_s, None,
                         own_goal_ahead_s)
    return WorldModel(
        player=player, step=step, now_s=now, robot=RobotPose(pose, sigma_m, sigma_rad),
        posture=Posture(None, False, False, False, None, (0.0, 0.0, 0.0), 0.0, ()),
        odometry=Odometry(True, 0.0, 0.0), game=game, team=TeamState(tuple(teammates), silent_for_s),
        obstacles=Obstacles(tuple(obstacles), pose), ball=BallModel(ball_torso, ball_torso, field),
        team_ball=TeamBall(team_ball), play=PlayStatus(restart, kickoff_played_s))
