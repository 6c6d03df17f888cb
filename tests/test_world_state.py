"""Saved states restore bit for bit, worlds are independent, and bad input changes nothing."""

from __future__ import annotations

import math

import pybullet as pb
import pytest

from world.camera_model import CameraPosition
from world.config import RobotSpec
from world.errors import (
    InvalidCommandError,
    InvalidPoseError,
    JointLimitError,
    UnknownMotionError,
    UnknownRobotError,
    WorldError,
)
from world.field import Pose2D
from world.motions import Motion
from world.robot_model import Joint, TeamColor
from world.world import World


def _busy_run(world: World, steps: int = 60) -> list:
    """Robots walk into each other near the ball; return every pose along the way."""
    trace = []
    world.command_motion("a", Motion.FORWARD)
    world.command_walk("b", 0.15, 0.05, -0.3)
    for _ in range(steps):
        world.step()
        trace.append((world.robot_pose("a"), world.robot_pose("b"), world.ball()))
    return trace


def _setup(world: World) -> None:
    world.place_robot("a", Pose2D(-0.4, 0.0, 0.0))
    world.place_robot("b", Pose2D(0.4, 0.05, math.pi))
    world.place_ball(0.0, 0.0)


def test_restore_gives_bit_identical_results(world):
    _setup(world)
    world.step(5)
    snapshot = world.save_state()
    first = _busy_run(world)
    world.restore_state(snapshot)
    second = _busy_run(world)
    assert first == second


def test_reset_returns_to_initial_state(world):
    initial = (world.robot_pose("a"), world.robot_pose("b"), world.ball(), world.time_s)
    _setup(world)
    world.step(10)
    world.reset()
    assert (world.robot_pose("a"), world.robot_pose("b"), world.ball(), world.time_s) == initial


def test_same_seed_same_run_different_seed_different_run(world):
    runs = []
    for seed in (3, 3, 4):
        world.reset(seed)
        _setup(world)
        runs.append(_busy_run(world, steps=40))
    assert runs[0] == runs[1]
    assert runs[0] != runs[2]


def test_two_worlds_in_one_process_are_independent(world):
    other = World([RobotSpec("a", TeamColor.BLUE), RobotSpec("b", TeamColor.RED)])
    try:
        other.reset(0)
        _setup(world)
        _setup(other)
        # Interleave steps; the other world also gets extra unrelated work.
        trace_world, trace_other = [], []
        world.command_motion("a", Motion.FORWARD)
        other.command_motion("a", Motion.FORWARD)
        world.command_walk("b", 0.15, 0.05, -0.3)
        other.command_walk("b", 0.15, 0.05, -0.3)
        for _ in range(40):
            world.step()
            other.step()
            other.render_camera("a")
            trace_world.append(world.robot_pose("a"))
            trace_other.append(other.robot_pose("a"))
        assert trace_world == trace_other
        other.place_robot("a", Pose2D(2.0, 1.0, 1.0))
        assert world.robot_pose("a") == trace_world[-1]
    finally:
        other.close()


def test_team_colour_changes(world):
    def waist_rgba():
        shapes = pb.getVisualShapeData(world.body_id("a"), physicsClientId=world.client)
        return next(s[7] for s in shapes if s[1] == int(Joint.WAIST))

    assert waist_rgba() == pytest.approx(TeamColor.BLUE.rgba)
    world.set_team_color("a", TeamColor.RED)
    assert waist_rgba() == pytest.approx(TeamColor.RED.rgba)
    world.reset()
    assert waist_rgba() == pytest.approx(TeamColor.BLUE.rgba)


# ---- bad input ------------------------------------------------------------------------

def _fingerprint(world: World):
    return (
        world.robot_pose("a"),
        world.robot_pose("b"),
        world.ball(),
        world.motion_status("a"),
        world.time_s,
    )


BAD_CALLS = [
    (lambda w: w.place_robot("a", Pose2D(float("nan"), 0.0, 0.0)), InvalidPoseError, "nan"),
    (lambda w: w.place_robot("a", Pose2D(0.0, 0.0, float("inf"))), InvalidPoseError, "inf"),
    (lambda w: w.place_robot("a", Pose2D(12.0, 0.0, 0.0)), InvalidPoseError, "12.0"),
    (lambda w: w.place_robot("zz", Pose2D(0.0, 0.0, 0.0)), UnknownRobotError, "'zz'"),
    (lambda w: w.place_ball(0.0, -9.0), InvalidPoseError, "-9.0"),
    (lambda w: w.place_ball(0.0, 0.0, vx=float("nan")), InvalidPoseError, "nan"),
    (lambda w: w.set_head("a", math.radians(130.0), 0.0), JointLimitError, "head_yaw"),
    (lambda w: w.set_head("a", 0.0, math.radians(-45.0)), JointLimitError, "head_pitch"),
    (lambda w: w.set_head("a", float("nan"), 0.0), JointLimitError, "nan"),
    (lambda w: w.command_motion("a", "moonwalk"), UnknownMotionError, "'moonwalk'"),
    (lambda w: w.command_motion("a", 3), UnknownMotionError, "3"),
    (lambda w: w.command_motion("a", "walk"), InvalidCommandError, "walk"),
    (lambda w: w.command_walk("a", 0.5, 0.0, 0.0), InvalidCommandError, "vx=0.5"),
    (lambda w: w.command_walk("a", 0.0, 0.0, float("nan")), InvalidCommandError, "omega=nan"),
    (lambda w: w.command_walk("nobody", 0.1, 0.0, 0.0), UnknownRobotError, "'nobody'"),
    (lambda w: w.set_camera("a", "top"), InvalidCommandError, "'top'"),
    (lambda w: w.set_team_color("a", "green"), InvalidCommandError, "'green'"),
    (lambda w: w.render_camera("c"), UnknownRobotError, "'c'"),
]


@pytest.mark.parametrize("call, error, named", BAD_CALLS)
def test_bad_input_is_typed_names_the_value_and_changes_nothing(world, call, error, named):
    _setup(world)
    world.command_motion("a", Motion.TURN_LEFT_40)
    world.step(3)
    before = _fingerprint(world)
    with pytest.raises(error) as info:
        call(world)
    assert isinstance(info.value, WorldError)
    assert named in str(info.value)
    assert _fingerprint(world) == before
    world.step(2)  # and the world still runs


def test_world_refuses_too_many_or_duplicate_robots():
    with pytest.raises(ValueError, match="unique"):
        World([RobotSpec("a", TeamColor.BLUE), RobotSpec("a", TeamColor.RED)])
    with pytest.raises(ValueError, match="at most 8"):
        World([RobotSpec(f"r{i}", TeamColor.BLUE) for i in range(9)])


def test_camera_switch(world):
    world.place_robot("a", Pose2D(0.0, 0.0, 0.0))
    world.set_camera("a", CameraPosition.BOTTOM)
    world.step(2)
    assert world.sensors("a").camera is CameraPosition.BOTTOM
