"""Small geometry of the behaviour: frames (field, torso) and directions (m, rad)."""

from __future__ import annotations

import math

from agents.modelling.ball_model import BallEstimate
from match.protocol import Pose2D
from world.field import FIELD


def relative(pose: Pose2D, ball: BallEstimate) -> BallEstimate:
    """A field-frame ball in the torso frame of ``pose``."""
    dx, dy = ball.x - pose.x, ball.y - pose.y
    c, s = math.cos(pose.theta), math.sin(pose.theta)
    return BallEstimate(c * dx + s * dy, -s * dx + c * dy, 0.0, 0.0, ball.sigma_m, ball.age_s)


def in_field(pose: Pose2D, rel: BallEstimate) -> tuple[float, float]:
    """A robot-relative position (m) in the field frame through ``pose``."""
    c, s = math.cos(pose.theta), math.sin(pose.theta)
    return pose.x + c * rel.x - s * rel.y, pose.y + s * rel.x + c * rel.y


def heading_error(pose: Pose2D, ball_xy: tuple[float, float], aim_xy: tuple[float, float]) -> float:
    """The direction from the ball to ``aim_xy`` minus the robot's heading, normalized (field frame, rad)."""
    return math.remainder(math.atan2(aim_xy[1] - ball_xy[1], aim_xy[0] - ball_xy[0]) - pose.theta, math.tau)


def on_target(heading_rad: float, ball_xy: tuple[float, float], goal_x: float, margin_m: float) -> bool:
    """Whether a ball kicked along ``heading_rad`` from ``ball_xy`` crosses the goal line at
    ``goal_x`` between the posts, ``margin_m`` inside their centres at least (field frame)."""
    toward = math.cos(heading_rad) * (goal_x - ball_xy[0])
    if toward <= 0.0:
        return False
    y_at_line = ball_xy[1] + math.tan(heading_rad) * (goal_x - ball_xy[0])
    return abs(y_at_line) < FIELD.goal_post_y - margin_m


def into_field(ball_xy: tuple[float, float], margin_m: float) -> tuple[float, float]:
    """A ball believed at ``ball_xy`` (field frame), moved ``margin_m`` inside the lines if beyond them."""
    x_max, y_max = FIELD.half_length - margin_m, FIELD.half_width - margin_m
    return min(max(ball_xy[0], -x_max), x_max), min(max(ball_xy[1], -y_max), y_max)
