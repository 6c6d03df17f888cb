"""The inertial sensors' noise: a constant bias per robot and white noise per reading, seeded."""

from __future__ import annotations

import math

import numpy as np
import pytest

from world.config import ImuNoise, RobotSpec, WorldConfig
from world.field import Pose2D
from world.robot_model import TeamColor
from world.world import World

STEPS = 250  # 10 s


def _gyro_yaw_drift(world: World, robot: str = "a") -> tuple[float, list]:
    world.place_robot(robot, Pose2D(0.0, 0.0, 0.0))
    readings, heading = [], 0.0
    for _ in range(STEPS):
        world.step()
        reading = world.sensors(robot)
        readings.append((reading.gyro_radps, reading.accelerometer_mps2))
        heading += reading.gyro_radps[2] * 0.04
    return heading, readings


@pytest.fixture
def pair():
    worlds = [World([RobotSpec("a", TeamColor.BLUE)], seed=s) for s in (3, 3, 4)]
    yield worlds
    for w in worlds:
        w.close()


def test_a_standing_robot_s_gyro_drifts_by_its_bias_and_the_seed_decides(pair) -> None:
    first, again, other = (_gyro_yaw_drift(w) for w in pair)
    assert first[1] == again[1]  # same seed, same readings
    assert first[1] != other[1]
    drifts = [abs(first[0]), abs(other[0])]
    assert max(drifts) > math.radians(0.1)  # no longer exact
    assert all(d < math.radians(15.0) for d in drifts)  # a bias of a few tenths of a degree per second


def test_noise_is_a_constant_bias_plus_white_noise_on_the_true_reading() -> None:
    noise = ImuNoise()
    exact = WorldConfig(imu_noise=ImuNoise(0.0, 0.0, 0.0, 0.0))
    with World([RobotSpec("a", TeamColor.BLUE)], seed=3) as noisy, World([RobotSpec("a", TeamColor.BLUE)], exact, seed=3) as true:
        noisy_readings, true_readings = _gyro_yaw_drift(noisy)[1], _gyro_yaw_drift(true)[1]
    for k, (bias_sigma, sigma) in enumerate(((noise.gyro_bias_sigma_radps, noise.gyro_noise_sigma_radps),
                                             (noise.accelerometer_bias_sigma_mps2, noise.accelerometer_noise_sigma_mps2))):
        error = np.array([n[k] for n in noisy_readings]) - np.array([t[k] for t in true_readings])
        assert np.all(np.abs(error.mean(axis=0)) < 4 * bias_sigma)  # one bias per axis
        assert np.allclose(error.std(axis=0), sigma, rtol=0.2)  # white noise on every reading


def test_reset_with_a_seed_draws_new_biases_and_restore_repeats_them() -> None:
    with World([RobotSpec("a", TeamColor.BLUE)], seed=1) as world:
        world.reset(5)
        first = _gyro_yaw_drift(world)[1]
        world.reset(5)
        assert _gyro_yaw_drift(world)[1] == first
        world.reset(6)
        assert _gyro_yaw_drift(world)[1] != first


def test_without_noise_the_readings_are_exact() -> None:
    exact = WorldConfig(imu_noise=ImuNoise(0.0, 0.0, 0.0, 0.0))
    with World([RobotSpec("a", TeamColor.BLUE)], exact, seed=1) as one, World([RobotSpec("a", TeamColor.BLUE)], exact, seed=2) as two:
        assert _gyro_yaw_drift(one)[1] == _gyro_yaw_drift(two)[1]


@pytest.mark.parametrize("bad", [-0.1, math.nan, math.inf])
def test_bad_noise_settings_are_refused(bad: float) -> None:
    with pytest.raises(ValueError, match="gyro_bias_sigma_radps"):
        ImuNoise(gyro_bias_sigma_radps=bad)


@pytest.mark.parametrize("seed", [1, 2])
def test_the_gyro_summed_over_steps_is_the_torso_s_turn_even_when_jostled(seed: int) -> None:
    """Two robots walking into each other jostle their torsos: an instant's angular velocity per
    step summed 20 degrees off the turn in 10 s; the mean over each step sums to the turn."""
    exact = WorldConfig(imu_noise=ImuNoise(0.0, 0.0, 0.0, 0.0))
    specs = [RobotSpec("a", TeamColor.BLUE), RobotSpec("b", TeamColor.RED)]
    with World(specs, exact, seed=seed) as world:
        world.place_robot("a", Pose2D(0.0, 0.0, 0.0))
        world.place_robot("b", Pose2D(0.32, 0.08, math.pi))
        summed, turned, last = 0.0, 0.0, world.robot_pose("a").theta
        for _ in range(STEPS):
            world.command_walk("a", 0.2, 0.05, 0.0)
            world.command_walk("b", 0.2, -0.05, 0.0)
            world.step()
            summed += world.sensors("a").gyro_radps[2] * 0.04
            theta = world.robot_pose("a").theta
            turned, last = turned + math.remainder(theta - last, math.tau), theta
    assert abs(turned) > math.radians(90.0)  # they pushed each other round
    assert summed == pytest.approx(turned, abs=math.radians(1.0))
