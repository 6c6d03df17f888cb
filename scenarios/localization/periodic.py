"""Periodic localization samples: the measured robots' own pose estimates while they play.

Scenario 3 of the thesis (section 6.4) in its literal sense: the measured robots play a
refereed game and localize as they go, and every ``sample_period_s`` of PLAYING time this
harness (never the agent) compares each measured robot's belief, its policy's
``pose_estimate()`` (:class:`match.protocol.PoseReporter`), with its true pose read from
the world. A robot is sampled only while the game state is PLAYING in normal play and it is
neither fallen nor held by the referee; PLAYING time is counted in control steps over the
whole run (both halves), so a sample falls every ``sample_period_s`` seconds of it.

Samples are :class:`~scenarios.localization.samples.LocalizationSample` rows like those of
localization events: ``method`` is the measured robot's policy name, ``event`` the robot's
sample index, ``landmarks_used`` and ``percepts`` 0 (a pose reporter does not say), and an
estimate that is missing, raises or is not three finite numbers gives NaN (a missing sample).
Units: metres, radians, seconds, field frame.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Mapping

from match.game import Match
from match.protocol import GameState, Policy, PoseReporter, SecondaryState
from scenarios.localization.samples import LocalizationSample
from scenarios.localization.spec import ScenarioSpec
from world.field import Pose2D

log = logging.getLogger(__name__)

SampleCallback = Callable[[int], None]  # called with the run index after every sample of a run


class UnmeasurableRobotError(TypeError):
    """A measured robot whose policy does not report its pose, so it cannot be sampled periodically."""

    def __init__(self, robot: str, policy: str, built: object) -> None:
        super().__init__(f"measured robot {robot}: policy {policy!r} built a {type(built).__name__} without "
                         "pose_estimate(); periodic sampling needs a policy that reports its pose (PoseReporter)")
        self.robot, self.policy = robot, policy


def in_play(match: Match) -> bool:
    """Whether the match is in normal play now: game state PLAYING, no penalty shoot-out."""
    if match.state is not GameState.PLAYING:
        return False
    return match.free_play or match.referee.secondary is SecondaryState.NORMAL


class PeriodicCollector:
    """Watches a run (:class:`match.runner.MatchObserver`): one sample of each measured robot
    that is up every ``spec.sample_period_s`` seconds of PLAYING time, up to the run's count.

    ``run`` and ``samples``: the run's index and how many samples it takes at most (over all
    its measured robots); the run also ends at the scenario's simulated-time limit.
    """

    def __init__(self, spec: ScenarioSpec, run: int, samples: int, policies: Mapping[str, Policy],
                 on_sample: SampleCallback | None = None):
        if spec.sample_period_s is None:
            raise ValueError(f"scenario {spec.name!r} has no sample period; it samples at localization events")
        self.spec, self.run, self.wanted = spec, run, samples
        self.labels = {r.id: r.policy for r in spec.robots if r.measured}
        self.agents: dict[str, PoseReporter] = {}
        for robot in spec.measured:
            policy = policies[robot]
            if not isinstance(policy, PoseReporter):
                raise UnmeasurableRobotError(robot, self.labels[robot], policy)
            self.agents[robot] = policy
        self.taken = {robot: 0 for robot in self.agents}
        self.samples: list[LocalizationSample] = []
        self.on_sample = on_sample
        self.playing_steps = 0  # control steps decided in play so far, both halves
        self._warned: set[str] = set()

    @property
    def events(self) -> int:
        """Samples taken so far (each is one robot at one instant)."""
        return len(self.samples)

    @property
    def complete(self) -> bool:
        """Whether the run has all the samples it may take."""
        return self.events >= self.wanted

    def done(self, match: Match) -> bool:
        """The run ends with its samples, or at the scenario's simulated-time limit (the match's end ends it too)."""
        return self.complete or match.world.time_s >= self.spec.max_sim_seconds_per_run

    def decided(self, match: Match, actions: Mapping[str, object]) -> None:
        """After the robots decided on this step's observations: a sample every period of play."""
        if not in_play(match):
            return
        elapsed = self.playing_steps  # steps of play before this one: the time since play began, in steps
        self.playing_steps += 1
        period = max(1, round(self.spec.sample_period_s / match.config.world.physics.control_step_s))
        if elapsed == 0 or elapsed % period or match.world.time_s < self.spec.warmup_seconds:
            return
        for agent in match.agents:
            robot = str(agent)
            if robot not in self.agents or self.complete:
                continue
            if not match.free_play and match.referee.holds(agent):
                continue
            truth = match.world.robot_truth(robot)
            if not truth.fallen:
                self._take(robot, truth.pose, match.world.time_s)

    def _take(self, robot: str, truth: Pose2D, time_s: float) -> None:
        ex, ey, et = self._estimate(robot)
        self.samples.append(LocalizationSample(self.run, robot, self.labels[robot], self.taken[robot], time_s,
                                               truth.x, truth.y, truth.theta, ex, ey, et, 0, 0))
        self.taken[robot] += 1
        if self.on_sample is not None:
            self.on_sample(self.run)

    def _estimate(self, robot: str) -> tuple[float, float, float]:
        """The robot's pose estimate (m, m, rad, field frame); NaNs when it has none or reports garbage."""
        nan = (math.nan, math.nan, math.nan)
        try:
            estimate = self.agents[robot].pose_estimate()
            if estimate is None:
                return nan
            x, y, theta = (float(v) for v in estimate)
        except Exception as error:  # the estimate is for the measurement only: garbage is a missing sample
            if robot not in self._warned:
                self._warned.add(robot)
                log.warning("run %d: pose_estimate() of %s failed (%s: %s); its sample has no estimate",
                            self.run, robot, type(error).__name__, error)
            return nan
        return (x, y, theta) if all(math.isfinite(v) for v in (x, y, theta)) else nan
