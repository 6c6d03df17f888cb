"""The move-scan-localize cycle (thesis chapter 6) on the bare world: agent and harness."""

from __future__ import annotations

import math

import pytest

from agents.behavior.scan_localize import ScanLocalizeAgent
from scenarios.localization_run import run_alone, summarize
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
