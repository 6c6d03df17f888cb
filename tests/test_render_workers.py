"""Render workers (world.render_workers): the frames they draw are the world's own, pixel for pixel."""

from __future__ import annotations

import logging
import random
from pathlib import Path

import numpy as np
import pytest

from match.env import parallel_env
from match.errors import MatchConfigError
from scenarios.matches.play import Lineup, run_lineup_match
from world.config import RobotSpec
from world.field import Pose2D
from world.robot_model import TeamColor
from world.world import MAX_RENDER_WORKERS, World, _shares

QUICK = {"initial_seconds": 0.0, "ready_seconds": 1.0, "set_seconds": 0.0}
ROBOTS = [RobotSpec(f"{side}_{i}", TeamColor.BLUE if side == "home" else TeamColor.RED)
          for side in ("home", "away") for i in range(4)]


def _scatter(world: World, seed: int) -> None:
    """Robots at random poses, walking and turning with their heads turned; the ball rolling."""
    rng = random.Random(seed)
    for robot in world.robot_ids:
        world.place_robot(robot, Pose2D(rng.uniform(-2.5, 2.5), rng.uniform(-1.5, 1.5), rng.uniform(-3.0, 3.0)))
        world.command_walk(robot, 0.1, 0.0, 0.3)
        world.set_head(robot, rng.uniform(-1.0, 1.0), 0.3)
    world.place_ball(0.3, 0.2, 0.5, 0.1)


def test_a_render_worker_draws_the_frames_the_world_draws() -> None:
    with World(ROBOTS, render_workers=1) as world:
        _scatter(world, 0)
        for step in range(16):
            world.step()
            if step == 8:  # half time: the waistbands change colour
                world.set_team_color("home_0", TeamColor.RED)
            robots = list(world.robot_ids)[step % 2::2]
            frames = list(world.render_cameras(robots))
            assert sorted(robot for robot, _ in frames) == sorted(robots)
            assert [robot for robot, _ in frames[:2]] == robots[2:]  # this process's share comes first
            for robot, frame in frames:
                assert np.array_equal(frame, world.render_camera(robot)), (step, robot)
        assert world._render_workers  # the worker never failed


def test_frames_left_uncollected_do_not_mix_with_the_next_ones() -> None:
    with World(ROBOTS, render_workers=1) as world:
        _scatter(world, 2)
        robots = list(world.robot_ids)
        world.step()
        next(world.render_cameras(robots))  # the caller stops after the first frame: the worker's are not read
        world.step()
        frames = dict(world.render_cameras(robots))
        for robot in robots:
            assert np.array_equal(frames[robot], world.render_camera(robot)), robot


def test_a_render_worker_that_dies_is_replaced_by_the_world_itself(caplog: pytest.LogCaptureFixture) -> None:
    with World(ROBOTS, render_workers=1) as world:
        _scatter(world, 1)
        world.step()
        robots = list(world.robot_ids)
        dict(world.render_cameras(robots))  # the worker is up
        worker = world._render_workers[0]
        worker._process.kill()
        worker._process.join()
        with caplog.at_level(logging.WARNING, logger="world.world"):
            frames = dict(world.render_cameras(robots))
        assert "render worker failed" in caplog.text and "exit code" in caplog.text
        assert not world._render_workers
        for robot in robots:
            assert np.array_equal(frames[robot], world.render_camera(robot)), robot


def test_a_match_is_the_same_with_and_without_render_workers(tmp_path: Path) -> None:
    for workers in (0, 1):
        run_lineup_match(tmp_path / str(workers), Lineup(), home=2, away=2, half_seconds=60.0, seed=4,
                         progress=False, max_steps=80, referee=QUICK, render_workers=workers)
    for name in ("events.jsonl", "match_log.npz"):
        assert (tmp_path / "0" / name).read_bytes() == (tmp_path / "1" / name).read_bytes(), name


@pytest.mark.parametrize("value", [-1, MAX_RENDER_WORKERS + 1, 1.0, True, "1", None])
def test_a_bad_number_of_render_workers_is_refused(value: object) -> None:
    with pytest.raises(ValueError, match="render_workers"):
        World(ROBOTS[:2], render_workers=value)
    with pytest.raises(MatchConfigError, match=r"render_workers .*expected an integer 0-4"):
        parallel_env(render_workers=value)


def test_frames_are_shared_out_evenly_the_last_share_the_largest() -> None:
    robots = [f"r{i}" for i in range(5)]
    assert _shares(robots, 2) == [["r0", "r1"], ["r2", "r3", "r4"]]
    assert _shares(robots, 3) == [["r0"], ["r1", "r2"], ["r3", "r4"]]
    assert _shares(robots[:1], 2) == [[], ["r0"]]
