"""Scenario 1 of thesis chapter 6 on the bare world: one robot alone, move-scan-localize.

The measured robot runs :class:`agents.behavior.scan_localize.ScanLocalizeAgent` on the
observations it would get in a match (camera image only while its camera is on), with
every localization method side by side. After each of its localization events, this
harness (not the agent) reads the robot's true pose from the world, the thesis' GPS, and
makes one :class:`LocalizationSample` per method.
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from agents.behavior.scan_localize import ScanLocalizeAgent
from match.observations import build_observation, game_observation, radio_observation
from match.protocol import MOTIONS, CameraChoice
from match.protocol.game_control import GameControlView, GameState, KickOff, SecondaryState
from world.config import RobotSpec
from world.field import GoalColor, Pose2D, normalize_angle
from world.teams import TeamColor
from world.world import World

log = logging.getLogger(__name__)

ROBOT = "home_1"
DEFAULT_START = Pose2D(-1.0, 0.0, 0.0)
STEPS_PER_SAMPLE_LIMIT = 2000  # 80 s of simulated time: a cycle that takes longer is stuck

_PLAYING = GameControlView(
    GameState.PLAYING, SecondaryState.NORMAL, KickOff.NONE, 0, 0, 0, 0, 600.0, 1, TeamColor.BLUE, GoalColor.BLUE
)


@dataclass(frozen=True)
class LocalizationSample:
    """One method's estimate at one localization event, against the true pose (m, rad).

    ``est_*`` are NaN when the method had no estimate; the errors are NaN then too.
    """

    run: int
    robot: str
    method: str
    event: int
    sim_time_s: float
    true_x: float
    true_y: float
    true_theta: float
    est_x: float
    est_y: float
    est_theta: float
    landmarks_used: int
    percepts: int
    # Wall time of the method's localize(): a measurement of the machine, not of the match,
    # so it is left out of comparisons.
    compute_ms: float = field(default=math.nan, compare=False, repr=False)

    @property
    def position_error_m(self) -> float:
        return math.hypot(self.est_x - self.true_x, self.est_y - self.true_y)

    @property
    def orientation_error_deg(self) -> float:
        if math.isnan(self.est_theta):
            return math.nan
        return abs(math.degrees(normalize_angle(self.est_theta - self.true_theta)))


@dataclass(frozen=True)
class RunResult:
    samples: tuple[LocalizationSample, ...]
    sim_seconds: float
    wall_seconds: float


def run_alone(
    samples: int,
    seed: int,
    methods: Sequence[str],
    run: int = 0,
    start: Pose2D = DEFAULT_START,
    camera_model: str = "exact",
) -> RunResult:
    """Scenario 1: ``samples`` localization events of one robot alone on the field."""
    started = time.perf_counter()
    agent = ScanLocalizeAgent(methods, start, seed=seed, camera_model=camera_model)
    out: list[LocalizationSample] = []
    with World([RobotSpec(ROBOT, TeamColor.BLUE)], seed=seed) as world:
        world.place_robot(ROBOT, start)
        world.place_ball(0.0, 3.0)  # off the field: scenario 1's field is empty
        world.step(10)
        camera = CameraChoice.OFF
        steps = 0
        while len(agent.events) < samples:
            reading = world.sensors(ROBOT)
            image = world.render_camera(ROBOT) if camera is not CameraChoice.OFF else None
            observation = build_observation(reading, image, game_observation(_PLAYING, 1), radio_observation([], 0))
            seen = len(agent.events)
            action = agent.act(observation)
            if len(agent.events) > seen:
                out.extend(_samples(world, agent.events[-1], run))
            camera = CameraChoice(int(action.get("camera", camera)))
            if camera.position is not None:
                world.set_camera(ROBOT, camera.position)
            if "head" in action:
                world.set_head(ROBOT, *(float(a) for a in action["head"]))
            world.command_motion(ROBOT, MOTIONS[int(action["motion"])])
            world.step()
            steps += 1
            if steps > STEPS_PER_SAMPLE_LIMIT * (samples + 1):
                raise RuntimeError(f"run {run}: {len(agent.events)} of {samples} samples after {steps} steps")
        sim_seconds = world.time_s
    return RunResult(tuple(out), sim_seconds, time.perf_counter() - started)


def _samples(world: World, event, run: int) -> list[LocalizationSample]:
    truth = world.robot_pose(ROBOT)
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
                run, ROBOT, method, event.index, world.time_s, truth.x, truth.y, truth.theta, ex, ey, et, used,
                len(event.percepts), ms,
            )
        )
    return rows


def summarize(samples: Sequence[LocalizationSample]) -> dict[str, dict[str, float]]:
    """Per method: mean and median position (cm) and orientation (deg) errors, counts, median localize() ms."""
    out: dict[str, dict[str, float]] = {}
    for method in dict.fromkeys(s.method for s in samples):
        rows = [s for s in samples if s.method == method]
        pos = np.array([s.position_error_m for s in rows])
        ori = np.array([s.orientation_error_deg for s in rows])
        ok = np.isfinite(pos)
        out[method] = {
            "samples": len(rows),
            "with_estimate": int(ok.sum()),
            "position_mean_cm": float(np.mean(pos[ok]) * 100.0) if ok.any() else math.nan,
            "position_median_cm": float(np.median(pos[ok]) * 100.0) if ok.any() else math.nan,
            "orientation_mean_deg": float(np.mean(ori[ok])) if ok.any() else math.nan,
            "orientation_median_deg": float(np.median(ori[ok])) if ok.any() else math.nan,
            "localize_ms_median": float(np.nanmedian([s.compute_ms for s in rows])) if rows else math.nan,
        }
    return out
