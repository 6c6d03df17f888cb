"""Seeds that cannot collide: streams of copies, SuperSuit's and RLlib's vector envs, action spaces of copies.

The vector envs are built as a learner builds them, from a parent env that was reset before:
SuperSuit's process vector env (both start methods) and RLlib's multi-agent vector env in two
env runners that each receive the same pickled env creator (as Ray ships it) and are seeded as
RLlib seeds them (runner ``w`` with ``seed + w``, its sub-env ``j`` with ``seed + w + j``).
"""

from __future__ import annotations

import copy
import hashlib
import multiprocessing as mp
import pickle

import numpy as np
import pytest

from match import parallel_env
from match.errors import MatchConfigError
from match.protocol import CameraChoice, Motion
from match.wrappers import ActionSet, DiscreteActions, FlatObservations

pytestmark = pytest.mark.render

COPIES = 4
STEPS = 6
STILL = (0.0, 0.0, 0.0)
BLIND = ActionSet(motions=((Motion.STAND, STILL), (Motion.WALK, (0.2, 0.0, 0.0))), heads=((0.0, 0.3),),
                  cameras=(CameraChoice.OFF,))


def learner_env():
    """A 1 v 1 learner's view: flat observations, two choices (stand, walk), cameras off; random starts."""
    return DiscreteActions(FlatObservations(parallel_env(1, 1, preset="learning", start="random")), BLIND, flat=True)


def _digest(*arrays) -> str:
    return hashlib.sha256(b"".join(np.ascontiguousarray(a).tobytes() for a in arrays)).hexdigest()[:16]


# ---- streams --------------------------------------------------------------------------------


def test_a_standalone_env_plays_the_seed_it_is_given_and_copies_play_their_own():
    env = parallel_env(1, 1, preset="learning")
    env.reset(seed=7)
    assert env.stream == () and env.episode_seed == 7
    first, second = copy.deepcopy(env), pickle.loads(pickle.dumps(env))
    assert (first.stream, second.stream) == ((0,), (1,))
    assert copy.deepcopy(first).stream == (0, 0)
    seeds = [twin.reset(seed=7) and twin.episode_seed for twin in (first, second)]
    assert len({7, *seeds}) == 3
    again = parallel_env(1, 1, preset="learning", stream=(0,))
    again.reset(seed=7)
    assert again.episode_seed == seeds[0]  # a stream is reproducible: a copy's episodes can be replayed
    env.reset()
    first.reset()
    assert env.episode_seed != first.episode_seed  # unseeded: the copy does not repeat the original's next seed
    for each in (env, first, second, again):
        each.close()


def test_action_spaces_of_copies_sample_apart():
    env = learner_env()
    twins = [copy.deepcopy(env) for _ in range(3)]
    for agent in env.possible_agents:
        samples = [tuple(int(e.action_space(agent).sample()) for _ in range(16)) for e in (env, *twins)]
        assert len(set(samples)) == 4, agent
    raw = env.unwrapped
    raw_samples = {_digest(*(np.asarray(v) for v in raw.action_space("home_0").sample().values()))}
    for twin in twins:
        raw_samples.add(_digest(*(np.asarray(v) for v in twin.unwrapped.action_space("home_0").sample().values())))
    assert len(raw_samples) == 4
    for each in (env, *twins):
        each.close()


@pytest.mark.parametrize("seed", [-1, 2**64, 1.5, True, "3", np.float32(2.0)])
def test_bad_seeds_are_refused_before_anything_changes(seed):
    env = parallel_env(1, 1, preset="learning")
    env.reset(seed=3)
    env.step({})
    before = (env.match.step_index, env.episode_seed)
    with pytest.raises(MatchConfigError, match=r"seed = .*expected None or an integer"):
        env.reset(seed=seed)
    assert (env.match.step_index, env.episode_seed) == before
    env.close()


@pytest.mark.parametrize("stream", [(-1,), (2**32,), "0", (0.5,), (True,), tuple(range(33))])
def test_bad_streams_are_refused(stream):
    with pytest.raises(MatchConfigError, match="stream = "):
        parallel_env(1, 1, stream=stream)


# ---- vector envs of copies ---------------------------------------------------------------------


def _walks(count: int, agents: int) -> np.ndarray:
    """Every agent of every sub-env walks (choice 1): the trajectories differ only by their seeds."""
    return np.ones(count * agents, dtype=np.int64)


@pytest.fixture
def start_method(request):
    before = mp.get_start_method(allow_none=True)
    mp.set_start_method(request.param, force=True)
    yield request.param
    mp.set_start_method(before, force=True)


@pytest.mark.slow
@pytest.mark.parametrize("start_method", ["fork", "spawn"], indirect=True)
def test_supersuit_sub_envs_of_a_reset_parent_play_four_distinct_reproducible_trajectories(start_method):
    ss = pytest.importorskip("supersuit")
    parent = learner_env()
    parent.reset(seed=0)  # reset before vectorising: its copies must not repeat its sequence
    markov = ss.pettingzoo_env_to_vec_env_v1(parent)
    vector = ss.concat_vec_envs_v1(markov, COPIES, num_cpus=2, base_class="gymnasium")
    agents = len(parent.possible_agents)

    def trajectories(seed: int | None) -> list[str]:
        observations, _ = vector.reset(seed=seed)
        steps = [observations]
        for _ in range(STEPS):
            observations, *_ = vector.step(_walks(COPIES, agents))
            steps.append(observations)
        per_copy = np.stack(steps).reshape(len(steps), COPIES, agents, -1)
        return [_digest(per_copy[:, c]) for c in range(COPIES)]

    try:
        seeded = trajectories(5)
        assert len(set(seeded)) == COPIES, seeded
        assert trajectories(5) == seeded  # the same seed, the same four
        unseeded = trajectories(None)
        assert len(set(unseeded)) == COPIES and not set(unseeded) & set(seeded)
    finally:
        vector.close()
    parent.close()


def test_rllib_env_runners_of_a_reset_parent_play_four_distinct_reproducible_trajectories():
    cloudpickle = pytest.importorskip("cloudpickle")
    pettingzoo_env = pytest.importorskip("ray.rllib.env.wrappers.pettingzoo_env", reason="the ray extra: RLlib")
    sync = pytest.importorskip("ray.rllib.env.vector.sync_vector_multi_agent_env")
    parent = learner_env()
    parent.reset(seed=0)

    def creator():
        return pettingzoo_env.ParallelPettingZooEnv(copy.deepcopy(parent))

    shipped = cloudpickle.dumps(creator)  # Ray pickles the creator once and every runner loads the same bytes
    runners = {w: sync.SyncVectorMultiAgentEnv([cloudpickle.loads(shipped)] * 2) for w in (1, 2)}

    def trajectories(seed: int | None) -> list[str]:
        digests = []
        for w, vector in runners.items():
            observations, _ = vector.reset(seed=None if seed is None else seed + w)
            steps = [[observations]]
            for _ in range(STEPS):
                observations, *_ = vector.step([dict.fromkeys(o, 1) for o in observations])
                steps.append([observations])
            for j in range(2):
                digests.append(_digest(*(step[0][j][a] for step in steps for a in sorted(step[0][j]))))
        return digests

    try:
        seeded = trajectories(5)
        assert len(set(seeded)) == COPIES, seeded
        assert trajectories(5) == seeded
        unseeded = trajectories(None)
        assert len(set(unseeded)) == COPIES and not set(unseeded) & set(seeded)
    finally:
        for vector in runners.values():
            vector.close()
        parent.close()
