"""The learners' views of the env: image-only and flat observations, discrete actions, percepts.

Each is checked on its own, with gymnasium's vector utilities on its spaces, and under SuperSuit:
its image wrappers and its vector envs, two worker processes started with the spawn start
method, after which the parent env still works.
"""

from __future__ import annotations

import math
import multiprocessing as mp
import pickle

import numpy as np
import pytest
from gymnasium import spaces
from gymnasium.vector import VectorEnv
from gymnasium.vector.utils import (
    batch_space,
    concatenate,
    create_empty_array,
    create_shared_memory,
    iterate,
    read_from_shared_memory,
    write_to_shared_memory,
)

from agents.learning import PERCEPT_LABELS, PerceptObservations, percept_space
from match import RobotStadiumEnv, parallel_env
from match.errors import InvalidActionError, MatchConfigError, StepRefusedError, UnknownAgentError
from match.game import MatchConfig
from match.protocol import Action, CameraChoice, GameState, Motion, make_action, parse_action
from match.referee import RefereeConfig
from match.wrappers import (
    DEFAULT_HEADS,
    ActionSet,
    DiscreteActions,
    FlatObservations,
    ImageObservations,
    flat_layout,
)

pytestmark = pytest.mark.render

QUICK = RefereeConfig(half_seconds=1.0, initial_seconds=0.2, ready_seconds=0.4, set_seconds=0.2, shootout=False)
SMALL = {"home_players": 1, "away_players": 1, "config": MatchConfig(referee=QUICK)}
LOOK = {"home_0": make_action(head=(0.0, 0.3), camera=1), "away_0": make_action(head=(0.0, 0.3), camera=0)}
TOP_ONLY = ActionSet(cameras=(CameraChoice.TOP,))


def small_env(**kwargs) -> RobotStadiumEnv:
    return parallel_env(**{**SMALL, **kwargs})


@pytest.fixture(scope="module")
def shared():
    """One 1 v 1 env for the tests that reset it with their own seed first."""
    env = small_env()
    yield env
    env.close()


def _playing(env) -> None:
    while env.unwrapped.match.referee.state is not GameState.PLAYING:
        env.step({})


# ---- image and flat observations ---------------------------------------------------------


def test_image_observations_are_the_camera_images(shared):
    env = ImageObservations(shared)
    assert env.observation_space("home_0") == spaces.Box(0, 255, (120, 160, 3), np.uint8)
    with pytest.raises(UnknownAgentError, match="home_5"):
        env.observation_space("home_5")
    observations, _ = env.reset(seed=1)
    assert set(observations) == {"home_0", "away_0"} and observations["home_0"].shape == (120, 160, 3)
    for _ in range(3):
        observations, *_ = env.step(LOOK)
    assert env.observation_space("home_0").contains(observations["home_0"])
    assert observations["home_0"].std() > 5 and not observations["away_0"].any()


def test_flat_observations_follow_the_observation_dict(shared):
    env = FlatObservations(shared, scaled=False)
    labels = env.layout.labels
    assert len(labels) == 43 and env.observation_space("away_0").shape == (43,)
    assert "image" not in " ".join(labels) and "radio/data/0" not in labels
    twin = small_env()  # the same match unwrapped: its observation dicts
    env.reset(seed=2)
    twin.reset(seed=2)
    for _ in range(3):
        observations, *_ = env.step(LOOK)
        raw, *_ = twin.step(LOOK)
    vector = dict(zip(labels, observations["home_0"].tolist()))
    expected = raw["home_0"]
    for label, value in [("head/0", expected["head"][0]), ("head/1", expected["head"][1]),
                         ("accelerometer/2", expected["accelerometer"][2]), ("sonar/3", expected["sonar"][3]),
                         ("game/player", expected["game"]["player"]), ("game/score/1", expected["game"]["score"][1]),
                         ("camera", expected["camera"]), ("radio/count", expected["radio"]["count"]),
                         ("motion_elapsed_s", expected["motion_elapsed_s"]), ("fallen", expected["fallen"])]:
        assert vector[label] == float(np.float32(value)), label
    assert vector["camera"] == 1.0 and vector["accelerometer/2"] > 5.0
    assert env.observation_space("home_0").contains(observations["home_0"])
    twin.close()
    with_radio = flat_layout(shared.observation_space("home_0"), radio=True)
    assert len(with_radio.labels) == 43 + 8 + 8 + 8 * 128
    with pytest.raises(MatchConfigError, match="radio = 1"):
        FlatObservations(shared, radio=1)
    with pytest.raises(MatchConfigError, match="scaled = 'yes'"):
        FlatObservations(shared, scaled="yes")


