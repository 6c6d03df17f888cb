"""The ``robotstadium perception`` command: vision errors against ground truth (thesis 4.6).

One world is built for the whole run. Each frame (seeded by ``numpy.random.default_rng``):
the measured robot stands at a pose uniform inside the field lines with a uniform heading,
in the thesis' scan posture (top camera, head pitch 17 degrees down, head yaw one of the
five scan yaws -80, -40, 0, 40, 80 degrees, thesis 5.1), with ``crowd`` other robots of both
teams standing uniformly on the field, at least ``MIN_SEPARATION_M`` from it and from each
other, heading anywhere. Robots not in the crowd, and the ball, wait off the carpet. After
a random settle time (``SETTLE_STEPS``) the camera frame is rendered (with ``--head-rate``, while the
head turns at that rate: :func:`stage_frame`), every camera model's pipeline
processes it, and its percepts are scored (:mod:`scenarios.perception.scoring`) against the
true landmarks (:mod:`scenarios.perception.truth`).
"""

from __future__ import annotations

import logging
import math
import platform
import time
from pathlib import Path

import numpy as np
import pybullet as pb
from tqdm import tqdm

from agents.vision.camera_models import DEFAULT_CAMERA_MODEL, level_rotation
from agents.vision.frame import CameraFrame
from agents.vision.head_scan import SCAN_PITCH_RAD
from agents.vision.overlay import save_overlay
from agents.vision.pipeline import VisionPipeline
from scenarios.perception import report
from scenarios.perception.records import (
    CROWD_ORDER,
    SETTLE_STEPS,
    FrameRecord,
    FrameSetup,
    PerceptionConfig,
    PerceptionConfigError,
)
from scenarios.perception.scoring import FrameScore, has_error, kind_statistics, match_frame
from scenarios.perception.truth import project_landmarks, true_landmarks
from world.camera_model import CameraPosition
from world.config import RobotSpec, WorldConfig
from world.field import FIELD, LandmarkKind, Pose2D
from world.robot_model import TeamColor
from world.world import World

log = logging.getLogger(__name__)

MEASURED = "home_1"
SCAN_YAWS_DEG: tuple[float, ...] = (-80.0, -40.0, 0.0, 40.0, 80.0)  # thesis 5.1: five frames per scan
SCAN_PITCH_DEG = math.degrees(SCAN_PITCH_RAD)  # 17.0
MIN_SEPARATION_M = 0.5
MIN_POST_CLEARANCE_M = 0.3  # no robot is placed into a goal post
PARKING_Y_M = -(FIELD.carpet_half_width + 0.8)  # off the carpet: never between a camera and a landmark
MAX_PLACEMENT_TRIES = 10_000


def roster() -> list[RobotSpec]:
    home = [RobotSpec(f"home_{i}", TeamColor.BLUE) for i in range(4)]
    away = [RobotSpec(f"away_{i}", TeamColor.RED) for i in range(4)]
    return home + away


def _clear_of_posts(x: float, y: float) -> bool:
    posts = [lm for lm in FIELD.landmarks if lm.kind is LandmarkKind.GOAL_POST]
    return all(math.hypot(x - p.x, y - p.y) >= MIN_POST_CLEARANCE_M for p in posts)


def _field_point(rng: np.random.Generator, taken: list[tuple[float, float]]) -> tuple[float, float]:
    hx, hy = FIELD.half_length, FIELD.half_width
    for _ in range(MAX_PLACEMENT_TRIES):
        x, y = float(rng.uniform(-hx, hx)), float(rng.uniform(-hy, hy))
        if _clear_of_posts(x, y) and all(math.hypot(x - a, y - b) >= MIN_SEPARATION_M for a, b in taken):
            return x, y
    raise PerceptionConfigError(f"no free spot {MIN_SEPARATION_M} m from {len(taken)} robots after {MAX_PLACEMENT_TRIES} tries")


def sample_setup(rng: np.random.Generator, crowd: int) -> FrameSetup:
    """A random frame setup: robot pose, scan yaw and ``crowd`` other robots (module docstring)."""
    x, y = _field_point(rng, [])
    theta = float(rng.uniform(-math.pi, math.pi))
    yaw = math.radians(float(rng.choice(SCAN_YAWS_DEG)))
    taken = [(x, y)]
    others = []
    for _ in range(crowd):
        cx, cy = _field_point(rng, taken)
        taken.append((cx, cy))
        others.append(Pose2D(cx, cy, float(rng.uniform(-math.pi, math.pi))))
    settle = int(rng.integers(SETTLE_STEPS[0], SETTLE_STEPS[1] + 1))
    return FrameSetup(Pose2D(x, y, theta), yaw, tuple(others), settle)


def stage_frame(world: World, setup: FrameSetup, head_rate_radps: float = 0.0) -> None:
    """Put the robots of ``setup`` in place and let them settle. With ``head_rate_radps``, the head
    settles one control step short of its yaw, a frame is taken there (the camera profile's previous
    frame, not scored), and the head turns on to the yaw in the frame's control step: the camera
    profile blurs and shears the frame by that turn, as in a head scan."""
    step_rad = head_rate_radps * world.config.physics.control_step_s
    world.place_robot(MEASURED, setup.pose)
    world.set_camera(MEASURED, CameraPosition.TOP)
    world.set_head(MEASURED, setup.head_yaw_rad - step_rad, SCAN_PITCH_RAD)
    for robot_id, pose in zip(CROWD_ORDER, setup.crowd):
        world.place_robot(robot_id, pose)
    world.step(setup.settle_steps)
    if step_rad > 0.0:
        world.render_camera(MEASURED)
        world.set_head(MEASURED, setup.head_yaw_rad, SCAN_PITCH_RAD)
        world.step(1)


