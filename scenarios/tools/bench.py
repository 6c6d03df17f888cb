"""The project's own benchmark: what one camera frame and one control step cost.

Each benchmark is a named function in :data:`BENCHMARKS` that gets the number of timed
repeats and returns flat metrics (``<name>_ms_median``, ``<name>_ms_p90``, ...); they are
merged, with a description of the machine, into ``bench.json``. Add a benchmark by
appending to :data:`BENCHMARKS`. Times are wall-clock (``time.perf_counter``), measured
after a warm-up; quote medians (docs/design/performance.md section 6). :func:`compare_results` sets two
runs' figures side by side (``robotstadium bench --compare``).
"""

from __future__ import annotations

import contextlib
import logging
import math
import multiprocessing
import os
import platform
import sys
import time
from collections.abc import Callable, Iterator, Mapping, Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING

import numba
import numpy as np
import pybullet as pb

from agents.vision.head_scan import SCAN_PITCH_RAD
from scenarios.common.io import write_json
from scenarios.common.untrusted import SmallFileError, load_json, read_small_file
from scenarios.tools.world_demo import FORMATION, team_roster
from world.camera_model import NAO_CAMERA, world_to_camera
from world.field import Pose2D
from world.motions import Motion
from world.camera_profiles import DEFAULT_CAMERA_PROFILE
from world.config import RenderConfig, WorldConfig
from world.raster.threads import parallel_cameras
from world.world import World

if TYPE_CHECKING:
    from match.controllers import ProcessControllers
    from match.game import Match

log = logging.getLogger(__name__)

DEFAULT_REPEATS = 200
QUICK_REPEATS = 20
RENDER_WARMUP = 10
RENDER_BLOCK = 10
"""Frames one renderer draws before the other takes its turn: each is timed in its own steady state (its
data in the processor's caches, as in a match, where one renderer draws every frame), and both within the
same minute of the machine's load."""
PHYSICS_WARMUP = 25
SETTLE_STEPS = 5


@dataclass(frozen=True)
class Benchmark:
    """A named measurement: ``run(repeats)`` returns its metrics as a flat dict of numbers."""

    name: str
    description: str
    run: Callable[[int], dict[str, float]]


# ---- robot camera frame -------------------------------------------------------------------

RENDER_VIEWER = "home_1"
RENDER_VIEWER_POSE = Pose2D(-2.2, 0.0, 0.0)
"""Just in front of the blue goal area, facing the field (+x)."""

RENDER_OTHERS: dict[str, tuple[float, float]] = {
    "home_0": (1.2, 17.0),
    "away_2": (3.8, 9.0),
    "home_3": (2.0, 3.5),
    "away_0": (4.5, -1.5),
    "away_1": (2.8, -6.0),
    "away_3": (3.4, -11.0),
    "home_2": (1.5, -17.5),
}
"""Other robots as (distance m, bearing deg CCW) from the viewer: 1.2-4.5 m ahead, inside its
46 deg field of view, at bearings far enough apart that none hides another."""

RENDER_BALL = (0.9, 0.0)
"""The ball, (distance m, bearing deg) from the viewer, in front of everybody."""

RENDER_HEAD_YAWS_RAD = tuple(math.radians(0.2 * k) for k in range(-3, 4))
"""The viewer's head turns through these, one per frame (one control step apart), so that every frame
is seen from a new camera pose, as in a match: the world keeps the analytic hall of its last few
camera poses, and a camera that never moved would be timed without drawing it."""


def setup_render_scene(world: World) -> None:
    """Viewer near its own goal area, head pitched 17 deg down, the 7 others in its view.

    Raises :class:`RuntimeError` if the pinhole model puts any other robot's torso centre
    or ground point outside the image, so the benchmark always renders all robots.
    """
    viewer = RENDER_VIEWER_POSE
    c, s = math.cos(viewer.theta), math.sin(viewer.theta)

    def field_point(distance_m: float, bearing_deg: float) -> tuple[float, float]:
        ahead, left = distance_m * math.cos(math.radians(bearing_deg)), distance_m * math.sin(math.radians(bearing_deg))
        return viewer.x + c * ahead - s * left, viewer.y + s * ahead + c * left

    world.place_robot(RENDER_VIEWER, viewer)
    for robot_id, (distance_m, bearing_deg) in RENDER_OTHERS.items():
        x, y = field_point(distance_m, bearing_deg)
        world.place_robot(robot_id, Pose2D(x, y, math.atan2(viewer.y - y, viewer.x - x)))
    world.place_ball(*field_point(*RENDER_BALL))
    world.set_head(RENDER_VIEWER, 0.0, SCAN_PITCH_RAD)
    world.step(SETTLE_STEPS)
    check_all_in_view(world, RENDER_VIEWER, list(RENDER_OTHERS))