def test_scaled_flat_observations_map_each_entry_onto_its_range(shared):
    scaled, raw = FlatObservations(shared), FlatObservations(shared, scaled=False)
    assert scaled.observation_space("home_0") == spaces.Box(-1.0, 1.0, (45,), np.float32)
    labels = scaled.labels
    assert labels.index("motion_remaining_s/endless") == labels.index("motion_remaining_s") + 1
    assert labels.index("game/seconds_since_drop_in/none") == labels.index("game/seconds_since_drop_in") + 1
    shared.reset(seed=2)
    _playing(shared)
    walk = {"home_0": make_action(Motion.WALK, walk=(0.1, 0.0, 0.0)), "away_0": make_action()}
    for _ in range(3):
        observations, *_ = shared.step(walk)
    vector = dict(zip(labels, scaled._convert("home_0", observations["home_0"]).tolist()))
    units = dict(zip(raw.labels, raw._convert("home_0", observations["home_0"]).tolist()))
    assert units["motion_remaining_s"] >= 1e6 and vector["motion_remaining_s/endless"] == 1.0
    assert vector["motion_remaining_s"] == -1.0
    assert units["game/seconds_since_drop_in"] >= 1e5 and vector["game/seconds_since_drop_in/none"] == 1.0
    assert vector["head/0"] == pytest.approx(-1.0 + 2.0 * (units["head/0"] + 2.0857) / (2 * 2.0857), abs=1e-3)
    assert vector["accelerometer/2"] == pytest.approx(units["accelerometer/2"] / 30.0, abs=1e-6)
    assert vector["game/player"] == -1.0 and vector["fallen"] == -1.0


# ---- discrete actions ----------------------------------------------------------------------


def test_discrete_action_spaces():
    env = small_env()
    multi = DiscreteActions(env)
    assert multi.action_space("home_0") == spaces.MultiDiscrete([13, 15, 3])
    radio = DiscreteActions(env, ActionSet(radio_symbols=3))
    assert radio.action_space("away_0") == spaces.MultiDiscrete([13, 15, 3, 4])
    flat = DiscreteActions(env, TOP_ONLY, flat=True)
    assert flat.action_space("home_0") == spaces.Discrete(13 * 15)
    twin = DiscreteActions(small_env())
    assert np.array_equal(multi.action_space("away_0").sample(), twin.action_space("away_0").sample())
    with pytest.raises(UnknownAgentError):
        multi.action_space("away_3")
    env.close()
    twin.close()


def test_a_choice_is_the_action_it_names():
    actions = ActionSet(radio_symbols=5)
    assert parse_action("home_0", actions.action((1, 2, 0, 0))) == Action(
        Motion.WALK, walk=(pytest.approx(0.2), 0.0, 0.0), head=tuple(pytest.approx(v) for v in DEFAULT_HEADS[2]),
        camera=CameraChoice.TOP, radio=b"")
    assert parse_action("home_0", actions.action((9, 0, 2, 5))).radio == bytes([5])
    assert parse_action("home_0", actions.action((9, 0, 2, 5))).motion is Motion.KICK_LEFT


@pytest.mark.parametrize(
    "changes, words",
    [
        ({"heads": ((0.0, 1.0),)}, "head"),
        ({"motions": ((Motion.FORWARD, (0.1, 0.0, 0.0)),)}, "motion"),
        ({"motions": ((Motion.WALK, (0.5, 0.0, 0.0)),)}, "motion"),
        ({"cameras": (1,)}, "camera"),
        ({"cameras": ()}, "cameras"),
        ({"radio_symbols": 256}, "radio_symbols = 256"),
        ({"radio_symbols": True}, "radio_symbols = True"),
    ],
)
def test_bad_action_sets_are_refused(changes, words):
    with pytest.raises(MatchConfigError, match=words):
        ActionSet(**changes)