def park_others(world: World, crowd: int) -> None:
    """Robots outside the crowd, and the ball, off the carpet (no landmark lies behind them)."""
    for i, robot_id in enumerate(CROWD_ORDER[crowd:]):
        world.place_robot(robot_id, Pose2D(-3.0 + i, PARKING_Y_M, math.pi / 2))
    world.place_ball(3.5, PARKING_Y_M)


def run_perception(out_dir: Path, config: PerceptionConfig) -> dict:
    """Run the perception measurement, write its outputs into ``out_dir``, return the summary."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    started = time.perf_counter()
    rng = np.random.default_rng(config.seed)
    pipelines = {name: VisionPipeline(name) for name in config.models}
    records: list[FrameRecord] = []
    false_positive_examples: list[report.Example] = []  # shown first, then frames with misses only
    miss_examples: list[report.Example] = []
    with World(roster(), WorldConfig(camera_profile=config.camera_profile), seed=config.seed) as world:
        park_others(world, config.crowd)
        for index in tqdm(range(config.frames), desc="perception", unit="frame", disable=not config.progress,
                          dynamic_ncols=True):
            setup = sample_setup(rng, config.crowd)
            stage_frame(world, setup, config.head_rate_radps)
            truth = world.robot_truth(MEASURED)
            if truth.fallen:
                log.warning("frame %d: the measured robot fell while settling", index)
            s = world.sensors(MEASURED)
            image = world.render_camera(MEASURED)
            frame = CameraFrame(image, s.head_yaw_rad, s.head_pitch_rad, s.camera, s.accelerometer_mps2)
            truths = true_landmarks(world, MEASURED, config.max_range_m)
            record = FrameRecord(index, setup, truth.pose, truths, fallen=truth.fallen,
                                 true_tilt_deg=math.degrees(truth.tilt_rad),
                                 applied_tilt_deg=applied_tilt_deg(s.accelerometer_mps2))
            results = {}
            for name, pipe in pipelines.items():
                t0 = time.perf_counter()
                results[name] = result = pipe.process(frame)
                record.process_ms[name] = (time.perf_counter() - t0) * 1e3
                record.scores[name] = match_frame(result.percepts, truths)
            records.append(record)
            first = record.scores[config.models[0]]
            kept = false_positive_examples if any(not p.matched for p in first.percepts) else miss_examples
            if len(kept) < config.examples and has_error(first):
                kept.append(report.Example(index, config.models[0], image, example_marks(world, first)))
                save_overlay(out_dir / "overlays" / f"frame_{index:04d}_{config.models[0]}.png", results[config.models[0]], image)
    summary = build_summary(records, config, time.perf_counter() - started)
    examples = (false_positive_examples + miss_examples)[: config.examples]
    report.write_outputs(out_dir, summary, records, config, sorted(examples, key=lambda e: e.frame))
    return summary


def applied_tilt_deg(accelerometer_mps2: tuple[float, float, float]) -> float:
    """The body tilt (deg) that the exact camera model reads from this accelerometer value (0: upright)."""
    level = level_rotation(accelerometer_mps2)
    return math.degrees(math.acos(max(-1.0, min(1.0, (float(np.trace(level)) - 1.0) / 2.0))))


def example_marks(world: World, score: FrameScore) -> list[report.Mark]:
    """Marks for an example image: true visible landmarks (where they project) and every percept."""
    marks = []
    pixels = project_landmarks(world, MEASURED, score.truths)
    matched = score.matched_ids()
    for truth, pixel in zip(score.truths, pixels):
        if truth.visible and pixel is not None:
            state = "truth-found" if truth.landmark.id in matched else "truth-missed"
            marks.append(report.Mark(pixel, state, truth.landmark.id.value))
    for scored in score.percepts:
        label = scored.truth.landmark.id.value if scored.truth else f"FP {scored.percept.kind.value}"
        marks.append(report.Mark(scored.percept.pixel, "percept-tp" if scored.matched else "percept-fp", label))
    return marks


def build_summary(records: list[FrameRecord], config: PerceptionConfig, wall_seconds: float) -> dict:
    """The ``summary.json`` content (timings last, so a comparison can drop them)."""
    timed = DEFAULT_CAMERA_MODEL if DEFAULT_CAMERA_MODEL in config.models else config.models[0]
    medians = {name: float(np.median([r.process_ms[name] for r in records])) for name in config.models}
    return {
        "frames": len(records),
        "ms_per_frame_median": medians[timed],
        "models": {name: kind_statistics((r.scores[name] for r in records), config.max_range_m) for name in config.models},
        "seed": config.seed,
        "crowd": config.crowd,
        "camera_profile": config.camera_profile,
        "head_rate_radps": config.head_rate_radps,
        "max_range_m": config.max_range_m,
        "fallen_frames": sum(r.fallen for r in records),
        "false_tilt_frames": sum(r.false_tilt for r in records),  # accelerometer tilt off the true one by > 2 deg
        "posture": {"camera": "top", "head_pitch_deg": SCAN_PITCH_DEG, "head_yaws_deg": list(SCAN_YAWS_DEG),
                    "settle_steps": list(SETTLE_STEPS)},
        "definitions": report.DEFINITIONS,
        "command": config.command,
        "timed_model": timed,
        "ms_per_frame_median_by_model": medians,
        "wall_seconds": wall_seconds,
        "versions": {"python": platform.python_version(), "numpy": np.__version__, "pybullet": pb.getAPIVersion()},
    }


TIMING_KEYS = ("ms_per_frame_median", "ms_per_frame_median_by_model", "wall_seconds")
