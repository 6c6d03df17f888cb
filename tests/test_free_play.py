"""The match's free play (no ball in play, no referee) and the runner's observer hook."""

from __future__ import annotations

import math

import pytest

from match.errors import MatchConfigError
from match.free_play import OFF_FIELD_BALL_XY, FreePlay
from match.game import Match, MatchConfig
from match.protocol import CameraChoice, GameState, Pose2D
from match.runner import run_match
from tests.user_policies import Spinner, WalkForward

STARTS = (("home_1", Pose2D(-1.0, 0.5, 0.3)), ("away_2", Pose2D(1.0, -1.0, 3.0)))


def free_play_config(starts=STARTS) -> MatchConfig:
    return MatchConfig(free_play=FreePlay(starts), initial_camera=CameraChoice.OFF)


class StepCounter:
    """An observer that ends the run after ``limit`` steps and keeps what it saw."""

    def __init__(self, limit: int) -> None:
        self.limit = limit
        self.decided_steps: list[tuple[int, dict]] = []

    def decided(self, match: Match, actions) -> None:
        self.decided_steps.append((match.step_index, dict(actions)))

    def done(self, match: Match) -> bool:
        return match.step_index >= self.limit


def test_free_play_places_the_robots_and_stays_playing() -> None:
    match = Match(free_play_config())
    try:
        observations = match.reset(seed=4)
        assert match.agent_names == ("home_1", "away_2")
        truth = match.truth()
        for robot, start in STARTS:
            x, y, theta = truth["robots"][robot]["pose"]
            assert math.hypot(x - start.x, y - start.y) < 0.05
            assert abs(math.remainder(theta - start.theta, math.tau)) < 0.05
        assert truth["ball"]["position"][:2] == pytest.approx(OFF_FIELD_BALL_XY, abs=0.01)
        assert truth["time_s"] == pytest.approx(0.4)  # the settling steps
        assert all(o["game"]["state"] == GameState.PLAYING for o in observations.values())
        for _ in range(30):
            result = match.step({})
            assert result.events == () and not result.finished
        assert match.events == []
    finally:
        match.close()


def test_a_walking_policy_walks_in_free_play() -> None:
    config = free_play_config()
    match = Match(config)
    try:
        observer = StepCounter(limit=100)
        policies = {"home_1": WalkForward(), "away_2": Spinner()}
        summary = run_match(config, policies, seed=1, progress=False, match=match, observer=observer)
        assert summary.steps == 100 and summary.faults["total"] == 0
        x, y, _ = match.truth()["robots"]["home_1"]["pose"]
        start = STARTS[0][1]
        along = (x - start.x) * math.cos(start.theta) + (y - start.y) * math.sin(start.theta)
        assert along > 0.3  # 4 s at 0.15 m/s
        _, _, theta = match.truth()["robots"]["away_2"]["pose"]
        assert abs(math.remainder(theta - STARTS[1][1].theta, math.tau)) > 0.5
    finally:
        match.close()


def test_the_observer_sees_every_decided_step_and_ends_the_run() -> None:
    config = free_play_config()
    observer = StepCounter(limit=7)
    policies = {"home_1": Spinner(), "away_2": Spinner()}
    summary = run_match(config, policies, seed=2, progress=False, observer=observer)
    assert summary.steps == 7
    assert [step for step, _ in observer.decided_steps] == list(range(7))
    assert all(set(actions) == {"home_1", "away_2"} for _, actions in observer.decided_steps)


def test_policies_are_reset_with_their_robot_and_a_seed_from_the_match_seed() -> None:
    config = free_play_config()
    seeds = []
    for _ in range(2):
        policies = {"home_1": Spinner(), "away_2": Spinner()}
        run_match(config, policies, seed=9, progress=False, max_steps=1)
        assert [p.agent_id for p in policies.values()] == ["home_1", "away_2"]
        seeds.append(tuple(p.seed for p in policies.values()))
    assert seeds[0] == seeds[1] and seeds[0][0] != seeds[0][1]
    policies = {"home_1": Spinner(), "away_2": Spinner()}
    run_match(config, policies, seed=9, progress=False, max_steps=1, policy_seeds={"home_1": 5, "away_2": 6})
    assert [p.seed for p in policies.values()] == [5, 6]


@pytest.mark.parametrize(
    "starts, words",
    [
        ((), "at least one robot"),
        ((("home_9", Pose2D(0, 0, 0)),), "home_9"),
        ((("home_1", Pose2D(0, 0, 0)), ("home_1", Pose2D(1, 0, 0))), "twice"),
        ((("home_1", Pose2D(math.nan, 0, 0)),), "finite"),
        ((("home_1", (0, 0, 0)),), "Pose2D"),
    ],
)
def test_bad_free_play_starts_are_refused(starts, words: str) -> None:
    with pytest.raises(MatchConfigError, match=words):
        FreePlay(starts)
