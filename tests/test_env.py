"""The PettingZoo parallel environment: API, spaces, validation, rewards, determinism."""

from __future__ import annotations

import numpy as np
import pytest
from pettingzoo.test import parallel_api_test

from match import RobotStadiumEnv, parallel_env
from match.errors import InvalidActionError, RadioPacketError, StepRefusedError, UnknownAgentError
from match.game import MatchConfig
from match.protocol import GameState, Motion, make_action
from match.referee import RefereeConfig

pytestmark = pytest.mark.render

QUICK = RefereeConfig(half_seconds=1.0, initial_seconds=0.2, ready_seconds=0.4, set_seconds=0.2, shootout=False)


def quick_env(home: int = 1, away: int = 1, **kwargs) -> RobotStadiumEnv:
    return parallel_env(home_players=home, away_players=away, config=MatchConfig(referee=QUICK), **kwargs)


def random_actions(env: RobotStadiumEnv, camera_on: bool = True) -> dict:
    actions = {a: env.action_space(a).sample() for a in env.agents}
    if camera_on:
        for action in actions.values():
            action["camera"] = 1 + action["camera"] % 2
    return actions


def test_parallel_api():
    env = quick_env()
    parallel_api_test(env, num_cycles=220)
    env.close()


def test_agents_spaces_and_metadata():
    env = parallel_env(home_players=2, away_players=3)
    assert env.metadata["name"] == "robotstadium_v0"
    assert env.possible_agents == ["home_0", "home_1", "away_0", "away_1", "away_2"]
    with pytest.raises(UnknownAgentError, match="home_3"):
        env.observation_space("home_3")
    env.close()
    with pytest.raises(ValueError, match="away players"):
        parallel_env(home_players=1, away_players=5)


def test_observations_stay_in_their_space():
    env = quick_env(2, 2)
    observations, _ = env.reset(seed=4)
    for _ in range(40):
        for agent, observation in observations.items():
            assert env.observation_space(agent).contains(observation), agent
        observations, *_ = env.step(random_actions(env, camera_on=False))
    env.close()


def test_camera_off_gives_zeros_and_on_gives_a_picture():
    env = quick_env()
    env.reset(seed=0)
    observations, *_ = env.step({"home_0": make_action(camera=0), "away_0": make_action(camera=1)})
    assert observations["home_0"]["camera"] == 0 and not observations["home_0"]["image"].any()
    assert observations["away_0"]["camera"] == 1 and observations["away_0"]["image"].std() > 5
    env.close()


@pytest.mark.parametrize(
    "action, error, words",
    [
        ({"head": [0.0, 3.0]}, InvalidActionError, "'head'"),
        ({"walk": [float("nan"), 0.0, 0.0], "motion": "walk"}, InvalidActionError, "'walk'"),
        ({"motion": 99}, InvalidActionError, "'motion'"),
        ({"camera": 7}, InvalidActionError, "'camera'"),
        ({"radio": b"x" * 129}, RadioPacketError, "128 bytes"),
        ({"radio": "text"}, RadioPacketError, "'radio'"),
        ({"radio": {"data": np.zeros(128, np.uint8), "length": 200}}, RadioPacketError, "'radio.length' = 200"),
        ({"kick": 1}, InvalidActionError, "'kick'"),
    ],
)
def test_bad_action_is_refused_and_nothing_is_applied(action, error, words):
    env = quick_env(2, 1)
    env.reset(seed=1)
    match = env.match
    before = (match.world.time_s, match.step_index, match.radio.counts.sent, match.world.motion_status("home_0").current)
    good = make_action(Motion.FORWARD, radio=b"hi")
    with pytest.raises(error, match=words) as raised:
        env.step({"home_0": good, "away_0": action})
    assert "away_0" in str(raised.value)
    after = (match.world.time_s, match.step_index, match.radio.counts.sent, match.world.motion_status("home_0").current)
    assert after == before
    env.close()


def test_unknown_agent_is_refused():
    env = quick_env()
    env.reset(seed=1)
    with pytest.raises(UnknownAgentError, match="home_7") as raised:
        env.step({"home_7": make_action()})
    assert isinstance(raised.value, StepRefusedError) and isinstance(raised.value, LookupError)
    env.close()