def test_discrete_actions_drive_the_robots_and_the_radio():
    env = DiscreteActions(parallel_env(home_players=2, away_players=1, config=MatchConfig(referee=QUICK)),
                          ActionSet(radio_symbols=3))
    env.reset(seed=3)
    _playing(env)
    observations, *_ = env.step({"home_0": np.array([0, 4, 0, 3]), "home_1": [0, 0, 2, 0], "away_0": None})
    inbox = observations["home_1"]["radio"]
    assert int(inbox["count"]) == 1 and inbox["data"][0][: int(inbox["length"][0])].tobytes() == bytes([3])
    for _ in range(10):
        observations, *_ = env.step({"home_0": (np.int64(0), 4, 0, 0)})
    assert observations["home_0"]["head"][0] == pytest.approx(DEFAULT_HEADS[4][0], abs=0.05)
    assert observations["home_0"]["camera"] == 1
    env.close()


@pytest.mark.parametrize(
    "flat, bad",
    [
        (False, np.array([13, 0, 0])),
        (False, [0, 15, 0]),
        (False, [0, 0, -1]),
        (False, np.array([0.0, 0.0, 0.0])),
        (False, [0, 0]),
        (False, [True, 0, 0]),
        (False, 3),
        (True, 13 * 15 * 3),
        (True, -1),
        (True, 1.0),
        (True, np.array([1])),
    ],
)
def test_bad_choices_are_refused_before_anything_happens(shared, flat, bad):
    env = DiscreteActions(shared, flat=flat)
    env.reset(seed=4)
    time_s = shared.match.world.time_s
    with pytest.raises(InvalidActionError, match=r"'away_0'.*'action'") as raised:
        env.step({"home_0": env.action_space("home_0").sample(), "away_0": bad})
    assert raised.value.agent == "away_0"
    assert shared.match.world.time_s == time_s
    with pytest.raises(UnknownAgentError):
        env.step({"home_9": env.action_space("home_0").sample()})
    with pytest.raises(StepRefusedError, match="dict"):
        env.step([0, 0, 0])


# ---- percepts ------------------------------------------------------------------------------


def test_percepts_show_the_ball_and_the_landmarks_ahead():
    env = PerceptObservations(small_env(privileged=True))
    assert len(PERCEPT_LABELS) == 85 and env.observation_space("home_0") == percept_space()
    env.reset(seed=5)
    for _ in range(4):
        observations, _, _, _, infos = env.step(LOOK)
    percepts = dict(zip(PERCEPT_LABELS, observations["home_0"].tolist()))
    x, y, theta = infos["home_0"]["true_pose"]
    ball_x, ball_y = infos["home_0"]["ball"]["position"][:2]
    distance = math.hypot(ball_x - x, ball_y - y)
    bearing = math.remainder(math.atan2(ball_y - y, ball_x - x) - theta, math.tau)
    assert percepts["ball/seen"] == 1.0
    assert percepts["ball/distance"] == pytest.approx(distance, rel=0.1)
    assert percepts["ball/bearing"] == pytest.approx(bearing, abs=0.05)
    assert percepts["head_pitch"] == pytest.approx(0.3, abs=0.03) and percepts["camera"] == 1.0
    assert sum(percepts[name] for name in PERCEPT_LABELS if name.endswith("/seen") and name != "ball/seen") >= 2
    assert env.observation_space("home_0").contains(observations["home_0"])
    assert np.count_nonzero(observations["away_0"][3:]) == 0  # its camera is off
    twin = pickle.loads(pickle.dumps(env))
    twin_observations, _ = twin.reset(seed=5)
    for _ in range(4):
        twin_observations, *_ = twin.step(LOOK)
    assert np.array_equal(twin_observations["home_0"], observations["home_0"])  # a copy sees the same
    env.close()
    twin.close()


