"""Episodes as options (length, halves, pauses, shoot-out, start, max_cycles; the learning preset) and reward
functions of the match's truth, which never reaches an observation."""

from __future__ import annotations

import math
from types import MappingProxyType

import numpy as np
import pytest

from pettingzoo.test import api_test, parallel_api_test

import match.env as env_module
from match import parallel_env
from match.episodes import LEARNING, Episode
from match.errors import InvalidActionError, MatchConfigError, RewardError
from match.events import EventKind, MatchEvent
from match.game import MatchConfig
from match.protocol import GameState, Motion, make_action
from match.pose_estimates import PoseEstimates
from match.referee import RefereeConfig
from match.rewards import BallProgress, Goals, Possession, Shots, Weighted
from match.starts import RANDOM_MARGIN_M, RANDOM_SPACING_M, WAITING_Y_M
from match.truth import BallTruth, MatchTruth, RobotTruth
from match.wrappers import flat_layout
from world.field import FIELD

pytestmark = pytest.mark.render


@pytest.fixture(scope="module")
def env():
    env = parallel_env(2, 2, preset="learning", half_seconds=2.0)
    yield env
    env.close()


def _run_out(env, actions=None) -> tuple[int, dict]:
    steps, terminations = 0, {}
    while env.agents:
        _, _, terminations, _, _ = env.step(actions or {})
        steps += 1
    return steps, terminations


# ---- episodes ---------------------------------------------------------------------------------


def test_the_default_episode_is_the_referees_full_match():
    env = parallel_env(1, 1)
    assert env.episode == Episode() and env.match.referee.config == RefereeConfig()
    assert env.max_cycles == 100_000
    env.close()


def test_the_learning_preset_is_one_half_without_pauses_or_shootout(env):
    assert LEARNING.halves == 1 and LEARNING.pauses is False and LEARNING.shootout is False
    env.reset(seed=1)
    states = [env.match.referee.state]
    for _ in range(3):
        env.step({})
        states.append(env.match.referee.state)
    assert states == [GameState.INITIAL, GameState.READY, GameState.SET, GameState.PLAYING]
    steps, terminations = _run_out(env)
    assert all(terminations.values()) and env.match.referee.state is GameState.FINISHED
    assert env.match.referee.half == 1 and env.match.referee.shootout is None
    assert steps == pytest.approx(2.0 / 0.04, abs=2)


def test_options_change_one_episode_only(env):
    env.reset(seed=2, options={"max_cycles": 7, "half_seconds": 30.0})
    steps, _ = _run_out(env)
    assert steps == 7 and env.match.referee.config.half_seconds == 30.0
    env.reset(seed=2)
    assert env.match.referee.config.half_seconds == 2.0 and env.match.referee.state is GameState.INITIAL


def test_a_penalty_start_places_one_attacker_and_one_keeper_and_plays_at_once(env):
    env.reset(seed=3, options={"start": "penalty", "half_seconds": 30.0})
    truth = env.truth()
    assert truth.state is GameState.PLAYING and env.match.referee.kickoff is None
    assert (truth.ball.x, truth.ball.y) == pytest.approx((FIELD.penalty_mark_x, 0.0), abs=0.02)
    attacker, keeper = truth.robots["home_1"], truth.robots["away_0"]
    assert attacker.x == pytest.approx(FIELD.penalty_mark_x - 0.22, abs=0.03) and abs(attacker.theta) < 0.1
    assert keeper.x == pytest.approx(2.85, abs=0.03) and abs(abs(keeper.theta) - math.pi) < 0.1
    for waiting in ("home_0", "away_1"):
        assert truth.robots[waiting].y == pytest.approx(WAITING_Y_M, abs=0.03)
    walk = {"home_1": make_action(Motion.WALK, walk=(0.2, 0.0, 0.0))}
    for _ in range(60):
        env.step(walk)
    assert env.truth().ball.x > FIELD.penalty_mark_x + 0.1  # play went on: the attacker pushed the ball


def test_random_starts_are_drawn_from_the_seed(env):
    def placed(seed):
        env.reset(seed=seed, options={"start": "random"})
        truth = env.truth()
        return truth, [(r.x, r.y) for r in truth.robots.values()] + [(truth.ball.x, truth.ball.y)]

    (truth, points), (_, again), (_, other) = placed(4), placed(4), placed(5)
    assert points == again and points != other and truth.state is GameState.PLAYING
    for i, (x, y) in enumerate(points):
        assert abs(x) <= FIELD.half_length - RANDOM_MARGIN_M + 0.05 and abs(y) <= FIELD.half_width - RANDOM_MARGIN_M + 0.05
        for px, py in points[i + 1:]:
            assert math.hypot(x - px, y - py) >= RANDOM_SPACING_M - 0.05