def check_all_in_view(world: World, viewer: str, others: Sequence[str]) -> None:
    """Raise :class:`RuntimeError` unless every robot of ``others`` projects into ``viewer``'s image."""
    rotation, position = world.camera_pose(viewer)
    outside = []
    for robot_id in others:
        truth = world.robot_truth(robot_id)
        points = np.array([[truth.pose.x, truth.pose.y, truth.z_m], [truth.pose.x, truth.pose.y, 0.0]])
        pixels = NAO_CAMERA.project(world_to_camera(points, rotation, position))
        if not NAO_CAMERA.in_image(pixels).all():
            where = f"({truth.pose.x:.2f}, {truth.pose.y:.2f})"
            outside.append(f"{robot_id} at {where} -> pixels {pixels.round(1).tolist()}")
    if outside:
        raise RuntimeError(f"render benchmark: robots outside {viewer}'s camera image: {'; '.join(outside)}")


RENDER_VARIANTS: dict[str, tuple[str, str]] = {
    "": ("numba", "clean"),
    "_tiny": ("tiny", "clean"),
    "_profiled": ("numba", DEFAULT_CAMERA_PROFILE),
}
"""The frames the render benchmarks time (key suffix -> renderer, camera profile): each renderer's image as
drawn (the profile's pass is the same after either renderer, and timed on its own by
:func:`bench_camera_profiles`), and the compiled renderer's image through the default camera profile,
as a robot gets it."""


def bench_render(repeats: int) -> dict[str, float]:
    """One 160x120 robot camera frame with all 8 robots in the scene and 7 of them in view, each from a
    new camera pose (:data:`RENDER_HEAD_YAWS_RAD`; the head's turn and the control step are not timed),
    in turns of :data:`RENDER_BLOCK` frames: by the compiled renderer (``render``), by the reference
    renderer, TinyRenderer with the analytic hall (``render_*_tiny``), and by the compiled renderer
    through the default camera profile (``render_*_profiled``); see :data:`RENDER_VARIANTS`."""
    with _render_scenes() as worlds:
        samples = {suffix: np.empty(repeats) for suffix in worlds}
        for suffix, i in _turns(tuple(worlds), RENDER_WARMUP + repeats):
            world = worlds[suffix]
            world.set_head(RENDER_VIEWER, RENDER_HEAD_YAWS_RAD[i % len(RENDER_HEAD_YAWS_RAD)], SCAN_PITCH_RAD)
            world.step(1)
            start = time.perf_counter()
            world.render_camera(RENDER_VIEWER)
            if i >= RENDER_WARMUP:
                samples[suffix][i - RENDER_WARMUP] = (time.perf_counter() - start) * 1e3
    metrics: dict[str, float] = {}
    for suffix, values in samples.items():
        metrics.update(_suffixed(summarize("render", values), suffix))
    metrics["render_tiny_over_numba_ratio"] = metrics["render_ms_median_tiny"] / metrics["render_ms_median"]
    return metrics


@contextlib.contextmanager
def _render_scenes() -> Iterator[dict[str, World]]:
    """The scene of :func:`setup_render_scene` in a world of each of :data:`RENDER_VARIANTS` (key suffix ->
    world), closed after."""
    worlds: dict[str, World] = {}
    try:
        for suffix, (renderer, profile) in RENDER_VARIANTS.items():
            worlds[suffix] = World(team_roster(), WorldConfig(render=RenderConfig(renderer=renderer),
                                                              camera_profile=profile))
            setup_render_scene(worlds[suffix])
        yield worlds
    finally:
        for world in worlds.values():
            world.close()


def _turns(names: tuple[str, ...], count: int) -> Iterator[tuple[str, int]]:
    """``(name, i)`` for ``i`` in ``range(count)`` of each name, the names taking turns by blocks of
    :data:`RENDER_BLOCK` frames."""
    for first in range(0, count, RENDER_BLOCK):
        for name in names:
            for i in range(first, min(first + RENDER_BLOCK, count)):
                yield name, i


def _suffixed(metrics: dict[str, float], suffix: str) -> dict[str, float]:
    return {f"{key}{suffix}": value for key, value in metrics.items()}


def bench_cameras(repeats: int) -> dict[str, float]:
    """Every robot's camera frame of one step (8 cameras, :meth:`World.render_cameras`) in the scene of
    :func:`bench_render`, each step from new head angles, in turns of :data:`RENDER_BLOCK` steps: by the
    compiled renderer on numba's threads (``cameras_per_step``), on one thread (``*_serial``), by the
    reference renderer (``*_tiny``), and on numba's threads through the default camera profile
    (``*_profiled``)."""
    variants = {"": ("", True), "_serial": ("", False), "_tiny": ("_tiny", None), "_profiled": ("_profiled", True)}
    with _render_scenes() as worlds:
        samples = {suffix: np.empty(repeats) for suffix in variants}
        for suffix, i in _turns(tuple(variants), RENDER_WARMUP + repeats):
            scene, parallel = variants[suffix]
            world = worlds[scene]
            for robot in world.robot_ids:
                world.set_head(robot, RENDER_HEAD_YAWS_RAD[i % len(RENDER_HEAD_YAWS_RAD)], SCAN_PITCH_RAD)
            world.step(1)
            if world.compiled_renderer is not None:
                world.compiled_renderer.parallel = parallel
            start = time.perf_counter()
            for _ in world.render_cameras(world.robot_ids):
                pass
            if i >= RENDER_WARMUP:
                samples[suffix][i - RENDER_WARMUP] = (time.perf_counter() - start) * 1e3
    metrics: dict[str, float] = {}
    for suffix, values in samples.items():
        metrics.update(_suffixed(summarize("cameras_per_step", values), suffix))
    metrics["cameras_per_step_threads"] = float(numba.config.NUMBA_NUM_THREADS if parallel_cameras() else 1)
    return metrics


