"""One run of a scenario: the simulation that yields its localization samples.

A run is independent given its seed (:meth:`ScenarioSpec.run_seeds`): the same task gives
the same samples, in whatever process it runs. Measured robots run
:class:`~agents.behavior.policies.scan_localize.ScanLocalizeAgent` with every method of the
scenario side by side; after each of their localization events this harness (never the
agent) reads the true pose from the world, the thesis' GPS, and makes one
:class:`~scenarios.localization.samples.LocalizationSample` per method. A scenario with
periodic sampling (``sample_period_s``) instead measures robots that play with their own
policy, every so many seconds of PLAYING time (:mod:`scenarios.localization.periodic`).

Every run is a :class:`~match.game.Match` played by the one game loop,
:func:`match.runner.run_match`, with a :class:`SampleCollector` watching it. Without a
referee the match runs in free play (no ball, the game state always PLAYING, robots placed
at their start poses); with the referee there are kick-offs, goals, half-time and robots
replaced. Every robot plays the policy its scenario file names.
"""

from __future__ import annotations

import dataclasses
import logging
import math
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from agents.behavior.policies.scan_localize import LocalizationEvent
from agents.policies import make_policy
from match.free_play import FreePlay
from match.game import Match, MatchConfig
from match.protocol import CameraChoice, Policy
from match.protocol.ids import AgentId, Side
from match.runner import run_match
from scenarios.localization.periodic import PeriodicCollector
from scenarios.localization.samples import LocalizationSample, RunResult
from scenarios.localization.spec import RobotEntry, ScenarioSpec
from world.config import WorldConfig
from world.field import FIELD, Pose2D
from world.motions import MotionNoise

log = logging.getLogger(__name__)

