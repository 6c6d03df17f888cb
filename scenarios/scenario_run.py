"""One run of a scenario: the simulation that yields its localization samples.

A run is independent given its seed (:meth:`ScenarioSpec.run_seeds`): the same task gives
the same samples, in whatever process it runs. Measured robots run
:class:`~agents.behavior.scan_localize.ScanLocalizeAgent` with every method of the
scenario side by side; after each of their localization events this harness (never the
agent) reads the true pose from the world, the thesis' GPS, and makes one
:class:`~scenarios.localization_run.LocalizationSample` per method.

Without a referee the robots stand on the bare world (no ball, the game state always
PLAYING); with the referee it is a :class:`~match.game.Match` with kick-offs, goals,
half-time and robots replaced, and the other robots play the scripted policy.
"""

from __future__ import annotations

import dataclasses
import logging
import math
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

from agents.behavior.scan_localize import LocalizationEvent, ScanLocalizeAgent
from agents.behavior.scripted import ScriptedPlayer
from match.game import Match, MatchConfig
from match.observations import build_observation, game_observation, radio_observation
from match.protocol import MOTIONS, CameraChoice, make_action
from match.protocol.game_control import GameControlView, GameState, KickOff, SecondaryState
from match.protocol.ids import AgentId, Side
from scenarios.localization_run import LocalizationSample
from scenarios.scenario_spec import Policy, ScenarioSpec
from world.config import RobotSpec, WorldConfig
from world.field import FIELD, GoalColor, Pose2D
from world.motions import Motion, MotionNoise
from world.teams import TeamColor
from world.world import World

log = logging.getLogger(__name__)

RANDOM_START_MARGIN_M = 0.5  # random start poses are drawn this far inside the field lines
OFF_FIELD_BALL = (0.0, 3.0)  # without a referee the ball waits on the carpet beyond the side line

_PLAYING = GameControlView(
    GameState.PLAYING, SecondaryState.NORMAL, KickOff.NONE, 0, 0, 0, 0, 600.0, 1, TeamColor.BLUE, GoalColor.BLUE
)

SampleCallback = Callable[[int], None]  # called with the run index after every sample of a run


@dataclass(frozen=True)
class RunTask:
    """What one run needs: the scenario, the run's index and seed, and how many samples it takes."""

    spec: ScenarioSpec
    run: int
    seed: int
    samples: int


@dataclass(frozen=True)
class RunOutcome:
    """The samples of one run (one per method per localization event) and its costs.

    ``complete`` is False when the run ended (time limit, end of the match) short of its
    samples.
    """

    run: int
    seed: int
    samples: tuple[LocalizationSample, ...]
    sim_seconds: float
    wall_seconds: float
    complete: bool

    @property
    def events(self) -> int:
        """Localization events the run recorded (each gives one sample per method)."""
        return len({(s.robot, s.event) for s in self.samples})


class _Stand:
    """The ``stand`` policy: stand still, camera off."""

    def act(self, observation: dict) -> dict:
        return make_action(Motion.STAND, camera=CameraChoice.OFF)


def run_tasks(spec: ScenarioSpec) -> tuple[RunTask, ...]:
    """The runs of a scenario, in order."""
    return tuple(
        RunTask(spec, run, seed, samples)
        for run, (seed, samples) in enumerate(zip(spec.run_seeds(), spec.run_samples()))
    )


def simulate_run(task: RunTask, on_sample: SampleCallback | None = None) -> RunOutcome:
    """Simulate one run until it has ``task.samples`` localization events of measured robots."""
    started = time.perf_counter()
    if task.spec.referee:
        samples, sim_seconds, complete = _run_match(task, on_sample)
    else:
        samples, sim_seconds, complete = _run_bare(task, on_sample)
    outcome = RunOutcome(task.run, task.seed, tuple(samples), sim_seconds, time.perf_counter() - started, complete)
    if not complete:
        log.warning("run %d ended with %d of %d samples after %.0f s simulated", task.run, outcome.events,
                    task.samples, sim_seconds)
    return outcome


def world_config(spec: ScenarioSpec) -> WorldConfig:
    """The world of a scenario: the default one with its motion noise scaled."""
    noise = MotionNoise()
    scale = spec.motion_noise_scale
    scaled = {f.name: getattr(noise, f.name) * scale for f in dataclasses.fields(MotionNoise)}
    return WorldConfig(motion_noise=MotionNoise(**scaled))


# ---- the bare world ------------------------------------------------------------------------


def _run_bare(task: RunTask, on_sample: SampleCallback | None) -> tuple[list[LocalizationSample], float, bool]:
    spec = task.spec
    rng = np.random.default_rng(task.seed)
    starts = {r.id: r.start if r.start is not None else _random_pose(rng) for r in spec.robots}
    agent_seeds = rng.integers(0, 2**63, size=len(spec.robots))
    policies: dict[str, object] = {}
    for robot, agent_seed in zip(spec.robots, agent_seeds):
        if robot.policy is Policy.SCAN_LOCALIZE:
            policies[robot.id] = ScanLocalizeAgent(spec.methods, starts[robot.id], int(agent_seed), spec.camera_model)
        else:
            policies[robot.id] = _Stand()
    specs = [RobotSpec(r.id, _color(r.id)) for r in spec.robots]
    collector = _Collector(task, policies, on_sample)
    cameras = {r.id: CameraChoice.OFF for r in spec.robots}
    with World(specs, world_config(spec), seed=int(rng.integers(0, 2**63))) as world:
        for robot, pose in starts.items():
            world.place_robot(robot, pose)
        world.place_ball(*OFF_FIELD_BALL)
        world.step(10)
        while not collector.done and world.time_s < spec.max_sim_seconds_per_run:
            for robot, policy in policies.items():
                image = world.render_camera(robot) if cameras[robot] is not CameraChoice.OFF else None
                game = game_observation(_PLAYING, AgentId.parse(robot).player)
                observation = build_observation(world.sensors(robot), image, game, radio_observation([], 0))
                action = policy.act(observation)
                collector.after_act(robot, world.robot_pose(robot), world.time_s)
                cameras[robot] = _apply(world, robot, action, cameras[robot])
            world.step()
        return collector.samples, world.time_s, collector.done


