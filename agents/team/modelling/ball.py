"""The own ball: the ball model's estimate, trusted for ``ball.lost_s`` without a sighting."""

from __future__ import annotations

from agents.modelling.ball_model import BallModel as BallFilter
from agents.modelling.ball_model import to_field
from agents.team.modelling.representations import BallModel, RobotPose
from agents.team.params import TeamParams


def own_ball(ball: BallFilter, robot: RobotPose, params: TeamParams) -> BallModel:
    """The own ball in the torso frame and, when recent, in the field frame through the pose estimate."""
    torso = ball.relative()
    recent = torso if torso is not None and torso.age_s <= params.ball.lost_s else None
    field = None
    if recent is not None:
        pose = robot.pose_field
        field = to_field(recent, (pose.x, pose.y, pose.theta), robot.sigma_m, robot.sigma_rad)
    return BallModel(torso, recent, field)
