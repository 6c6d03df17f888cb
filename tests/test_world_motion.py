"""Motions move robots through physics, with seeded noise; only nominal effects are reported."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pybullet as pb
import pytest

from world.config import RobotSpec, WorldConfig
from world.field import Pose2D, normalize_angle
from world.motions import MOTION_SPECS, Motion, MotionNoise
from world.robot_model import TeamColor
from world.world import World

START = Pose2D(-1.0, 0.0, 0.0)


def _play(world: World, robot: str, motion: Motion, extra_steps: int = 10) -> None:
    assert world.command_motion(robot, motion)
    steps = math.ceil(MOTION_SPECS[motion].duration_s / world.config.physics.control_step_s)
    world.step(steps + extra_steps)
    assert world.motion_status(robot).current is None


def _displacement(start: Pose2D, end: Pose2D) -> tuple[float, float, float]:
    """(forward, left, turn) of ``end`` in the frame of ``start``."""
    dx, dy = end.x - start.x, end.y - start.y
    c, s = math.cos(start.theta), math.sin(start.theta)
    return c * dx + s * dy, -s * dx + c * dy, normalize_angle(end.theta - start.theta)


@pytest.fixture(scope="module")
def quiet_world():
    """One robot, no motion noise: real displacement should equal nominal."""
    world = World([RobotSpec("a", TeamColor.BLUE)], WorldConfig(motion_noise=MotionNoise.none()))
    yield world
    world.close()


@pytest.mark.parametrize(
    "motion", [Motion.FORWARD, Motion.BACKWARD, Motion.SIDE_STEP_LEFT, Motion.TURN_RIGHT_40, Motion.TURN_LEFT_180]
)
def test_noiseless_motion_lands_on_nominal(quiet_world, motion):
    quiet_world.reset(0)
    quiet_world.place_robot("a", START)
    quiet_world.step(5)
    start = quiet_world.robot_pose("a")
    _play(quiet_world, "a", motion)
    forward, left, turn = _displacement(start, quiet_world.robot_pose("a"))
    nominal = MOTION_SPECS[motion].nominal
    assert forward == pytest.approx(nominal.forward_m, abs=0.015)
    assert left == pytest.approx(nominal.left_m, abs=0.015)
    assert turn == pytest.approx(normalize_angle(nominal.turn_rad), abs=math.radians(1.5))


@pytest.mark.slow
def test_forward_walk_spreads_by_configured_noise(world):
    """Mean lands near nominal; spread matches scale_sigma (5% of 0.25 m)."""
    forwards = []
    for seed in range(16):
        world.reset(seed)
        world.place_robot("a", START)
        world.place_robot("b", Pose2D(2.0, 2.5, 0.0))
        world.step(3)
        start = world.robot_pose("a")
        _play(world, "a", Motion.FORWARD, extra_steps=3)
        forwards.append(_displacement(start, world.robot_pose("a"))[0])
    nominal = MOTION_SPECS[Motion.FORWARD].nominal.forward_m
    sigma = world.config.motion_noise.scale_sigma * nominal
    assert np.mean(forwards) == pytest.approx(nominal, abs=2.5 * sigma)
    assert 0.4 * sigma < np.std(forwards) < 2.0 * sigma


def test_turn_40_lands_in_thesis_range(world):
    """Thesis section 5.5: a nominal 40 degree turn lands anywhere between 35 and 45 degrees."""
    turns = []
    for seed in range(10):
        world.reset(seed)
        world.place_robot("a", START)
        world.step(3)
        start = world.robot_pose("a")
        _play(world, "a", Motion.TURN_LEFT_40, extra_steps=3)
        turns.append(math.degrees(_displacement(start, world.robot_pose("a"))[2]))
    assert all(34.0 <= t <= 46.0 for t in turns), turns
    assert np.std(turns) > 0.5  # the noise is really there


def test_only_nominal_displacement_is_reported(world):
    world.place_robot("a", START)
    world.step(3)
    _play(world, "a", Motion.SIDE_STEP_RIGHT)
    finished = world.sensors("a").motion.last_finished
    assert finished.motion is Motion.SIDE_STEP_RIGHT and finished.completed
    assert finished.nominal == MOTION_SPECS[Motion.SIDE_STEP_RIGHT].nominal


def test_same_seed_same_motion_result(world):
    results = []
    for _ in range(2):
        world.reset(7)
        world.place_robot("a", START)
        _play(world, "a", Motion.TURN_RIGHT_60)
        results.append(world.robot_pose("a"))
    assert results[0] == results[1]


def test_continuous_walk_moves_and_reports_on_stop(world):
    world.place_robot("a", START)
    world.command_walk("a", 0.15, 0.0, 0.0)
    world.step(50)  # 2 s
    assert world.motion_status("a").current is Motion.WALK
    world.command_motion("a", Motion.STAND)
    finished = world.motion_status("a").last_finished
    assert finished.motion is Motion.WALK and not finished.completed
    assert finished.nominal.forward_m == pytest.approx(0.30, abs=0.01)
    assert world.robot_pose("a").x - START.x == pytest.approx(0.30, abs=0.06)


def test_robot_pushes_robot(world):
    world.place_robot("a", Pose2D(0.0, 0.0, 0.0))
    world.place_robot("b", Pose2D(0.35, 0.0, math.pi))
    world.place_ball(-3.0, 2.5)
    world.command_walk("a", 0.2, 0.0, 0.0)
    world.step(100)
    assert world.robot_pose("b").x > 0.5  # b was pushed back by a
    assert any(world.sensors("a").bumpers)
    assert world.sensors("a").sonar_m[0] < 0.5


def test_fall_and_stand_up(world):
    world.place_robot("a", Pose2D(0.0, 1.0, 0.0))
    world.step(3)
    pb.resetBaseVelocity(world.body_id("a"), (0.0, 1.8, 0.0), (0.0, 0.0, 0.0), physicsClientId=world.client)
    world.step(50)
    sensors = world.sensors("a")
    assert sensors.fallen and world.robot_truth("a").tilt_rad > math.radians(60)
    ax, ay, az = sensors.accelerometer_mps2
    assert abs(az) < 3.0 and math.hypot(ax, ay) > 7.0  # gravity now lies along the torso
    assert not world.command_motion("a", Motion.FORWARD)
    assert world.motion_status("a").refused is Motion.FORWARD
    wrong = Motion.STAND_UP_FROM_BACK if sensors.motion.fall_side.value == "front" else Motion.STAND_UP_FROM_FRONT
    right = Motion.STAND_UP_FROM_FRONT if wrong is Motion.STAND_UP_FROM_BACK else Motion.STAND_UP_FROM_BACK
    _play(world, "a", wrong)
    assert world.sensors("a").fallen
    _play(world, "a", right, extra_steps=25)
    assert not world.sensors("a").fallen
    assert world.robot_truth("a").tilt_rad < math.radians(5)
    assert world.sensors("a").accelerometer_mps2[2] > 9.0
    assert world.command_motion("a", Motion.FORWARD)


@pytest.mark.parametrize("push_mps", [1.8, -1.8], ids=["falls forward", "falls backward"])
def test_after_standing_up_it_faces_the_way_it_faced_before_the_fall(world, push_mps):
    """A robot facing +x pushed forward lands on its front, pushed backward on its back; either way it
    stands up facing about +x again (it pushes itself up over its hands, or sits up toward its feet),
    never turned round."""
    world.place_robot("a", Pose2D(0.0, 0.0, 0.0))
    world.step(3)
    pb.resetBaseVelocity(world.body_id("a"), (push_mps, 0.0, 0.0), (0.0, 0.0, 0.0), physicsClientId=world.client)
    world.step(50)
    sensors = world.sensors("a")
    assert sensors.fallen and sensors.motion.fall_side.value == ("front" if push_mps > 0 else "back")
    right = Motion.STAND_UP_FROM_FRONT if push_mps > 0 else Motion.STAND_UP_FROM_BACK
    _play(world, "a", right, extra_steps=25)
    truth = world.robot_truth("a")
    assert not truth.fallen and abs(math.remainder(truth.pose.theta, math.tau)) < math.radians(45)


def test_kick_moves_ball(world):
    world.place_robot("a", Pose2D(0.0, 0.0, 0.0))
    world.place_robot("b", Pose2D(-2.0, 2.0, 0.0))
    world.place_ball(0.13, -0.05)
    world.step(3)
    world.command_motion("a", Motion.KICK_RIGHT)
    speeds = []
    for _ in range(50):
        world.step()
        ball = world.ball()
        speeds.append(math.hypot(ball.vx, ball.vy))
    assert max(speeds) > 1.0
    assert world.ball().x > 1.0 and world.ball().last_toucher == "a"


def _kick_after_walk(world, seed: int, ahead: float, left: float) -> float:
    """How far (m) along the robot's heading a kick sends a ball placed ``ahead`` and ``left`` of it
    right after 29 control steps of walking forward at 0.08 m/s."""
    world.reset(seed)
    world.place_robot("a", Pose2D(0.0, 0.0, 0.0))
    world.place_robot("b", Pose2D(-3.0, 2.5, 0.0))
    world.place_ball(-2.0, -2.0)
    world.step(3)
    world.command_walk("a", 0.08, 0.0, 0.0)
    world.step(29)
    pose = world.robot_pose("a")
    c, s = math.cos(pose.theta), math.sin(pose.theta)
    bx, by = pose.x + c * ahead - s * left, pose.y + s * ahead + c * left
    world.place_ball(bx, by)
    world.command_motion("a", Motion.KICK_LEFT if left > 0 else Motion.KICK_RIGHT)
    world.step(60)
    ball = world.ball()
    return (ball.x - bx) * c + (ball.y - by) * s


@pytest.mark.parametrize("seed, ahead, left", [(2006, 0.165, 0.045), (2013, 0.155, -0.045), (2006, 0.16, 0.03)])
def test_a_kick_never_squeezes_the_ball_back_between_the_feet(world, seed, ahead, left):
    """With these kick noise draws, a kick whose follow-through swung the leg on to hip -0.75 rad
    pitched the robot back, lifted the foot over the ball and brought it down in front of it:
    the ball went 1-2.5 m backward (own goals). The follow-through now stops at -0.45 rad."""
    assert _kick_after_walk(world, seed, ahead, left) > 1.5


def test_ball_rolls_a_plausible_distance(world):
    world.place_robot("a", Pose2D(-3.5, 3.0, 0.0))
    world.place_robot("b", Pose2D(-3.5, -3.0, 0.0))
    world.place_ball(-2.0, 0.0, vx=1.5)
    world.step(250)
    ball = world.ball()
    assert math.hypot(ball.vx, ball.vy) < 0.02
    assert 2.0 <= ball.x + 2.0 <= 4.0


def test_ball_bounces_off_post(world):
    world.place_robot("a", Pose2D(-3.5, 3.0, 0.0))
    world.place_robot("b", Pose2D(-3.5, -3.0, 0.0))
    world.place_ball(2.5, 0.75, vx=2.0)
    world.step(20)
    assert world.ball().vx < 0.0


def test_upright_robot_sensors(world):
    world.place_robot("a", Pose2D(0.0, 0.0, 0.0))
    world.place_robot("b", Pose2D(1.0, 0.0, math.pi))
    world.step(10)
    sensors = world.sensors("a")
    assert sensors.accelerometer_mps2[2] == pytest.approx(9.81, abs=0.3)
    assert max(abs(g) for g in sensors.gyro_radps) < 0.05
    upper_left, upper_right = sensors.sonar_m[:2]
    assert min(upper_left, upper_right) < 1.0  # robot b stands 1 m ahead
    assert not any(sensors.bumpers) and not sensors.fallen


def test_interrupted_motion_reports_partial_nominal(world):
    world.place_robot("a", START)
    world.command_motion("a", Motion.FORWARD)
    world.step(25)  # 1 s of 2.5 s
    world.command_motion("a", Motion.TURN_LEFT_20)
    finished = world.motion_status("a").last_finished
    assert finished.motion is Motion.FORWARD and not finished.completed
    assert finished.nominal.forward_m == pytest.approx(0.1, abs=0.005)


def test_motion_names_parse(world):
    world.place_robot("a", START)
    assert world.command_motion("a", "turn_left_60")
    assert world.motion_status("a").current is Motion.TURN_LEFT_60


def test_noise_config_is_used(world):
    noise = replace(MotionNoise(), scale_sigma=0.0, lateral_drift_per_m=0.0, heading_drift_rad_per_m=0.0)
    rng = np.random.default_rng(0)
    real = noise.real_displacement(MOTION_SPECS[Motion.FORWARD].nominal, rng)
    assert real == MOTION_SPECS[Motion.FORWARD].nominal


def test_stand_up_while_standing_keeps_the_robot_up(world):
    world.place_robot("a", START)
    _play(world, "a", Motion.STAND_UP_FROM_BACK)
    truth = world.robot_truth("a")
    assert not truth.fallen and truth.tilt_rad < math.radians(3)
    assert math.hypot(truth.pose.x - START.x, truth.pose.y - START.y) < 0.02


def test_walk_recommanded_every_step_keeps_its_stride(world):
    """A controller that re-sends the walk each step (with small speed changes) walks straight
    on, its gyro stays near zero, and each speed change reports the nominal walk so far."""
    world.place_robot("a", Pose2D(-1.0, 0.0, 0.0))
    yaw_rates, walked = [], 0.0
    for i in range(100):
        world.command_walk("a", 0.2 - 0.002 * (i % 2), 0.0, 0.0)
        world.step()
        yaw_rates.append(world.sensors("a").gyro_radps[2])
        walked += world.motion_status("a").last_finished.nominal.forward_m if i else 0.0
    pose = world.robot_pose("a")
    assert pose.x - (-1.0) == pytest.approx(0.8, abs=0.08)
    assert abs(pose.theta) < math.radians(3)
    assert abs(float(np.mean(yaw_rates))) < 0.05
    assert walked == pytest.approx(0.2 * 0.04 * 99, rel=0.05)
