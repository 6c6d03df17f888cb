"""The clear-line set play (agents.team.behavior.set_plays.clear_line), from hand-built world models: a ball at
the own goal line beside the goal is pushed along the line toward the side line; off (as shipped), the striker
plays as before."""

from __future__ import annotations

import math

import pytest

from agents.modelling.ball_model import BallEstimate
from agents.radio import Intention
from agents.team.behavior.set_plays.clear_line import line_clearing
from agents.team.behavior.striker.play import Striker
from agents.team.modelling.snapshot import snapshot
from agents.team.params import TeamParams
from match.protocol import Motion, Pose2D
from world.field import FIELD

OFF = TeamParams.default()  # shipped off
P = OFF.replace(clear_line={"enabled": True})


@pytest.mark.parametrize("attack", [1.0, -1.0])
def test_the_place_is_beside_the_goal_at_the_own_line(attack: float) -> None:
    p = P.clear_line
    line = -attack * FIELD.half_length
    for by in (-1.1, 1.1, FIELD.goal_post_y + p.beside_post_m, p.outer_y_m):
        aim = line_clearing((line + attack * 0.1, by), attack, p)
        assert aim is not None and aim.clearing and aim.push
        away = math.copysign(1.0, by) * (aim.y - by)  # toward the nearer side line ...
        into = attack * (aim.x - (line + attack * 0.1))  # ... turned into the field by turn_deg
        assert away > 0.0 and into > 0.0 and math.atan2(into, away) == pytest.approx(p.turn_rad)
    for bx, by in ((line + attack * 0.1, 0.5), (line + attack * (p.depth_m + 0.05), 1.1),
                   (line + attack * 0.1, p.outer_y_m + 0.1), (-line, 1.1)):
        assert line_clearing((bx, by), attack, p) is None


@pytest.mark.parametrize("attack", [1.0, -1.0])
def test_a_striker_facing_along_the_line_pushes_the_ball_toward_the_side_line(attack: float) -> None:
    """The ball before its left foot, the robot between it and the goal facing the side line: it pushes the
    ball that way. Without the card it aims 40 degrees and more from the line and orbits to get there."""
    ball_xy = (-attack * (FIELD.half_length - 0.15), attack * 1.1)
    theta = attack * math.pi / 2
    c, s = math.cos(theta), math.sin(theta)
    ball_rel = BallEstimate(0.14, 0.05, 0.0, 0.0, 0.03, 0.0)
    pose = Pose2D(ball_xy[0] - (c * 0.14 - s * 0.05), ball_xy[1] - (s * 0.14 + c * 0.05), theta)
    world = snapshot(pose, ball_torso=ball_rel, attack=attack)
    assert math.dist(ball_xy, (world.ball.field.x, world.ball.field.y)) < 1e-9
    on = Striker(P).play(world, False, False)
    assert on.motion is Motion.WALK and on.intention is Intention.KICK and on.walk[0] > 0.0
    off = Striker(OFF).play(world, False, False)
    assert off.intention is Intention.GO_TO_BALL


@pytest.mark.parametrize("attack", [1.0, -1.0])
def test_a_striker_coming_from_the_field_walks_between_the_ball_and_the_goal(attack: float) -> None:
    """From the field it walks round to the ball's near-goal side, where without the card it makes for a spot
    behind the ball beyond its own end line: another walk."""
    ball_xy = (-attack * (FIELD.half_length - 0.1), 1.2)
    pose = Pose2D(ball_xy[0] + attack * 0.9, 1.2, math.pi if attack > 0 else 0.0)
    c, s = math.cos(pose.theta), math.sin(pose.theta)
    dx, dy = ball_xy[0] - pose.x, ball_xy[1] - pose.y
    ball_rel = BallEstimate(c * dx + s * dy, -s * dx + c * dy, 0.0, 0.0, 0.03, 0.0)
    world = snapshot(pose, ball_torso=ball_rel, attack=attack)
    on = Striker(P).play(world, False, False)
    assert on.motion is Motion.WALK and on.intention is Intention.GO_TO_BALL
    assert on != Striker(OFF).play(world, False, False)


def test_off_or_elsewhere_the_card_leaves_the_play_to_the_next() -> None:
    """A ball in the open field, or only the team's ball: the same requests with the card on and off."""
    pose = Pose2D(-1.0, 0.0, 0.0)
    for ball_rel, team_ball in ((BallEstimate(0.5, 0.1, 0.0, 0.0, 0.03, 0.0), None),
                                (None, BallEstimate(-2.9, 1.1, 0.0, 0.0, 0.1, 0.5))):
        world = snapshot(pose, ball_torso=ball_rel, team_ball=team_ball)
        assert Striker(P).play(world, False, False) == Striker(OFF).play(world, False, False)
