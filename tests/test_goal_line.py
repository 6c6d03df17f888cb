"""A ball at the own goal line in front of the goal is held off, never walked round."""

from __future__ import annotations

import math

import pytest

from agents.behavior.skills import ARRIVED_M
from agents.behavior.tactics.goal_line import HOLD_NEAR_M, at_own_goal_line, hold_off, hold_pose
from agents.modelling.ball_model import BallEstimate
from agents.radio import Intention
from agents.team.agent import TeamAgent
from match.protocol import Motion, Pose2D
from tests.team_scene import strike
from world.field import FIELD


def _mirrored(attack: float, x: float, y: float, theta: float) -> Pose2D:
    """A pose given in the frame where the own goal is at x = -3, in the field frame."""
    if attack > 0:
        return Pose2D(x, y, theta)
    return Pose2D(-x, -y, math.remainder(theta + math.pi, math.tau))


def _relative(pose: Pose2D, xy: tuple[float, float]) -> BallEstimate:
    dx, dy = xy[0] - pose.x, xy[1] - pose.y
    c, s = math.cos(pose.theta), math.sin(pose.theta)
    return BallEstimate(c * dx + s * dy, -s * dx + c * dy, 0.0, 0.0, 0.02, 0.0)


@pytest.mark.parametrize("attack", [1.0, -1.0])
@pytest.mark.parametrize("player, robot, ball", [
    # Seen in self-play (own-goal frame): a striker 0.21 m from a ball lying on the goal line, which it
    # believed just beyond it, side-stepped round it (walk 0.03, 0.1, -0.37) and pushed it in 1.8 s later.
    ("_1", (-2.94, 0.11, math.pi - math.radians(34.0)), (-3.14, 0.17)),
    # A goalkeeper 0.17 m from a ball on the goal line beside its post went round it to clear it.
    ("_0", (-2.83, -0.72, 1.02 - math.pi), (-2.956, -0.831)),
])
def test_a_robot_near_a_ball_at_its_own_goal_line_stands(attack: float, player: str, robot, ball) -> None:
    pose = _mirrored(attack, *robot)
    ball_xy = (attack * ball[0], attack * ball[1])
    agent = TeamAgent()
    agent.reset("away" + player, 0)
    motion, walk, _ = strike(agent, pose, _relative(pose, ball_xy), None, attack, (0.0, 0.0))
    assert motion is Motion.STAND and walk == (0.0, 0.0, 0.0)
    assert agent.behavior.intention is not Intention.KICK


@pytest.mark.parametrize("attack", [1.0, -1.0])
def test_the_band_is_the_goal_mouth_at_the_line(attack: float) -> None:
    line = -attack * FIELD.half_length
    assert at_own_goal_line((line + attack * 0.1, 0.0), attack)
    assert at_own_goal_line((line - attack * 0.05, 0.7), attack)  # believed just beyond it, at the post
    assert not at_own_goal_line((line + attack * 0.2, 0.0), attack)  # room behind it: cleared (agents.behavior.tactics.aim)
    assert not at_own_goal_line((line + attack * 0.05, FIELD.goal_post_y + 0.2), attack)  # beside the goal
    assert not at_own_goal_line((-line - attack * 0.05, 0.0), attack)  # the opponent goal line


@pytest.mark.parametrize("attack", [1.0, -1.0])
@pytest.mark.parametrize("start", [(-1.5, 0.0, 0.0), (-2.95, 0.8, -1.5), (-2.4, -0.6, 2.5), (-3.2, 0.5, 0.0),
                                   (-2.0, 1.5, math.pi)])
def test_a_robot_coming_to_the_ball_waits_in_front_of_it_and_never_comes_nearer(attack: float, start) -> None:
    ball_xy = (attack * (-FIELD.half_length + 0.05), attack * 0.1)
    pose = _mirrored(attack, *start)
    nearest = math.inf
    dt = 0.04
    for _ in range(int(30.0 / dt)):
        motion, (vx, vy, omega) = hold_off(pose, ball_xy, attack)
        c, s = math.cos(pose.theta), math.sin(pose.theta)
        pose = Pose2D(pose.x + (c * vx - s * vy) * dt, pose.y + (s * vx + c * vy) * dt, pose.theta + omega * dt)
        nearest = min(nearest, math.dist((pose.x, pose.y), ball_xy))
    assert motion is Motion.STAND
    assert nearest > HOLD_NEAR_M - 0.02
    spot = hold_pose(ball_xy, attack)
    assert attack * spot.x > attack * ball_xy[0]  # in front of the ball, toward the field
    assert math.dist((pose.x, pose.y), ball_xy) < HOLD_NEAR_M + ARRIVED_M + 0.01  # waits there


@pytest.mark.parametrize("attack", [1.0, -1.0])
def test_a_ball_off_the_line_is_played_as_before(attack: float) -> None:
    pose = _mirrored(attack, -2.2, 0.3, math.pi * 0.9)
    ball_xy = (attack * (-FIELD.half_length + 0.3), attack * 0.2)
    agent = TeamAgent()
    agent.reset("home_1", 0)
    motion, walk, _ = strike(agent, pose, _relative(pose, ball_xy), None, attack, (0.0, 0.0))
    assert motion is Motion.WALK and any(walk)
    assert agent.behavior.intention is Intention.GO_TO_BALL