@pytest.mark.parametrize("options, words", [
    ({"start": "corner"}, "start = 'corner'"),
    ({"halves": 3}, "halves = 3"),
    ({"half_seconds": -1.0}, "half_seconds = -1.0"),
    ({"half_seconds": float("nan")}, "half_seconds = nan"),
    ({"max_cycles": 0}, "max_cycles = 0"),
    ({"pauses": "no"}, "pauses = 'no'"),
    ({"shootout": 1}, "shootout = 1"),
    ([("start", "random")], "reset options"),
])
def test_bad_options_are_refused_before_anything_changes(env, options, words):
    env.reset(seed=5)
    env.step({})
    before = (env.match.step_index, env.episode_seed, list(env.agents))
    with pytest.raises(MatchConfigError, match=words):
        env.reset(seed=6, options=options)
    assert (env.match.step_index, env.episode_seed, list(env.agents)) == before


@pytest.mark.parametrize("settings, words", [
    ({"preset": "fast"}, "preset = 'fast'"),
    ({"start": 3}, "start = 3"),
    ({"halves": 0}, "halves = 0"),
    ({"reward_fn": lambda truth: {}}, "reward_fn = "),
    ({"privileged": 1}, "privileged = 1"),
])
def test_bad_settings_are_refused(settings, words):
    with pytest.raises(MatchConfigError, match=words):
        parallel_env(1, 1, **settings)


# ---- rewards ----------------------------------------------------------------------------------


def _truth(ball=(0.0, 0.0), velocity=(0.0, 0.0), toucher=None, touched_s=None, time_s=10.0, goals=(), events=(),
           state=GameState.PLAYING) -> MatchTruth:
    robots = {"home_0": RobotTruth(-1.0, 0.0, 0.0, False, "home", 1), "away_0": RobotTruth(1.0, 0.0, math.pi, False,
                                                                                           "away", -1)}
    return MatchTruth(time_s, 0, state, 1, MappingProxyType({"home": 0, "away": 0}),
                      MappingProxyType({"home": 0, "away": 0}), goals, events,
                      BallTruth(*ball, 0.05, *velocity, toucher, touched_s), MappingProxyType(robots))


def test_ball_progress_counts_metres_toward_each_teams_goal_during_play_only():
    reward = BallProgress(per_metre=2.0)
    reward.reset(_truth(ball=(0.0, 0.0)))
    assert reward(_truth(ball=(0.1, 0.3))) == pytest.approx({"home_0": 0.2, "away_0": -0.2})
    throw_in = (MatchEvent(10.0, EventKind.THROW_IN, {}),)
    assert reward(_truth(ball=(2.0, 0.0), events=throw_in)) == {"home_0": 0.0, "away_0": 0.0}
    assert reward(_truth(ball=(0.0, 0.0))) == {"home_0": 0.0, "away_0": 0.0}  # a jump: placed, not kicked
    assert reward(_truth(ball=(0.1, 0.0), state=GameState.READY)) == {"home_0": 0.0, "away_0": 0.0}


def test_possession_goes_to_the_team_that_touched_last():
    reward = Possession(per_second=1.0)
    reward.reset(_truth(time_s=10.0))
    assert reward(_truth(time_s=10.04)) == {"home_0": 0.0, "away_0": 0.0}
    assert reward(_truth(time_s=10.08, toucher="away_0", touched_s=10.06)) == pytest.approx(
        {"home_0": -0.04, "away_0": 0.04})


def test_shots_credit_a_touch_toward_the_goal_once():
    reward = Shots(points=1.0)
    reward.reset(_truth())
    on_target = _truth(ball=(1.0, 0.2), velocity=(1.5, 0.1), toucher="home_0", touched_s=9.9)
    assert reward(on_target) == {"home_0": 1.0, "away_0": 0.0}
    assert reward(on_target) == {"home_0": 0.0, "away_0": 0.0}  # the same touch
    wide = _truth(ball=(1.0, 0.2), velocity=(1.0, 1.0), toucher="home_0", touched_s=9.95)
    own_goal_way = _truth(ball=(1.0, 0.0), velocity=(-1.5, 0.0), toucher="home_0", touched_s=9.97)
    assert reward(wide)["home_0"] == reward(own_goal_way)["home_0"] == 0.0
    assert reward(_truth(ball=(-1.0, 0.0), velocity=(-2.0, 0.0), toucher="away_0", touched_s=9.99))["away_0"] == 1.0