# ---- gymnasium's vector utilities on every view ---------------------------------------------

VIEWS = {
    "env": lambda env: env,
    "image": ImageObservations,
    "flat": FlatObservations,
    "flat_radio": lambda env: FlatObservations(env, radio=True),
    "discrete": lambda env: DiscreteActions(env, ActionSet(radio_symbols=2)),
    "discrete_flat": lambda env: DiscreteActions(env, flat=True),
    "percepts": PerceptObservations,
}


@pytest.mark.parametrize("view", VIEWS)
def test_gymnasium_vector_utilities_handle_every_view(shared, view):
    env = VIEWS[view](shared)
    for space in (env.observation_space("home_0"), env.action_space("home_0")):
        space.seed(7)
        samples = [space.sample() for _ in range(2)]
        batched = batch_space(space, 2)
        batch = concatenate(space, samples, create_empty_array(space, 2))
        assert batched.contains(batch)
        assert len(list(iterate(batched, batch))) == 2
        memory = create_shared_memory(space, n=2, ctx=mp.get_context("spawn"))
        for i, sample in enumerate(samples):
            write_to_shared_memory(space, i, sample, memory)
        shared_batch = read_from_shared_memory(space, memory, n=2)
        assert np.array_equal(spaces.flatten(batched, shared_batch), spaces.flatten(batched, batch))
        assert spaces.flatten_space(space).shape[0] > 0


# ---- SuperSuit ------------------------------------------------------------------------------

ss = pytest.importorskip("supersuit", reason="SuperSuit is in the test extra: pip install -e '.[test]'")


@pytest.fixture
def spawn():
    """The spawn start method for the test (the default on macOS and Windows, and on Linux from Python 3.14)."""
    before = mp.get_start_method(allow_none=True)
    mp.set_start_method("spawn", force=True)
    yield
    mp.set_start_method(before, force=True)


def _image_stack(env):
    return ss.frame_stack_v1(ss.resize_v1(ss.color_reduction_v0(DiscreteActions(ImageObservations(env), TOP_ONLY),
                                                                  "full"), 42, 32), 3)


CHAINS = {
    "env": (lambda env: env, 200),
    "image": (_image_stack, 40),
    "flat_discrete": (lambda env: DiscreteActions(FlatObservations(env), ActionSet(radio_symbols=2)), 40),
    "percepts_discrete": (lambda env: DiscreteActions(PerceptObservations(env), TOP_ONLY, flat=True), 40),
}


@pytest.mark.slow
@pytest.mark.parametrize("chain", CHAINS)
def test_supersuit_vector_envs_in_two_spawned_processes(spawn, chain):
    wrap, steps = CHAINS[chain]
    parent = small_env()
    view = wrap(parent)
    if chain == "image":
        assert view.observation_space("home_0").shape == (32, 42, 3)
    # Kept: gymnasium 1.2's VectorEnv.__del__ closes SuperSuit's Markov wrapper, and with it the env it wraps.
    markov = ss.pettingzoo_env_to_vec_env_v1(view)
    vector = ss.concat_vec_envs_v1(markov, 2, num_cpus=2, base_class="gymnasium")
    try:
        assert isinstance(vector, VectorEnv) and vector.num_envs == 4
        single_obs, single_act = vector.observation_space, vector.action_space
        single_act.seed(0)
        observations, _ = vector.reset(seed=0)
        assert batch_space(single_obs, 4).contains(observations)
        episodes = 0
        for _ in range(steps):
            actions = concatenate(single_act, [single_act.sample() for _ in range(4)], create_empty_array(single_act, 4))
            observations, rewards, terminations, truncations, _ = vector.step(actions)
            episodes += int(terminations[0] or truncations[0])
            assert rewards.shape == (4,) and batch_space(single_obs, 4).contains(observations)
    finally:
        vector.close()
    if chain == "env":
        assert episodes >= 1  # the quick 1 v 1 match ends within 200 steps: the vector env reset it
    observations, _ = view.reset(seed=1)  # the parent env works on
    view.step({a: view.action_space(a).sample() for a in view.agents})
    assert parent.state().shape == (19,)
    parent.close()
