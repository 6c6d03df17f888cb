"""The env's PettingZoo conventions: independent copies, the global state, seeding, closing, AEC factories."""

from __future__ import annotations

import copy
import gc
import pickle
import warnings
from functools import partial

import numpy as np
import pytest
from gymnasium import spaces
from pettingzoo import AECEnv
from pettingzoo.test import api_test, max_cycles_test, parallel_seed_test, render_test, state_test
from pettingzoo.utils.conversions import parallel_to_aec_wrapper

import match.env as env_module
from match import RobotStadiumEnv, parallel_env, raw_env
from match.env_state import state_labels, state_space
from match.errors import EnvClosedError, MatchConfigError, StepRefusedError
from match.game import MatchConfig
from match.protocol import GameState, Motion, make_action
from match.protocol.ids import roster
from match.referee import RefereeConfig

pytestmark = pytest.mark.render

QUICK = RefereeConfig(half_seconds=1.0, initial_seconds=0.2, ready_seconds=0.4, set_seconds=0.2, shootout=False)
SMALL = {"home_players": 1, "away_players": 1, "config": MatchConfig(referee=QUICK)}


def small_env(**kwargs) -> RobotStadiumEnv:
    return parallel_env(**{**SMALL, **kwargs})


def small_aec(**kwargs) -> AECEnv:
    return env_module.env(**{**SMALL, **kwargs})


@pytest.fixture(scope="module")
def shared():
    """One 1 v 1 env for the tests that reset it with their own seed first (building a world takes ~1 s)."""
    env = small_env()
    yield env
    env.close()


def _playing(env: RobotStadiumEnv) -> None:
    while env.match.referee.state is not GameState.PLAYING:
        env.step({})


def _flat(value, prefix=""):
    if isinstance(value, dict):
        for key in sorted(value):
            yield from _flat(value[key], f"{prefix}/{key}")
    elif isinstance(value, (list, tuple)):
        for i, item in enumerate(value):
            yield from _flat(item, f"{prefix}/{i}")
    else:
        yield prefix, value


def _byte_equal(a, b) -> bool:
    """Same keys, and every leaf the same type, dtype, shape and bytes."""
    flat_a, flat_b = list(_flat(a)), list(_flat(b))
    if [k for k, _ in flat_a] != [k for k, _ in flat_b]:
        return False
    for (_, x), (_, y) in zip(flat_a, flat_b):
        if type(x) is not type(y):
            return False
        if isinstance(x, np.ndarray):
            if x.dtype != y.dtype or x.shape != y.shape or x.tobytes() != y.tobytes():
                return False
        elif isinstance(x, bytes | str) or x is None:
            if x != y:
                return False
        elif np.asarray(x).tobytes() != np.asarray(y).tobytes():
            return False
    return True


# ---- copies -------------------------------------------------------------------------


def test_match_config_pickles():
    config = MatchConfig(home_players=2, away_players=3, referee=QUICK)
    assert pickle.loads(pickle.dumps(config)) == config


def test_copies_have_their_own_worlds():
    """pickle, deepcopy and copy each give a new env with the same settings: stepping, closing or collecting
    one leaves the others alone."""
    original = small_env(max_cycles=77, privileged=True)
    original.reset(seed=3)
    _playing(original)
    copies = {
        "pickle": pickle.loads(pickle.dumps(original)),
        "deepcopy": copy.deepcopy(original),
        "copy": copy.copy(original),
    }
    clients = {original.match.world.client, *(twin.match.world.client for twin in copies.values())}
    assert len(clients) == 4
    walk = {"home_0": make_action(Motion.WALK, walk=(0.2, 0.0, 0.0)), "away_0": make_action()}
    for name, twin in copies.items():
        assert (twin.max_cycles, twin.privileged, twin.possible_agents) == (77, True, ["home_0", "away_0"]), name
        assert twin.match.config == original.match.config, name
        with pytest.raises(StepRefusedError, match="call reset"):  # a copy is a new env, not a snapshot
            twin.step({})
        twin.reset(seed=3)
        twin_before = twin.state()
        for _ in range(5):
            original.step(walk)
        assert np.array_equal(twin.state(), twin_before), name  # the original's steps do not move the copy
        original_time, original_state = original.match.world.time_s, original.state()
        for _ in range(5):
            twin.step({})
        assert original.match.world.time_s == original_time, name
        assert np.array_equal(original.state(), original_state), name
    copies["pickle"].close()
    del copies
    gc.collect()
    _, _, terminations, _, _ = original.step(walk)  # the original's world is still open
    assert terminations == {"home_0": False, "away_0": False}
    assert original.state().shape == (19,)
    original.close()