def test_weighted_adds_terms_and_refuses_bad_ones():
    reward = Weighted((1.0, Goals()), (0.5, BallProgress()))
    reward.reset(_truth())
    assert reward(_truth(ball=(0.2, 0.0), goals=("away",))) == pytest.approx({"home_0": -0.9, "away_0": 0.9})
    with pytest.raises(MatchConfigError, match="Weighted term"):
        Weighted((1.0, "goals"))
    with pytest.raises(MatchConfigError, match="weight = nan"):
        Weighted((float("nan"), Goals()))


class _Broken:
    def __init__(self, value):
        self.value = value

    def reset(self, truth):
        pass

    def __call__(self, truth):
        return {"home_0": self.value}


@pytest.mark.parametrize("value, words", [(float("nan"), "nan"), ("1", "'1'"), (True, "True")])
def test_a_reward_that_is_not_a_finite_number_is_an_error(value, words):
    env = parallel_env(1, 1, preset="learning", reward_fn=_Broken(value))
    env.reset(seed=0)
    with pytest.raises(RewardError, match=rf"'home_0'.*{words}.*expected a finite number"):
        env.step({})
    env.close()


def test_goals_as_a_reward_function_equal_the_envs_rewards_and_truth_stays_out_of_observations():
    quick = MatchConfig(referee=RefereeConfig(half_seconds=5.0, initial_seconds=0.2, ready_seconds=0.4,
                                              set_seconds=0.2, shootout=False))
    plain = parallel_env(2, 2, config=quick)
    shaped = parallel_env(2, 2, config=quick, privileged=True, reward_fn=Weighted((1.0, Goals()), (0.0, Shots())))
    flat = flat_layout(plain.observation_space("home_0"), radio=True)
    first = [e.reset(seed=9)[0] for e in (plain, shaped)]
    totals = [dict.fromkeys(plain.possible_agents, 0.0) for _ in range(2)]
    for step in range(40):
        if step == 25:
            for e in (plain, shaped):
                e.match.world.place_ball(-2.9, 0.1, vx=-1.0)  # into the blue goal: the away team scores
        results = [e.step({}) for e in (plain, shaped)]
        for total, result in zip(totals, results):
            for agent, reward in result[1].items():
                total[agent] += reward
        for agent in plain.possible_agents:
            observed = [result[0][agent] for result in results]
            assert np.array_equal(observed[0]["image"], observed[1]["image"]), step
            assert np.array_equal(flat.flatten(observed[0]), flat.flatten(observed[1])), step
    assert totals[0] == totals[1] == {"home_0": -1.0, "home_1": -1.0, "away_0": 1.0, "away_1": 1.0}
    assert set(first[1]["home_0"]) == set(first[0]["home_0"])
    for e in (plain, shaped):
        e.close()


def test_pose_estimates_are_rewarded_by_their_error_and_bad_ones_refused():
    env = PoseEstimates(parallel_env(1, 1, preset="learning", start="random"), position_weight=1.0,
                        heading_weight=0.5)
    env.reset(seed=3)
    truth = env.unwrapped.truth()
    home, away = truth.robots["home_0"], truth.robots["away_0"]
    stand = make_action()
    _, rewards, *_ = env.step({"home_0": {"action": stand, "pose": (home.x, home.y, home.theta)},
                               "away_0": {"action": stand, "pose": (away.x + 1.0, away.y, away.theta + 0.2)}})
    assert rewards["home_0"] == pytest.approx(0.0, abs=1e-9)
    assert rewards["away_0"] == pytest.approx(-(1.0 + 0.5 * 0.2), abs=1e-6)
    assert env.action_space("home_0")["pose"].shape == (3,)
    step_index = env.unwrapped.match.step_index
    with pytest.raises(InvalidActionError, match=r"'away_0'.*'pose'"):
        env.step({"home_0": {"action": stand, "pose": (0.0, 0.0, 0.0)},
                  "away_0": {"action": stand, "pose": (float("nan"), 0.0, 0.0)}})
    assert env.unwrapped.match.step_index == step_index
    env.close()


def test_pettingzoo_api_tests_on_learning_episodes_with_shaped_rewards():
    reward = Weighted((1.0, Goals()), (0.5, BallProgress()), (0.1, Possession()), (0.5, Shots()))
    env = parallel_env(1, 1, preset="learning", half_seconds=3.0, start="random", reward_fn=reward)
    parallel_api_test(env, num_cycles=120)
    env.close()
    aec = env_module.env(1, 1, preset="learning", half_seconds=2.0, start="penalty", reward_fn=reward)
    api_test(aec, num_cycles=60)
    aec.close()
