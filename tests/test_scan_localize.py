"""The move-scan-localize cycle (thesis chapter 6) on the bare world: agent and harness."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from agents.behavior.policies.scan_localize import ScanLocalizeAgent
from match.protocol import GameState
from scenarios.localization.run import RunTask, run_alone, simulate_run
from scenarios.localization.spec import RobotEntry, ScenarioSpec
from scenarios.localization.statistics import summarize
from world.field import Pose2D

METHODS = ("thesis", "particle", "odometry")


@pytest.fixture(scope="module")
def short_run():
    return run_alone(4, seed=3, methods=METHODS)


@pytest.mark.render
def test_every_event_gives_one_sample_per_method(short_run):
    samples = short_run.samples
    assert len(samples) == 4 * len(METHODS)
    assert [s.method for s in samples[: len(METHODS)]] == list(METHODS)
    assert sorted({s.event for s in samples}) == [0, 1, 2, 3]
    assert all(s.percepts >= 0 and math.isfinite(s.true_x) for s in samples)
    odometry = [s for s in samples if s.method == "odometry"]
    assert all(s.landmarks_used == 0 for s in odometry)


@pytest.mark.render
def test_the_robot_moves_and_the_landmark_methods_follow_it(short_run):
    samples = short_run.samples
    start = samples[0]
    assert any(math.hypot(s.true_x - start.true_x, s.true_y - start.true_y) > 0.05 or
               abs(s.true_theta - start.true_theta) > 0.1 for s in samples)
    stats = summarize(samples)
    # Loose bounds (the batch statistics carry the figures): a method that ignored its
    # percepts or lost the robot would be off by metres.
    assert stats["particle"]["position_mean_cm"] < 30.0
    assert stats["thesis"]["with_estimate"] >= 1


@pytest.mark.render
def test_same_seed_same_samples(short_run):
    again = run_alone(4, seed=3, methods=METHODS)
    assert [repr(s) for s in again.samples] == [repr(s) for s in short_run.samples]  # repr: NaN == NaN


def test_agent_needs_a_method():
    with pytest.raises(ValueError, match="at least one"):
        ScanLocalizeAgent((), Pose2D(0.0, 0.0, 0.0))


@pytest.mark.render
def test_a_scenario_run_logs_the_agents_estimates_beside_the_truth(tmp_path):
    """The run goes through the one runner; its match log holds the agent's pose estimates."""
    robot = RobotEntry("home_1", "scan_localize", measured=True, start=Pose2D(-1.0, 0.5, 0.0))
    spec = ScenarioSpec("one", "", 3, 1, 5, METHODS, "exact", False, (robot,))
    outcome = simulate_run(RunTask(spec, 0, 5, 3), out_dir=tmp_path)
    assert outcome.complete
    log = np.load(tmp_path / "match_log.npz")
    assert list(log["agents"]) == ["home_1"] and (log["state"] == int(GameState.PLAYING)).all()
    estimates, truth = log["estimates"][:, 0], log["robots"][:, 0]
    assert np.isfinite(estimates).all()
    error = np.hypot(*(estimates[-1, :2] - truth[-1, :2]))
    assert error < 0.5  # the guiding method (thesis) after three scans
    changed = np.flatnonzero(np.any(np.diff(estimates, axis=0) != 0, axis=1))
    assert len(changed) >= 2  # the estimate follows the localizations
    assert json.loads((tmp_path / "summary.json").read_text())["steps"] == len(log["time_s"]) - 1


def test_agent_reports_its_start_and_is_reset_by_the_runner_protocol():
    agent = ScanLocalizeAgent(("thesis",), Pose2D(0.5, -1.0, 1.0))
    assert agent.pose_estimate() == (0.5, -1.0, 1.0)
    agent.reset("home_2", 7)
    first = agent.waypoint
    agent.reset("home_2", 7)
    assert agent.agent_id == "home_2" and agent.waypoint == first and agent.events == []