# ---- physics control step -----------------------------------------------------------------

WALK_CYCLE: tuple[Motion, ...] = (Motion.FORWARD, Motion.TURN_LEFT_40, Motion.FORWARD, Motion.TURN_RIGHT_40)


class _Walkers:
    """Keeps every robot walking: the next motion of its cycle starts when one finishes."""

    def __init__(self, world: World):
        self.world = world
        self.next_index = {rid: i for i, rid in enumerate(world.robot_ids)}  # staggered phases

    def command(self) -> None:
        for rid, i in self.next_index.items():
            if self.world.motion_status(rid).current is None:
                self.world.command_motion(rid, WALK_CYCLE[i % len(WALK_CYCLE)])
                self.next_index[rid] = i + 1


def bench_physics_step(repeats: int) -> dict[str, float]:
    """One control step (40 ms, 5 physics substeps) with 8 walking robots and a rolling ball."""
    with World(team_roster()) as world:
        for robot_id, pose in FORMATION.items():
            world.place_robot(robot_id, pose)
        world.place_ball(0.0, 0.0, vx=0.4, vy=0.3)
        walkers = _Walkers(world)
        samples = time_ms(world.step, repeats, PHYSICS_WARMUP, before=walkers.command)
    return summarize("physics_step", samples)


# ---- environment step and a whole match ---------------------------------------------------

ENV_WARMUP = 10
QUICK_START = {"initial_seconds": 0.2, "ready_seconds": 0.4, "set_seconds": 0.2}
"""Referee pauses shortened so that the timed steps are mostly PLAYING."""


def bench_env(repeats: int) -> dict[str, float]:
    """``env.step`` with 8 agents, all cameras on, random valid actions; beside it, in the same
    run and on the same world, the rendering and physics alone (``World.step`` + 8 frames);
    then, on the same env, ``env.step`` with every camera off (``env_step_cameras_off``); then
    ``env.step`` with all cameras on again, drawn by the reference renderer (``env_step_*_tiny``)."""
    env = _bench_env_instance()
    try:
        env.reset(seed=0)
        world = env.match.world
        robots = env.match.agent_names

        def render_and_physics() -> None:
            world.step()
            for robot in robots:
                world.render_camera(robot)

        env_ms, raw_ms = np.empty(repeats), np.empty(repeats)
        for i in range(ENV_WARMUP + repeats):
            actions = _random_actions(env)
            start = time.perf_counter()
            env.step(actions)
            middle = time.perf_counter()
            render_and_physics()
            end = time.perf_counter()
            if i >= ENV_WARMUP:
                env_ms[i - ENV_WARMUP], raw_ms[i - ENV_WARMUP] = (middle - start) * 1e3, (end - middle) * 1e3
            if not env.agents:
                env.reset(seed=i)

        off_actions: dict = {}

        def draw_cameras_off() -> None:
            if not env.agents:
                env.reset(seed=ENV_WARMUP + repeats)
            off_actions.clear()
            off_actions.update(_random_actions(env, cameras_on=False))

        off_ms = time_ms(lambda: env.step(off_actions), repeats, ENV_WARMUP, before=draw_cameras_off)
    finally:
        env.close()
    metrics = {**summarize("env_step", env_ms), **summarize("render_physics_only", raw_ms),
               **summarize("env_step_cameras_off", off_ms)}
    metrics["env_steps_per_s"] = 1e3 / metrics["env_step_ms_median"]
    metrics["env_steps_per_s_cameras_off"] = 1e3 / metrics["env_step_cameras_off_ms_median"]
    metrics["render_physics_only_steps_per_s"] = 1e3 / metrics["render_physics_only_ms_median"]
    metrics["env_over_render_physics_ratio"] = metrics["env_step_ms_median"] / metrics["render_physics_only_ms_median"]
    return {**metrics, **_bench_env_tiny(repeats)}


def _time_random_steps(view, env, repeats: int) -> np.ndarray:
    """``repeats`` timings (ms) of ``view.step`` with random valid actions of ``env`` (the env under the view,
    every camera on), drawn before each step and not timed; a finished episode starts again; ``env`` is closed
    after."""
    actions: dict = {}

    def draw_actions() -> None:
        if not view.agents:
            view.reset(seed=1)
        actions.clear()
        actions.update(_random_actions(env))

    try:
        view.reset(seed=0)
        return time_ms(lambda: view.step(actions), repeats, ENV_WARMUP, before=draw_actions)
    finally:
        env.close()


def _bench_env_instance(renderer: str = "numba"):
    """The benchmarks' env: 8 agents, short pauses before the kick-off, cameras drawn by ``renderer``."""
    from match import parallel_env
    from match.game import MatchConfig
    from match.referee import RefereeConfig

    world = WorldConfig(render=RenderConfig(renderer=renderer))
    return parallel_env(config=MatchConfig(referee=RefereeConfig(**QUICK_START), world=world))