def test_a_copy_plays_its_own_matches():
    """A copy lies on its own stream: neither its seeded nor its unseeded resets repeat the original's."""
    walk = {
        "home_0": make_action(Motion.WALK, walk=(0.2, 0.0, 0.3)),
        "away_0": make_action(Motion.WALK, walk=(0.2, 0.0, -0.3)),
    }

    def trajectory(env: RobotStadiumEnv, seed: int | None) -> list[np.ndarray]:
        env.reset(seed=seed)
        _playing(env)
        states = []
        for _ in range(15):
            env.step(walk)
            states.append(env.state())
        return states

    original = small_env()
    original.reset(seed=8)
    twin = copy.deepcopy(original)
    for seed in (None, 9):
        original_run, twin_run = trajectory(original, seed), trajectory(twin, seed)
        assert not all(np.array_equal(a, b) for a, b in zip(original_run, twin_run)), seed
    replay = small_env(stream=twin.stream)  # the copy's stream, built anew: the copy's match again
    assert all(np.array_equal(a, b) for a, b in zip(trajectory(replay, 9), twin_run))
    for env in (original, twin, replay):
        env.close()


# ---- global state -------------------------------------------------------------------


def test_state_layout_and_space(shared):
    env = shared
    assert isinstance(env.state_space, spaces.Box)
    assert env.state_space.shape == (19,) and env.state_space.dtype == np.float32
    labels = state_labels(env.possible_agents)
    assert labels[:11] == ("game_state", "half", "seconds_remaining", "score_home", "score_away", "shootout_home",
                           "shootout_away", "ball_x", "ball_y", "ball_vx", "ball_vy")
    assert labels[11:] == ("home_0/x", "home_0/y", "home_0/theta", "home_0/fallen",
                           "away_0/x", "away_0/y", "away_0/theta", "away_0/fallen")
    env.reset(seed=0)
    state = env.state()
    assert state.shape == (19,) and state.dtype == np.float32 and env.state_space.contains(state)
    value = dict(zip(labels, state.tolist()))
    truth = env.match.truth()
    assert value["game_state"] == float(env.match.state) and value["half"] == 1.0
    assert value["seconds_remaining"] == pytest.approx(1.0)
    for agent in env.possible_agents:
        x, y, theta = truth["robots"][agent]["pose"]
        pose = (value[f"{agent}/x"], value[f"{agent}/y"], value[f"{agent}/theta"])
        assert pose == pytest.approx((x, y, theta), abs=1e-6)
        assert value[f"{agent}/fallen"] == float(truth["robots"][agent]["fallen"])
    assert state_space([str(a) for a in roster(4, 3)]).shape == (11 + 4 * 7,)


def test_state_follows_the_ball_and_the_score(shared):
    env = shared
    env.reset(seed=2)
    _playing(env)
    labels = state_labels(env.possible_agents)
    env.match.world.place_ball(0.5, -0.4, vx=1.0, vy=0.5)
    value = dict(zip(labels, env.state().tolist()))
    ball = (value["ball_x"], value["ball_y"], value["ball_vx"], value["ball_vy"])
    assert ball == pytest.approx((0.5, -0.4, 1.0, 0.5), abs=1e-3)
    assert value["game_state"] == float(GameState.PLAYING)
    env.step({})
    assert dict(zip(labels, env.state().tolist()))["ball_x"] > 0.52
    env.match.world.place_ball(-2.9, 0.1, vx=-1.0)  # into the blue goal: the away team scores
    for _ in range(20):
        env.step({})
    value = dict(zip(labels, env.state().tolist()))
    assert (value["score_home"], value["score_away"]) == (0.0, 1.0)


def test_pettingzoo_state_test():
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # state_test only warns about a doubtful state: make that fail
        state_test(small_aec(), small_env(), num_cycles=10)


# ---- conventions --------------------------------------------------------------------


@pytest.fixture
def no_display(monkeypatch):
    """pygame draws into memory: the CI machine has no display."""
    pytest.importorskip("pygame", reason="the human extra (pygame) is not installed")
    monkeypatch.setenv("SDL_VIDEODRIVER", "dummy")


def test_human_render_mode_shows_the_broadcast_view(no_display):
    import pygame

    env = small_env(render_mode="human")
    assert env.metadata["render_modes"] == ["human", "rgb_array"]
    env.reset(seed=0)
    assert env.render() is None and pygame.display.get_surface().get_size() == (640, 480)
    env.step({})
    pixels = pygame.surfarray.array3d(pygame.display.get_surface()).transpose(1, 0, 2)
    twin = small_env(render_mode="rgb_array")
    twin.reset(seed=0)
    twin.step({})
    assert np.array_equal(pixels, twin.render())  # the window shows the rgb_array frame
    env.close()
    assert pygame.display.get_surface() is None
    twin.close()
    with pytest.raises(MatchConfigError, match=r"'ansi'.*\['human', 'rgb_array'\]"):
        small_env(render_mode="ansi")