def _apply(world: World, robot: str, action: Mapping, camera: CameraChoice) -> CameraChoice:
    camera = CameraChoice(int(action.get("camera", camera)))
    if camera.position is not None:
        world.set_camera(robot, camera.position)
    if "head" in action:
        world.set_head(robot, *(float(a) for a in action["head"]))
    world.command_motion(robot, MOTIONS[int(action["motion"])])
    return camera


def _random_pose(rng: np.random.Generator) -> Pose2D:
    x = rng.uniform(-FIELD.half_length + RANDOM_START_MARGIN_M, FIELD.half_length - RANDOM_START_MARGIN_M)
    y = rng.uniform(-FIELD.half_width + RANDOM_START_MARGIN_M, FIELD.half_width - RANDOM_START_MARGIN_M)
    return Pose2D(float(x), float(y), float(rng.uniform(-math.pi, math.pi)))


def _color(robot: str) -> TeamColor:
    return TeamColor.BLUE if AgentId.parse(robot).side is Side.HOME else TeamColor.RED


# ---- a match with the referee ----------------------------------------------------------------


def _run_match(task: RunTask, on_sample: SampleCallback | None) -> tuple[list[LocalizationSample], float, bool]:
    spec = task.spec
    home = sum(1 for r in spec.robots if AgentId.parse(r.id).side is Side.HOME)
    config = MatchConfig(home_players=home, away_players=len(spec.robots) - home, world=world_config(spec))
    config = dataclasses.replace(config, referee=dataclasses.replace(config.referee, half_seconds=spec.half_seconds,
                                                                     shootout=False))
    rng = np.random.default_rng(task.seed)
    match_seed, *agent_seeds = (int(s) for s in rng.integers(0, 2**63, size=len(spec.robots) + 1))
    policies: dict[str, object] = {}
    for robot, agent_seed in zip(spec.robots, agent_seeds):
        if robot.policy is Policy.SCAN_LOCALIZE:
            policies[robot.id] = ScanLocalizeAgent(spec.methods, None, agent_seed, spec.camera_model)
        elif robot.policy is Policy.SCRIPTED:
            policies[robot.id] = ScriptedPlayer(robot.id)
        else:
            policies[robot.id] = _Stand()
    collector = _Collector(task, policies, on_sample)
    match = Match(config)
    try:
        observations = match.reset(match_seed)
        while not collector.done and not match.finished and match.world.time_s < spec.max_sim_seconds_per_run:
            actions = {}
            for robot in match.agent_names:
                actions[robot] = policies[robot].act(observations[robot])
                collector.after_act(robot, match.world.robot_pose(robot), match.world.time_s)
            observations = match.step(actions).observations
        return collector.samples, match.world.time_s, collector.done
    finally:
        match.close()


# ---- samples -----------------------------------------------------------------------------------


class _Collector:
    """Turns the measured agents' new localization events into samples, up to the run's count."""

    def __init__(self, task: RunTask, policies: Mapping[str, object], on_sample: SampleCallback | None):
        self.task = task
        self.agents = {r: policies[r] for r in task.spec.measured}
        self.seen = {r: 0 for r in self.agents}
        self.events = 0
        self.samples: list[LocalizationSample] = []
        self.on_sample = on_sample

    @property
    def done(self) -> bool:
        return self.events >= self.task.samples

    def after_act(self, robot: str, truth: Pose2D, time_s: float) -> None:
        """Called right after ``robot`` decided: its new events are paired with its pose now."""
        agent = self.agents.get(robot)
        if agent is None:
            return
        while self.seen[robot] < len(agent.events) and not self.done:
            event = agent.events[self.seen[robot]]
            self.seen[robot] += 1
            if time_s < self.task.spec.warmup_seconds:
                continue
            self.events += 1
            self.samples.extend(event_samples(event, truth, self.task.run, robot, time_s))
            if self.on_sample is not None:
                self.on_sample(self.task.run)


def event_samples(event: LocalizationEvent, truth: Pose2D, run: int, robot: str, time_s: float) -> list[LocalizationSample]:
    """One sample per method of one localization event, against the true pose (m, rad)."""
    rows = []
    compute = event.compute_ms or (math.nan,) * len(event.estimates)
    for (method, estimate), ms in zip(event.estimates, compute):
        if estimate is None:
            ex = ey = et = math.nan
            used = 0
        else:
            ex, ey, et = estimate.x_m, estimate.y_m, estimate.theta_rad
            used = len(estimate.landmarks_used)
        rows.append(
            LocalizationSample(
                run, robot, method, event.index, time_s, truth.x, truth.y, truth.theta, ex, ey, et, used,
                len(event.percepts), ms,
            )
        )
    return rows