def _random_actions(env, cameras_on: bool = True) -> dict:
    """Random valid actions for every agent of ``env``, each camera on (top or bottom) or every one off."""
    actions = {a: env.action_space(a).sample() for a in env.agents}
    for action in actions.values():
        action["camera"] = 1 + action["camera"] % 2 if cameras_on else 0  # top or bottom, or none
    return actions


def _bench_env_tiny(repeats: int) -> dict[str, float]:
    """``env.step`` as :func:`bench_env` times it (all cameras on) with the reference renderer
    (``env_step_*_tiny``)."""
    env = _bench_env_instance(renderer="tiny")
    step_ms = _time_random_steps(env, env, repeats)
    metrics = _suffixed(summarize("env_step", step_ms), "_tiny")
    metrics["env_steps_per_s_tiny"] = 1e3 / metrics["env_step_ms_median_tiny"]
    return metrics


VEC_ENVS = 2  # PettingZoo envs in SuperSuit's vector env, one per worker process
VEC_WARMUP = 10
ACTION_POOL = 16  # batches of random actions drawn before the timing, used in turn


def bench_vec_env(repeats: int) -> dict[str, float]:
    """Env steps per second under SuperSuit's vector env (``concat_vec_envs_v1``): two 8-agent envs in two
    worker processes (the default start method), random valid actions, with every camera on and with every
    camera off; ``repeats`` vector steps each (one vector step steps both envs)."""
    try:
        import supersuit
    except ImportError:
        log.warning("vec_env benchmark skipped: SuperSuit is not installed (pip install -e '.[test]')")
        return {}
    from gymnasium.vector.utils import concatenate, create_empty_array

    from match import parallel_env
    from match.game import MatchConfig
    from match.referee import RefereeConfig

    metrics: dict[str, float] = {}
    for cameras_on, suffix in ((True, ""), (False, "_cameras_off")):
        env = parallel_env(config=MatchConfig(referee=RefereeConfig(**QUICK_START)))
        agents = len(env.possible_agents)
        vector = supersuit.concat_vec_envs_v1(supersuit.pettingzoo_env_to_vec_env_v1(env), VEC_ENVS,
                                              num_cpus=VEC_ENVS, base_class="gymnasium")
        try:
            space = vector.action_space
            space.seed(0)
            pool = []
            for _ in range(ACTION_POOL):
                actions = [space.sample() for _ in range(vector.num_envs)]
                for action in actions:
                    action["camera"] = 1 + action["camera"] % 2 if cameras_on else 0
                pool.append(concatenate(space, actions, create_empty_array(space, vector.num_envs)))
            vector.reset(seed=0)
            samples = np.empty(repeats)
            for i in range(VEC_WARMUP + repeats):
                start = time.perf_counter()
                vector.step(pool[i % ACTION_POOL])
                if i >= VEC_WARMUP:
                    samples[i - VEC_WARMUP] = (time.perf_counter() - start) * 1e3
        finally:
            vector.close()
            env.close()
        metrics.update(summarize(f"vec_env_step{suffix}", samples))
        metrics[f"vec_env_steps_per_s{suffix}"] = VEC_ENVS * 1e3 / float(np.mean(samples))
        metrics[f"vec_env_agent_steps_per_s{suffix}"] = agents * metrics[f"vec_env_steps_per_s{suffix}"]
    return metrics


LEARNER_VIEWS = ("flat", "image", "percepts")  # the learners' observation views timed by bench_learner_views


def bench_learner_views(repeats: int) -> dict[str, float]:
    """``env.step`` through each learner view (``FlatObservations``, ``ImageObservations``,
    ``PerceptObservations``): 8 agents, random actions, every camera on (``learner_view_<view>_*``), and the
    percepts view's step over the plain env's (``learner_view_percepts_over_env_ratio``)."""
    from agents.learning import PerceptObservations
    from match.wrappers import FlatObservations, ImageObservations

    wrappers = {"flat": FlatObservations, "image": ImageObservations, "percepts": PerceptObservations}
    metrics: dict[str, float] = {}
    plain_ms = None
    for name in (None, *LEARNER_VIEWS):
        raw = _bench_env_instance()
        step_ms = _time_random_steps(raw if name is None else wrappers[name](raw), raw, repeats)
        if name is None:
            plain_ms = float(np.median(step_ms))
            continue
        metrics.update(summarize(f"learner_view_{name}_step", step_ms))
        metrics[f"learner_view_{name}_steps_per_s"] = 1e3 / metrics[f"learner_view_{name}_step_ms_median"]
    metrics["learner_view_percepts_over_env_ratio"] = metrics["learner_view_percepts_step_ms_median"] / plain_ms
    return metrics


BROADCAST_WARMUP = 5


def bench_broadcast(repeats: int) -> dict[str, float]:
    """The env's ``render()``: the 640x480 broadcast view with its score bar, 8 robots on the field after
    20 steps of random actions."""
    from match import parallel_env
    from match.game import MatchConfig
    from match.referee import RefereeConfig

    env = parallel_env(config=MatchConfig(referee=RefereeConfig(**QUICK_START)), render_mode="rgb_array")
    try:
        env.reset(seed=0)
        for _ in range(20):
            env.step({a: env.action_space(a).sample() for a in env.agents})
        samples = time_ms(env.render, repeats, BROADCAST_WARMUP)
    finally:
        env.close()
    metrics = summarize("broadcast_render", samples)
    metrics["broadcast_render_fps"] = 1e3 / metrics["broadcast_render_ms_median"]
    return metrics