def _playing(env: RobotStadiumEnv) -> None:
    while env.match.referee.state is not GameState.PLAYING:
        env.step({})


def test_goal_rewards_each_robot_of_both_teams():
    env = quick_env(2, 2, privileged=True)
    env.reset(seed=2)
    _playing(env)
    env.match.world.place_ball(-2.9, 0.1, vx=-1.0)  # into the blue goal: the away team scores
    total = dict.fromkeys(env.possible_agents, 0.0)
    for _ in range(20):
        _, rewards, *_ = env.step({})
        for agent, reward in rewards.items():
            total[agent] += reward
    assert total == {"home_0": -1.0, "home_1": -1.0, "away_0": 1.0, "away_1": 1.0}
    assert env.match.score == {"home": 0, "away": 1}
    env.close()


def test_ground_truth_only_when_privileged():
    plain, privileged = quick_env(), quick_env(privileged=True)
    _, infos = plain.reset(seed=0)
    assert infos == {"home_0": {}, "away_0": {}}
    _, infos = privileged.reset(seed=0)
    assert len(infos["home_0"]["true_pose"]) == 3 and "ball" in infos["away_0"]
    plain.close()
    privileged.close()


def test_match_end_terminates_every_agent():
    env = quick_env()
    env.reset(seed=0)
    for _ in range(400):
        _, _, terminations, truncations, _ = env.step({a: make_action() for a in env.agents})
        if not env.agents:
            break
    assert env.agents == [] and all(terminations.values()) and not any(truncations.values())
    with pytest.raises(StepRefusedError, match="call reset"):
        env.step({})
    with pytest.raises(StepRefusedError, match="finished"):
        env.match.step({})
    env.close()


def test_truncation_at_max_cycles():
    env = quick_env(max_cycles=5)
    with pytest.raises(StepRefusedError, match="call reset"):
        env.step({})
    env.reset(seed=0)
    for _ in range(5):
        _, _, terminations, truncations, _ = env.step({a: make_action() for a in env.agents})
    assert all(truncations.values()) and not any(terminations.values()) and env.agents == []
    time_s = env.match.world.time_s
    with pytest.raises(StepRefusedError, match="call reset"):  # a truncated episode does not go on
        env.step({})
    assert env.match.world.time_s == time_s
    env.close()


def test_rgb_array_render_is_a_broadcast_view():
    env = quick_env(render_mode="rgb_array")
    env.reset(seed=0)
    frame = env.render()
    assert frame.shape == (480, 640, 3) and frame.dtype == np.uint8
    env.close()


def _flatten(value, prefix=""):
    if isinstance(value, dict):
        for key in sorted(value):
            yield from _flatten(value[key], f"{prefix}/{key}")
    elif isinstance(value, (list, tuple)):
        for i, item in enumerate(value):
            yield from _flatten(item, f"{prefix}/{i}")
    else:
        yield prefix, value


def _same(a, b) -> bool:
    flat_a, flat_b = list(_flatten(a)), list(_flatten(b))
    if [k for k, _ in flat_a] != [k for k, _ in flat_b]:
        return False
    return all(np.array_equal(np.asarray(x), np.asarray(y)) for (_, x), (_, y) in zip(flat_a, flat_b))


@pytest.mark.slow
def test_same_seed_same_actions_same_match_for_200_steps():
    envs = [parallel_env(home_players=2, away_players=2, privileged=True,
                         config=MatchConfig(referee=RefereeConfig(initial_seconds=0.2, ready_seconds=0.4, set_seconds=0.2)))
            for _ in range(2)]
    first = [env.reset(seed=11) for env in envs]
    assert _same(first[0], first[1])
    sampler = envs[0]
    for step in range(200):
        actions = random_actions(sampler)
        results = [env.step(actions) for env in envs]
        assert _same(results[0], results[1]), f"diverged at step {step}"
    assert envs[0].match.world.time_s == pytest.approx(8.0)
    for env in envs:
        env.close()