RANDOM_START_MARGIN_M = 0.5  # random start poses are drawn this far inside the field lines
ALONE_ROBOT = "home_1"  # the robot of run_alone
ALONE_START = Pose2D(-1.0, 0.0, 0.0)

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
    """The samples of one run (one per method per localization event, or one per periodic
    sample) and its costs.

    ``complete`` is False when the run ended (time limit, end of the match) short of its
    samples; with periodic sampling a run that played its match to the end is complete.
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


def run_tasks(spec: ScenarioSpec) -> tuple[RunTask, ...]:
    """The runs of a scenario, in order."""
    return tuple(
        RunTask(spec, run, seed, samples)
        for run, (seed, samples) in enumerate(zip(spec.run_seeds(), spec.run_samples()))
    )


def simulate_run(task: RunTask, on_sample: SampleCallback | None = None, out_dir: Path | None = None) -> RunOutcome:
    """Simulate one run until it has ``task.samples`` localization events of measured robots
    (with periodic sampling: samples, or the match's end).

    ``out_dir``: where to write the run's match outputs (``summary.json``, ``events.jsonl``,
    ``match_log.npz`` with every robot's pose estimate beside the truth); None writes nothing.
    """
    started = time.perf_counter()
    spec = task.spec
    rng = np.random.default_rng(task.seed)
    if spec.referee:
        match_seed, *agent_seeds = (int(s) for s in rng.integers(0, 2**63, size=len(spec.robots) + 1))
        starts: dict[str, Pose2D | None] = {r.id: None for r in spec.robots}
        config = _refereed_config(spec)
    else:
        starts = {r.id: r.start if r.start is not None else _random_pose(rng) for r in spec.robots}
        agent_seeds = [int(s) for s in rng.integers(0, 2**63, size=len(spec.robots))]
        match_seed = int(rng.integers(0, 2**63))
        free_play = FreePlay(tuple((robot, pose) for robot, pose in starts.items() if pose is not None))
        config = MatchConfig(world=world_config(spec), initial_camera=CameraChoice.OFF, free_play=free_play)
    policies = {r.id: _policy(r, spec, starts[r.id]) for r in spec.robots}
    collector: SampleCollector | PeriodicCollector
    if spec.periodic:
        collector = PeriodicCollector(spec, task.run, task.samples, policies, on_sample)
    else:
        collector = SampleCollector(task, policies, on_sample)
    match = Match(config)
    try:
        run_match(config, policies, seed=match_seed, out_dir=out_dir, progress=False, match=match, observer=collector,
                  policy_seeds=dict(zip(policies, agent_seeds)))
        sim_seconds = match.world.time_s
        played_out = spec.periodic and not match.free_play and match.finished
    finally:
        match.close()
    complete = collector.complete or played_out
    outcome = RunOutcome(task.run, task.seed, tuple(collector.samples), sim_seconds, time.perf_counter() - started,
                         complete)
    if not complete:
        log.warning("run %d ended with %d of %d samples after %.0f s simulated", task.run, outcome.events,
                    task.samples, sim_seconds)
    return outcome


def _refereed_config(spec: ScenarioSpec) -> MatchConfig:
    home = sum(1 for r in spec.robots if AgentId.parse(r.id).side is Side.HOME)
    config = MatchConfig(home_players=home, away_players=len(spec.robots) - home, world=world_config(spec))
    referee = dataclasses.replace(config.referee, half_seconds=spec.half_seconds, shootout=False)
    return dataclasses.replace(config, referee=referee)


def _policy(robot: RobotEntry, spec: ScenarioSpec, start: Pose2D | None) -> Policy:
    """The robot's policy by its name; measured scan-localize robots get the scenario's localization options
    (with periodic sampling every robot plays its policy as it is)."""
    if robot.measured and not spec.periodic:
        return make_policy(robot.policy, methods=spec.methods, start=start, camera_model=spec.camera_model)
    return make_policy(robot.policy)


def world_config(spec: ScenarioSpec) -> WorldConfig:
    """The world of a scenario: the default one with its motion noise scaled and its camera profile."""
    noise = MotionNoise()
    scale = spec.motion_noise_scale
    scaled = {f.name: getattr(noise, f.name) * scale for f in dataclasses.fields(MotionNoise)}
    return WorldConfig(motion_noise=MotionNoise(**scaled), camera_profile=spec.camera_profile)


def _random_pose(rng: np.random.Generator) -> Pose2D:
    x = rng.uniform(-FIELD.half_length + RANDOM_START_MARGIN_M, FIELD.half_length - RANDOM_START_MARGIN_M)
    y = rng.uniform(-FIELD.half_width + RANDOM_START_MARGIN_M, FIELD.half_width - RANDOM_START_MARGIN_M)
    return Pose2D(float(x), float(y), float(rng.uniform(-math.pi, math.pi)))


# ---- samples -----------------------------------------------------------------------------------


class SampleCollector:
    """Watches a run (:class:`match.runner.MatchObserver`): turns the measured agents' new
    localization events into samples against the true pose, up to the run's count, and ends
    the run then or at the scenario's time limit."""

    def __init__(self, task: RunTask, policies: Mapping[str, Policy], on_sample: SampleCallback | None):
        self.task = task
        self.agents = {r: policies[r] for r in task.spec.measured}
        self.seen = {r: 0 for r in self.agents}
        self.events = 0
        self.samples: list[LocalizationSample] = []
        self.on_sample = on_sample

    @property
    def complete(self) -> bool:
        """Whether the run has all its samples."""
        return self.events >= self.task.samples

    def done(self, match: Match) -> bool:
        """The run ends with its samples, or at the scenario's simulated-time limit."""
        return self.complete or match.world.time_s >= self.task.spec.max_sim_seconds_per_run

    def decided(self, match: Match, actions: Mapping[str, object]) -> None:
        """After the robots decided: their new events are paired with their true poses now."""
        for robot in match.agent_names:
            if robot in self.agents:
                self._take_events(robot, match.world.robot_pose(robot), match.world.time_s)

    def _take_events(self, robot: str, truth: Pose2D, time_s: float) -> None:
        agent = self.agents[robot]
        while self.seen[robot] < len(agent.events) and not self.complete:
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


# ---- scenario 1 without a scenario file ---------------------------------------------------------


def run_alone(
    samples: int,
    seed: int,
    methods: Sequence[str],
    run: int = 0,
    start: Pose2D = ALONE_START,
    camera_model: str = "exact",
) -> RunResult:
    """Scenario 1: ``samples`` localization events of one robot alone on the field, from ``start``.

    The robot runs :class:`~agents.behavior.policies.scan_localize.ScanLocalizeAgent` (move, scan,
    localize) with every method of ``methods`` side by side, on the bare world.
    """
    robot = RobotEntry(ALONE_ROBOT, "scan_localize", measured=True, start=start)
    spec = ScenarioSpec("scenario 1", "", samples, 1, seed, tuple(methods), camera_model, False, (robot,))
    outcome = simulate_run(RunTask(spec, run, seed, samples))
    if not outcome.complete:
        raise RuntimeError(f"run {run}: {outcome.events} of {samples} samples")
    return RunResult(outcome.samples, outcome.sim_seconds, outcome.wall_seconds)