def bench_match(repeats: int) -> dict[str, float]:
    """Simulated seconds per wall second of an 8-robot match with the default policies in their default
    controller processes, as the match command plays it (``2 * repeats`` control
    steps from the kick-off), and its peak resident memory (MiB).

    The match is played in a fresh process (``spawn``), so ``peak_rss_simulator_mb`` is the peak of a
    simulator process that played only this match (interpreter, imports, world, match), not of the
    benchmarks before it. ``peak_rss_controllers_mb`` sums the controller processes' peaks, read just
    before the run closes them; ``peak_rss_mb`` is the sum of the two. The memory keys are left out where the system does
    not report them (Linux does).
    """
    with ProcessPoolExecutor(max_workers=1, mp_context=multiprocessing.get_context("spawn")) as pool:
        metrics = pool.submit(play_bench_match, repeats).result()
    log.info("match: %.0f steps, %.2fx real time, peak resident memory %s MiB", metrics["match_steps"],
             metrics["match_real_time_factor"], f"{metrics['peak_rss_mb']:.0f}" if "peak_rss_mb" in metrics else "?")
    return metrics


def play_bench_match(repeats: int) -> dict[str, float]:
    """The match of :func:`bench_match`, in this process: its real-time factor, steps and peak memory (MiB)."""
    from match.controllers import ControllerLimits, ProcessControllers
    from match.game import Match
    from match.runner import run_match
    from scenarios.matches.play import Lineup, match_config

    config = match_config()
    config = replace(config, referee=replace(config.referee, **QUICK_START))
    match = Match(config)
    try:
        controllers = Lineup().controllers(match.agents, ControllerLimits())
        assert isinstance(controllers, ProcessControllers)  # limits given: controller processes
        stop = _StopAfter(2 * repeats, controllers)
        summary = run_match(config, controllers, seed=0, progress=False, match=match, observer=stop)
    finally:
        match.close()
    metrics: dict[str, float] = {"match_real_time_factor": summary.real_time_factor, "match_steps": summary.steps}
    simulator_mb = own_peak_resident_mb()
    if simulator_mb is not None and stop.controllers_peak_mb is not None:
        metrics.update(peak_rss_mb=simulator_mb + stop.controllers_peak_mb,
                       peak_rss_simulator_mb=simulator_mb, peak_rss_controllers_mb=stop.controllers_peak_mb)
    else:
        log.warning("match benchmark: this system does not report peak memory; no peak_rss keys")
    return metrics


class _StopAfter:
    """A match observer that ends the run after ``steps`` steps, reading the controller processes' peak
    resident memory (MiB) first: the run closes them when it ends."""

    def __init__(self, steps: int, controllers: ProcessControllers):
        self.steps = steps
        self.controllers = controllers
        self.played = 0
        self.controllers_peak_mb: float | None = None

    def decided(self, match: Match, actions: Mapping[str, object]) -> None:
        self.played += 1

    def done(self, match: Match) -> bool:
        if self.played < self.steps:
            return False
        self.controllers_peak_mb = self.controllers.peak_resident_mb()
        return True


def own_peak_resident_mb() -> float | None:
    """This process's peak resident memory since it started, in MiB (``ru_maxrss``: KiB on Linux, bytes on
    macOS), None where the system does not say."""
    try:
        import resource
    except ImportError:  # Windows
        return None
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    if peak <= 0:
        return None
    return peak / 2**20 if sys.platform == "darwin" else peak / 1024


MEMORY_MAX_MATCHES = 20
MEMORY_MIN_MATCHES = 3
MEMORY_MATCH_STEPS = 50  # control steps of each match (2 s, mostly PLAYING with the quick start)