def test_render_takes_the_mode_as_rllibs_adapter_passes_it():
    env = small_env(render_mode="rgb_array")
    env.reset(seed=0)
    assert env.render(None).shape == env.render("rgb_array").shape == (480, 640, 3)
    with pytest.raises(MatchConfigError, match="render_mode"):
        env.render("human")
    pettingzoo_env = pytest.importorskip("ray.rllib.env.wrappers.pettingzoo_env", reason="the ray extra: RLlib")
    adapted = pettingzoo_env.ParallelPettingZooEnv(env)
    assert adapted.render().shape == (480, 640, 3)
    adapted.close()


def test_aec_factories_and_envs_built_alike_sample_alike():
    raw = raw_env(**SMALL)
    assert isinstance(raw, parallel_to_aec_wrapper) and isinstance(raw.unwrapped, RobotStadiumEnv)
    wrapped = small_aec()
    assert isinstance(wrapped, AECEnv) and not isinstance(wrapped, parallel_to_aec_wrapper)
    assert isinstance(wrapped.unwrapped, RobotStadiumEnv) and wrapped.state_space == raw.state_space
    for agent in raw.possible_agents:  # action spaces seeded at construction
        assert _byte_equal(raw.action_space(agent).sample(), wrapped.action_space(agent).sample())
    assert not _byte_equal(raw.action_space("home_0").sample(), raw.action_space("away_0").sample())
    raw.close()
    wrapped.close()


def test_reset_keeps_the_seeds_a_user_gave_the_action_spaces(shared):
    env = shared
    space = env.action_space("home_0")
    space.seed(123)
    expected = [space.sample() for _ in range(3)]
    space.seed(123)
    env.reset(seed=0)
    env.reset(seed=5)
    env.reset()
    assert _byte_equal([space.sample() for _ in range(3)], expected)


def test_no_step_after_the_end_and_no_time_passes(shared):
    env = shared
    env.reset(seed=0)
    while env.agents:
        _, _, terminations, truncations, _ = env.step({a: make_action(camera=0) for a in env.agents})
    assert all(terminations.values()) and not any(truncations.values())
    time_s, state = env.match.world.time_s, env.state()
    with pytest.raises(StepRefusedError, match="call reset"):
        env.step({a: make_action() for a in env.possible_agents})
    assert env.match.world.time_s == time_s and np.array_equal(env.state(), state)


def test_closed_env_refuses_with_typed_errors():
    env = small_env(render_mode="rgb_array")
    env.reset(seed=0)
    env.close()
    env.close()  # harmless
    with pytest.raises(EnvClosedError, match="reset"):
        env.reset(seed=0)
    with pytest.raises(StepRefusedError, match="closed"):
        env.step({})
    with pytest.raises(EnvClosedError, match="state"):
        env.state()
    with pytest.raises(EnvClosedError, match="render"):
        env.render()
    assert env.agents == []
    twin = copy.deepcopy(env)  # a closed env still copies: a new env with its settings
    twin.reset(seed=0)
    assert twin.render().shape == (480, 640, 3)
    twin.close()


# ---- PettingZoo's own checks --------------------------------------------------------


def test_pettingzoo_parallel_seed_test():
    parallel_seed_test(partial(small_env, privileged=True), num_cycles=50)


def test_pettingzoo_max_cycles_test_on_the_module():
    max_cycles_test(env_module)  # match.env has parallel_env, env and raw_env; 4 v 4, four cycles


def test_pettingzoo_render_test(no_display):
    render_test(small_aec)


def test_pettingzoo_api_test_on_the_aec_env():
    env = small_aec()
    api_test(env, num_cycles=60)
    env.close()


def test_same_seed_same_seeded_actions_same_observations_for_200_steps():
    envs = [small_env(privileged=True) for _ in range(2)]
    results = [env.reset(seed=21) for env in envs]
    assert _byte_equal(results[0], results[1])
    for env in envs:
        for i, agent in enumerate(env.possible_agents):
            env.action_space(agent).seed(100 + i)
    for step in range(200):
        if not envs[0].agents:
            results = [env.reset(seed=step) for env in envs]
        else:
            results = [env.step({a: env.action_space(a).sample() for a in env.agents}) for env in envs]
        assert _byte_equal(results[0], results[1]), f"diverged at step {step}"
        assert np.array_equal(envs[0].state(), envs[1].state())
    for env in envs:
        env.close()