def bench_memory(repeats: int) -> dict[str, float]:
    """Whether memory stays flat over consecutive matches in one process: a match per 10 repeats
    (:data:`MEMORY_MIN_MATCHES` to :data:`MEMORY_MAX_MATCHES`), each built anew, of
    :data:`MEMORY_MATCH_STEPS` steps with the default policies in this process, played in a fresh
    process (``spawn``); the resident memory (MiB) after the first, the second and the last, and
    the growth from the second to the last as a share of the second (``rss_growth_share``: the
    first two matches fill what the process builds once, such as lazily made tables). Left out
    where the system does not report resident memory (Linux does)."""
    matches = min(MEMORY_MAX_MATCHES, max(MEMORY_MIN_MATCHES, repeats // 10))
    with ProcessPoolExecutor(max_workers=1, mp_context=multiprocessing.get_context("spawn")) as pool:
        resident = pool.submit(play_memory_matches, matches).result()
    if resident is None:
        log.warning("memory benchmark: this system does not report resident memory; no rss keys")
        return {}
    first, second, last = resident[0], resident[1], resident[-1]
    log.info("memory: %.0f, %.0f and %.0f MiB after the first, the second and the last of %d matches", first,
             second, last, matches)
    return {"memory_matches": float(matches), "rss_first_match_mb": first, "rss_second_match_mb": second,
            "rss_last_match_mb": last, "rss_growth_share": (last - second) / second}


def play_memory_matches(matches: int) -> list[float] | None:
    """The matches of :func:`bench_memory`, in this process: the resident memory (MiB) after each."""
    import gc

    from match.protocol.ids import roster
    from match.runner import run_match
    from scenarios.matches.play import Lineup, match_config
    from world.process_memory import resident_mb

    config = match_config()
    config = replace(config, referee=replace(config.referee, **QUICK_START))
    resident: list[float] = []
    for seed in range(matches):
        policies = Lineup().policies(roster(config.home_players, config.away_players))
        run_match(config, policies, seed=seed, progress=False, max_steps=MEMORY_MATCH_STEPS)
        del policies
        gc.collect()
        mb = resident_mb(os.getpid())
        if mb is None:
            return None
        resident.append(mb)
    return resident


AGENT_WARMUP_STEPS = 10
AGENT_ROBOT = "home_1"


def bench_agent(repeats: int) -> dict[str, float]:
    """The team agent's ``act`` playing ``home_1`` in an 8-robot match (the others scripted):
    its cost on steps without a new camera frame and on steps with one (vision and
    localization); ``repeats`` of each after a warm-up. A step's cost is its ``act`` and its
    ``think`` (where the agent sees the step's frame, :class:`~match.protocol.Thinker`)."""
    from agents.team.agent import TeamAgent
    from match.game import Match
    from scenarios.matches.play import Lineup, match_config

    config = match_config()
    config = replace(config, referee=replace(config.referee, **QUICK_START))
    match = Match(config)
    try:
        policies = Lineup().policies(match.agents)
        for agent_id, policy in policies.items():
            policy.reset(agent_id, 0)
        agent = TeamAgent()
        agent.reset(AGENT_ROBOT, 0)
        observations = match.reset(0)
        with_frame: list[float] = []
        without: list[float] = []
        for step in range(40 * repeats + AGENT_WARMUP_STEPS):
            if min(len(with_frame), len(without)) >= repeats:
                break
            actions = {a: policies[a].act(observations[a]) for a in match.agent_names if a != AGENT_ROBOT}
            start = time.perf_counter()
            actions[AGENT_ROBOT] = agent.act(observations[AGENT_ROBOT])
            agent.think()
            elapsed_ms = (time.perf_counter() - start) * 1e3
            if step >= AGENT_WARMUP_STEPS:
                framed = int(observations[AGENT_ROBOT]["camera"]) != 0
                (with_frame if framed else without).append(elapsed_ms)
            observations = match.step(actions).observations
    finally:
        match.close()
    metrics = summarize("agent_act", np.array(without[:repeats]))
    metrics.update(summarize("agent_act_frame", np.array(with_frame[:repeats])))
    return metrics


# ---- camera profiles -------------------------------------------------------------------------

PROFILE_HEAD_RATE_RADPS = 1.0
"""The viewer's head turns at this rate between the two frames of the profile benchmark (a head scan's pace):
about 190 px/s of image motion, so a few pixels of blur and of rolling-shutter shear."""


def bench_camera_profiles(repeats: int) -> dict[str, float]:
    """Each camera profile's pass over a recorded 160x120 frame (:meth:`CameraEffects.apply`: the image motion
    from the camera pose of the frame before, one control step earlier while the head turns, the per-frame
    draws, the compiled pass), ``camera_profile_ms_*_<profile>``; the frame is rendered once in the scene of
    :func:`bench_render`."""
    from world.camera_profiles import CAMERA_PROFILES, CameraEffects, CameraPose

    with World(team_roster(), WorldConfig()) as world:
        setup_render_scene(world)
        before = world.camera_pose(RENDER_VIEWER)
        world.set_head(RENDER_VIEWER, PROFILE_HEAD_RATE_RADPS * world.config.physics.control_step_s, SCAN_PITCH_RAD)
        world.step(1)
        after = world.camera_pose(RENDER_VIEWER)
        frame = world.render_camera(RENDER_VIEWER).copy()
    step_s = world.config.physics.control_step_s
    metrics: dict[str, float] = {}
    for name, profile in CAMERA_PROFILES.items():
        effects = CameraEffects(profile, np.random.default_rng(0))
        first, second = CameraPose(0.0, "top", *before), CameraPose(step_s, "top", *after)

        def still() -> None:  # untimed: the frame before, from which the timed one moved
            effects.forget()
            effects.apply(RENDER_VIEWER, frame, first)

        samples = time_ms(lambda: effects.apply(RENDER_VIEWER, frame, second), repeats, RENDER_WARMUP, before=still)
        metrics.update(_suffixed(summarize("camera_profile", samples), f"_{name}"))
    return metrics


BENCHMARKS: tuple[Benchmark, ...] = (
    Benchmark("render", "robot camera frame, 160x120, 8 robots in the scene; beside it the reference renderer",
              bench_render),
    Benchmark("cameras", "all 8 camera frames of a step: on numba's threads, on one, and by the reference renderer",
              bench_cameras),
    Benchmark("physics_step", "World.step(): one 40 ms control step, 8 walking robots + ball", bench_physics_step),
    Benchmark("env", "env.step(): 8 agents, random actions, all cameras on (and render+physics alone), then off",
              bench_env),
    Benchmark("vec_env", "SuperSuit's vector env, 2 envs of 8 agents in 2 processes, cameras on and off",
              bench_vec_env),
    Benchmark("learner_views", "env.step() through the flat, image and percept views: 8 agents, all cameras on",
              bench_learner_views),
    Benchmark("broadcast", "env.render(): the 640x480 broadcast view, 8 robots", bench_broadcast),
    Benchmark("match", "an 8-robot match with the default policies in a fresh process, real-time factor and peak "
              "memory", bench_match),
    Benchmark("agent", "the team agent's act(): without and with a camera frame", bench_agent),
    Benchmark("memory", "consecutive short matches in one process: resident memory after the first, second and last",
              bench_memory),
    Benchmark("camera_profiles", "each camera profile's pass over a recorded 160x120 frame, the head turning",
              bench_camera_profiles),
)


# ---- running ------------------------------------------------------------------------------


def time_ms(
    fn: Callable[[], object], repeats: int, warmup: int, before: Callable[[], object] | None = None
) -> np.ndarray:
    """Wall-clock milliseconds of ``repeats`` calls of ``fn`` after ``warmup`` untimed ones.

    ``before`` runs untimed before every call (e.g. issuing commands).
    """
    samples = np.empty(repeats)
    for i in range(warmup + repeats):
        if before is not None:
            before()
        start = time.perf_counter()
        fn()
        elapsed = time.perf_counter() - start
        if i >= warmup:
            samples[i - warmup] = elapsed * 1e3
    return samples


def summarize(name: str, samples_ms: np.ndarray) -> dict[str, float]:
    return {
        f"{name}_ms_median": float(np.median(samples_ms)),
        f"{name}_ms_p90": float(np.percentile(samples_ms, 90)),
        f"{name}_ms_min": float(np.min(samples_ms)),
    }


def machine_info() -> dict[str, object]:
    """The machine as every match summary records it (:func:`match.runner.machine_description`), with the
    core count and the Python and pybullet versions."""
    from match.runner import machine_description

    return {**machine_description(), "cpu_count": os.cpu_count(), "python": platform.python_version(),
            "pybullet_api_version": pb.getAPIVersion(), "platform": platform.platform()}


def run_bench(out_dir: Path, repeats: int = DEFAULT_REPEATS, benchmarks: Sequence[Benchmark] = BENCHMARKS) -> dict:
    """Run ``benchmarks`` with ``repeats`` timed repeats each; write and return ``bench.json``."""
    if isinstance(repeats, bool) or not isinstance(repeats, int) or repeats < 1:
        raise ValueError(f"repeats must be a positive integer; got {repeats!r}")
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    results: dict = {"repeats": repeats}
    for benchmark in benchmarks:
        log.info("benchmark %s: %s (%d repeats)", benchmark.name, benchmark.description, repeats)
        metrics = benchmark.run(repeats)
        log.debug("benchmark %s: %s", benchmark.name, metrics)
        results.update(metrics)
    results["machine"] = machine_info()
    path = write_json(out_dir / "bench.json", results, allow_nan=True)
    log.info("wrote %s", path)
    return results


TABLE_STATS = ("median", "p90", "min")


def format_table(results: dict) -> str:
    """The metrics of ``results`` as a plain-text table: timings (ms) first, then other numbers."""
    rows = [("benchmark", *(f"{stat} ms" for stat in TABLE_STATS))]
    for key in results:
        if "_ms_median" not in key:
            continue
        name, suffix = key.split("_ms_median", 1)  # a variant's figures end in its suffix: render_ms_median_tiny
        cells = [results.get(f"{name}_ms_{stat}{suffix}") for stat in TABLE_STATS]
        rows.append((name + suffix, *("-" if value is None else f"{value:.3f}" for value in cells)))
    widths = [max(len(row[i]) for row in rows) for i in range(len(rows[0]))]
    lines = ["  ".join([row[0].ljust(widths[0]), *(c.rjust(w) for c, w in zip(row[1:], widths[1:]))]) for row in rows]
    lines.insert(1, "  ".join("-" * w for w in widths))
    for key, value in results.items():
        if key != "repeats" and "_ms_" not in key and isinstance(value, (int, float)) and not isinstance(value, bool):
            lines.append(f"{key}: {value:.3f}")
    lines.append(f"repeats: {results.get('repeats')}")
    return "\n".join(lines)


def format_comparison(rows: Sequence[Comparison], old_label: str) -> str:
    """``rows`` of :func:`compare_results` as a plain-text table (new, old, new/old, which way is worse,
    the mark), then how many are worse and better than ``old_label``."""
    table = [("key", "new", "old", "new/old", "worse if", "")]
    for row in rows:
        ratio = "-" if row.ratio is None else f"{row.ratio:.3f}"
        table.append((row.key, f"{row.new:.3f}", f"{row.old:.3f}", ratio, row.worse_when or "-", row.mark))
    widths = [max(len(line[i]) for line in table) for i in range(len(table[0]))]
    lines = ["  ".join([line[0].ljust(widths[0]), *(c.rjust(w) for c, w in zip(line[1:5], widths[1:5])),
                        line[5]]).rstrip() for line in table]
    lines.insert(1, "  ".join("-" * w for w in widths[:5]))
    worse, better = (sum(row.mark == mark for row in rows) for mark in ("worse", "better"))
    lines.append(f"against {old_label}: {worse} worse, {better} better by more than {COMPARE_THRESHOLD:.0%}")
    return "\n".join(lines)


# ---- comparing two runs -------------------------------------------------------------------

COMPARE_THRESHOLD = 0.10
"""A row is marked worse (better) when its ratio new/old is worse (better) by more than this fraction."""
HIGHER, LOWER = "higher", "lower"
COMPARE_FILE = "compare.json"
MAX_BENCH_FILE_BYTES = 1_000_000  # a bench.json is a few kB


class BenchFileError(ValueError):
    """A bench.json to compare with that cannot be read or holds no benchmark figures."""


@dataclass(frozen=True)
class Comparison:
    """One key of two runs: the new and old values, ``ratio`` new/old (None: the old value is 0),
    ``worse_when`` (:data:`HIGHER`, :data:`LOWER` or None: no direction) and ``mark``
    (``"worse"``, ``"better"`` or ``""``)."""

    key: str
    new: float
    old: float
    ratio: float | None
    worse_when: str | None
    mark: str


def worse_when(key: str) -> str | None:
    """Which way ``key`` gets worse: memory (``peak_rss*``, ``rss_*``) and times (``_ms_``) :data:`HIGHER`,
    rates (``_per_s``, ``_fps``, ``real_time_factor``) :data:`LOWER`; None for other numbers (counts, ratios)."""
    if key.startswith(("peak_rss", "rss_")) or "_ms_" in key:
        return HIGHER
    if "_per_s" in key or "_fps" in key or "real_time_factor" in key:
        return LOWER
    return None


def _number(value: object) -> float | None:
    """``value`` as a float if it is a finite number (not a bool), else None."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        return None
    return float(value)


def compare_results(new: Mapping[str, object], old: Mapping[str, object],
                    threshold: float = COMPARE_THRESHOLD) -> list[Comparison]:
    """Every key holding a finite number in both ``new`` and ``old`` (in ``new``'s order), with its ratio
    new/old and a mark: ``"worse"`` when the ratio is beyond ``1 + threshold`` in the worse direction
    (:func:`worse_when`; below ``1 - threshold`` for rates), ``"better"`` beyond it the other way. Keys
    in one of them only, and keys of no direction, get no mark."""
    rows = []
    for key, value in new.items():
        new_value, old_value = _number(value), _number(old.get(key))
        if new_value is None or old_value is None:
            continue
        ratio = new_value / old_value if old_value != 0 else None
        direction = worse_when(key)
        mark = ""
        if ratio is not None and direction is not None:
            higher, lower = ratio > 1 + threshold, ratio < 1 - threshold
            if higher or lower:
                mark = "worse" if (higher if direction == HIGHER else lower) else "better"
        rows.append(Comparison(key, new_value, old_value, ratio, direction, mark))
    return rows


_JSON_NAMES = {list: "an array", str: "a string", int: "a number", float: "a number", bool: "a boolean",
               type(None): "null"}


def read_bench_file(path: Path) -> dict:
    """The results of a ``bench.json``: a regular file of at most :data:`MAX_BENCH_FILE_BYTES`, a JSON object
    with at least one benchmark figure (a finite number under a key :func:`worse_when` knows);
    :class:`BenchFileError` naming ``path`` otherwise."""
    expected = "expected a bench.json of robotstadium bench, a JSON object with figures such as render_ms_median"
    path = Path(path)
    name = _shown(str(path))
    try:  # not a regular file, too big, nested too deep, not UTF-8, not JSON
        results = load_json(read_small_file(path, MAX_BENCH_FILE_BYTES))
    except SmallFileError as error:
        raise BenchFileError(f"{name}: {error.reason}; {expected}") from None
    if not isinstance(results, dict):
        raise BenchFileError(f"{name}: {_JSON_NAMES.get(type(results), 'a JSON value')}, not an object; {expected}")
    if not any(worse_when(key) is not None and _number(value) is not None for key, value in results.items()):
        raise BenchFileError(f"{name}: no benchmark figure; {expected}")
    return results


def _shown(text: str) -> str:
    """``text`` as a message shows a path: at most 60 characters."""
    return text if len(text) <= 60 else text[:57] + "..."


def write_comparison(out_dir: Path, rows: Sequence[Comparison], old_path: Path) -> Path:
    """Write ``compare.json``: the file compared with, the threshold, every row, and the keys marked worse
    and better."""
    document = {
        "old": str(old_path),
        "threshold": COMPARE_THRESHOLD,
        "rows": {row.key: {"new": row.new, "old": row.old, "ratio": row.ratio, "worse_when": row.worse_when,
                           "mark": row.mark} for row in rows},
        "worse": [row.key for row in rows if row.mark == "worse"],
        "better": [row.key for row in rows if row.mark == "better"],
    }
    path = write_json(Path(out_dir) / COMPARE_FILE, document)
    log.info("wrote %s", path)
    return path
