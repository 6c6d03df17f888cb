"""Calibration of the colour-segmentation thresholds on our own renderer (thesis section 4.1).

``robotstadium calibrate-colors`` renders robot camera frames at seeded random poses, knows
the true class of every pixel, fits one RGB box per colour class and writes
``agents/vision/data/color_thresholds.json`` (plus a report beside it).

True classes of a frame's pixels:

- bodies, from the labels the compiled renderer draws with the frame
  (:meth:`World.camera_labels`, pybullet's segmentation labels: object id and link index):
  the goals are blue or yellow, the ball orange, a robot's waist link cyan (blue team) or
  magenta (red team), its other links ``robot``, the walls, roof and banners ``other``;
- the ground, which the hall's drawing shows unlabelled: :meth:`GroundRenderer.floor_hits`
  (the renderer's own ground geometry) gives each ground pixel's field point, which is looked
  up in the carpet texture (line texels white, carpet texels green, off the carpet ``other``).

Fit (:func:`fit_thresholds`): per class and channel, the 0.5th to 99.5th percentile of the
true pixels, widened by :data:`MARGIN_LEVELS` on each side, then widened outward to whole
cells of the segmentation lookup table (4 levels), so that the table and the boxes agree
exactly. Evaluation (:func:`evaluate`) labels pixels with that table in the priority
order: per class, the fraction of its true pixels labelled with it; for ``robot`` and
``other`` pixels, the fraction labelled with a colour other than white (which is their
correct label, as unfitted pixels become white).
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from agents.vision.colors import PRIORITY, UNFITTED, ColorClass
from agents.vision.head_scan import SCAN_PITCH_RAD
from agents.vision.segmentation import LEVEL_SHIFT, ColorBox, ColorTable, ColorThresholds
from scenarios.common.io import write_json
from world import rendering
from world.camera_model import NAO_CAMERA, CameraPosition
from world.config import RobotSpec, WorldConfig
from world.field import GoalColor, Pose2D
from world.ground import GroundRenderer
from world.robot_model import Joint, TeamColor
from world.textures import LINE_RGB, TEXEL_M, carpet_texture
from world.world import World

CALIBRATION_PROFILE = "clean"
"""The camera profile calibrated on when none is named: the rendered colours, as the shipped thresholds
were fitted (a team calibrates on its own camera with ``camera_profile``)."""

log = logging.getLogger(__name__)

ROBOT = 7
"""Truth label of robot pixels other than the waistband (not a colour class)."""
OTHER = 8
"""Truth label of everything else: floor, walls, roof, banners, background."""
TRUTH_NAMES = {**{int(c): c.name.lower() for c in ColorClass}, ROBOT: "robot", OTHER: "other"}

WAIST_CLASS = {TeamColor.BLUE: ColorClass.CYAN, TeamColor.RED: ColorClass.MAGENTA}
GOAL_CLASS = {GoalColor.BLUE: ColorClass.BLUE, GoalColor.YELLOW: ColorClass.YELLOW}

LOW_PERCENTILE = 0.5
HIGH_PERCENTILE = 99.5
MARGIN_LEVELS = 12
"""RGB levels added on each side of a class's percentile range (covers shading not seen)."""

DEFAULT_FRAMES = 100
"""Frames of ``robotstadium calibrate-colors`` (about 4 s on one core)."""
ROBOTS_PER_TEAM = 3
SETTLE_STEPS = 5
"""Control steps after placing everything: the robots stand and the head reaches its angles."""
HOLDOUT_SEED_OFFSET = 1_000_003
"""Held-out frames are rendered from ``seed + HOLDOUT_SEED_OFFSET``."""

_OBJECT_BITS = 24  # pybullet: mask value = object id + ((link index + 1) << 24)


@dataclass(frozen=True)
class TruthFrame:
    """One rendered camera frame: ``image`` (H, W, 3) uint8 RGB and ``labels`` (H, W) uint8 truth."""

    image: np.ndarray
    labels: np.ndarray


@dataclass(frozen=True)
class ClassScore:
    """How one truth class fared: ``pixels`` counted, ``correct`` the fraction labelled right.

    Right is the class itself for a colour class, and white (what an unfitted pixel
    becomes) for ``robot`` and ``other``.
    """

    name: str
    pixels: int
    correct: float


@dataclass(frozen=True)
class CalibrationResult:
    """Fitted thresholds and their scores on the calibration and on held-out frames."""

    thresholds: ColorThresholds
    frames: int
    holdout_frames: int
    seed: int
    fit_scores: tuple[ClassScore, ...]
    holdout_scores: tuple[ClassScore, ...]
    seconds: float

    def to_json(self) -> dict:
        return {
            "source": self.thresholds.source,
            "frames": self.frames,
            "holdout_frames": self.holdout_frames,
            "seed": self.seed,
            "seconds": round(self.seconds, 2),
            "fit": {"low_percentile": LOW_PERCENTILE, "high_percentile": HIGH_PERCENTILE, "margin_levels": MARGIN_LEVELS},
            "meaning": "colour classes: fraction of true pixels labelled with their class; "
            "robot/other: fraction NOT labelled with a colour other than white",
            "calibration": {s.name: {"pixels": s.pixels, "correct": round(s.correct, 5)} for s in self.fit_scores},
            "holdout": {s.name: {"pixels": s.pixels, "correct": round(s.correct, 5)} for s in self.holdout_scores},
        }


# ---- truth ------------------------------------------------------------------------------


class TruthLabeller:
    """True per-pixel classes of a World's robot cameras (see the module docstring)."""

    def __init__(self, world: World):
        self.world = world
        field = world.config.field
        texture = carpet_texture(field, TEXEL_M)
        is_line = np.all(texture == np.asarray(LINE_RGB, np.uint8), axis=-1)
        self._carpet_labels = np.where(is_line, int(ColorClass.WHITE), int(ColorClass.GREEN)).astype(np.uint8)
        self._ground = GroundRenderer(field, world.config.render, world.scene.floor_half_extent)
        self._body_class: dict[int, int] = {world.ball_body_id: int(ColorClass.ORANGE)}
        for color, body in world.scene.goals.items():
            self._body_class[body] = int(GOAL_CLASS[color])
        self._robot_bodies = {world.body_id(rid): rid for rid in world.robot_ids}

    def labels(self, robot_id: str) -> np.ndarray:
        """Truth labels (H, W) uint8 of what ``robot_id``'s camera sees now."""
        world, cam = self.world, NAO_CAMERA
        rotation, position = world.camera_pose(robot_id)
        _, mask = world.camera_labels(robot_id)  # the bodies' labels, as the renderer drew them
        labels = self._body_labels(mask.astype(np.int64)).reshape(-1)
        # The hall is drawn analytically, without labels: label the pixels where its own ground
        # geometry puts the carpet and the floor.
        focal = rendering.focal_length_px(cam.height_px, cam.vertical_fov_rad)
        index, x, y = self._ground.floor_hits(mask < 0, rotation, position, focal)
        on_carpet, rows, cols = self._ground.carpet_texels(x, y)
        labels[index[on_carpet]] = self._carpet_labels[rows, cols]
        labels[index[~on_carpet & self._ground.on_floor(x, y)]] = OTHER
        return labels.reshape(cam.height_px, cam.width_px)

    def _body_labels(self, mask: np.ndarray) -> np.ndarray:
        labels = np.full(mask.shape, OTHER, np.uint8)
        drawn = mask >= 0
        body = np.where(drawn, mask & ((1 << _OBJECT_BITS) - 1), -1)
        link = np.where(drawn, (mask >> _OBJECT_BITS) - 1, -2)
        for body_id, label in self._body_class.items():
            labels[body == body_id] = label
        for body_id, robot_id in self._robot_bodies.items():
            of_robot = body == body_id
            labels[of_robot] = ROBOT
            team = self.world.robot_truth(robot_id).team
            labels[of_robot & (link == int(Joint.WAIST))] = int(WAIST_CLASS[team])
        return labels


# ---- sampling ---------------------------------------------------------------------------


def calibration_world(seed: int = 0, camera_profile: str = CALIBRATION_PROFILE) -> World:
    """A world with :data:`ROBOTS_PER_TEAM` robots of each team, its cameras of ``camera_profile``."""
    roster = [RobotSpec(f"{team.value}_{i}", team) for team in TeamColor for i in range(ROBOTS_PER_TEAM)]
    return World(roster, WorldConfig(camera_profile=camera_profile), seed=seed)


def _free_spot(taken: list[tuple[float, float]], propose, clearance_m: float):
    """A point from ``propose()`` at least ``clearance_m`` from every taken point (None after 30 tries)."""
    for _ in range(30):
        x, y = propose()
        if abs(x) < 3.6 and abs(y) < 2.6 and all(math.hypot(x - a, y - b) >= clearance_m for a, b in taken):
            return x, y
    return None


def stage_frame(world: World, rng: np.random.Generator) -> str:
    """Place robots, ball and one observer's head at random; return the observer's id.

    The observer stands on the field and faces a goal half the time; the others and the
    ball are mostly placed in front of it. Head pitch is mostly the thesis' 17 degrees
    down, sometimes anywhere from 15 degrees up to 29 down; the bottom camera a quarter
    of the time.
    """
    ids = list(world.robot_ids)
    observer = ids[int(rng.integers(len(ids)))]
    x, y = float(rng.uniform(-2.8, 2.8)), float(rng.uniform(-1.9, 1.9))
    if rng.random() < 0.5:
        goal_x = -3.0 if rng.random() < 0.5 else 3.0
        theta = math.atan2(-y, goal_x - x) + float(rng.normal(0.0, 0.4))
    else:
        theta = float(rng.uniform(-math.pi, math.pi))
    theta = math.atan2(math.sin(theta), math.cos(theta))
    world.place_robot(observer, Pose2D(x, y, theta))
    taken = [(x, y)]

    def ahead(near: float, far: float, spread: float):
        def propose():
            r, a = rng.uniform(near, far), theta + rng.uniform(-spread, spread)
            return x + r * math.cos(a), y + r * math.sin(a)

        return propose

    for i, rid in enumerate(ids):
        if rid == observer:
            continue
        if rng.random() < 0.75:
            spot = _free_spot(taken, ahead(0.5, 3.0, 0.45), 0.4)
        else:
            spot = _free_spot(taken, lambda: (rng.uniform(-3.4, 3.4), rng.uniform(-2.4, 2.4)), 0.4)
        if spot is None:  # no free spot found: park it off the carpet's edge, one place per robot
            spot = (-3.0 + 1.2 * i, -2.65 if y > 0 else 2.65)
        world.place_robot(rid, Pose2D(spot[0], spot[1], float(rng.uniform(-math.pi, math.pi))))
        taken.append(spot)
    ball = _free_spot(taken, ahead(0.2, 2.5, 0.35), 0.25) or (x + 0.3 * math.cos(theta), y + 0.3 * math.sin(theta))
    world.place_ball(*ball)
    if rng.random() < 0.7:
        pitch = float(np.clip(rng.normal(SCAN_PITCH_RAD, math.radians(4.0)), math.radians(-15.0), math.radians(29.0)))
    else:
        pitch = float(rng.uniform(math.radians(-15.0), math.radians(29.0)))
    world.set_head(observer, float(rng.uniform(-0.6, 0.6)), pitch)
    world.set_camera(observer, CameraPosition.BOTTOM if rng.random() < 0.25 else CameraPosition.TOP)
    world.step(SETTLE_STEPS)
    return observer


def render_truth_frames(frames: int, seed: int, camera_profile: str = CALIBRATION_PROFILE) -> list[TruthFrame]:
    """Render ``frames`` camera images at seeded random poses through ``camera_profile``, with the truth labels
    of the rendered image."""
    if not isinstance(frames, int) or frames < 1:
        raise ValueError(f"frames must be a positive integer; got {frames!r}")
    rng = np.random.default_rng(seed)
    out = []
    with calibration_world(seed, camera_profile) as world:
        labeller = TruthLabeller(world)
        for _ in range(frames):
            observer = stage_frame(world, rng)
            out.append(TruthFrame(world.render_camera(observer), labeller.labels(observer)))
    return out


# ---- fit and evaluation -----------------------------------------------------------------


def _snap_out(low: np.ndarray, high: np.ndarray) -> tuple[tuple[int, int, int], tuple[int, int, int]]:
    """Widen ``[low, high]`` to whole lookup-table cells (``1 << LEVEL_SHIFT`` levels)."""
    cell = 1 << LEVEL_SHIFT
    lo = np.clip(np.floor(low / cell) * cell, 0, 255).astype(int)
    hi = np.clip(np.floor(high / cell) * cell + cell - 1, 0, 255).astype(int)
    return tuple(int(v) for v in lo), tuple(int(v) for v in hi)


def fit_thresholds(frames: Sequence[TruthFrame], source: str = "") -> ColorThresholds:
    """One box per colour class from its true pixels (see the module docstring for the rule)."""
    images = np.concatenate([f.image.reshape(-1, 3) for f in frames]).astype(float)
    labels = np.concatenate([f.labels.reshape(-1) for f in frames])
    boxes = []
    for color in PRIORITY:
        pixels = images[labels == int(color)]
        if len(pixels) == 0:
            log.warning("no %s pixels in %d frames: the class gets no range", color.name.lower(), len(frames))
            continue
        low = np.percentile(pixels, LOW_PERCENTILE, axis=0) - MARGIN_LEVELS
        high = np.percentile(pixels, HIGH_PERCENTILE, axis=0) + MARGIN_LEVELS
        boxes.append(ColorBox(color, *_snap_out(low, high)))
    return ColorThresholds(tuple(boxes), source)


def evaluate(thresholds: ColorThresholds, frames: Sequence[TruthFrame]) -> tuple[ClassScore, ...]:
    """Scores of the lookup table (raw labels, before cleaning) on the frames' true pixels."""
    table = ColorTable(thresholds)
    predicted = np.concatenate([table.classify(f.image).reshape(-1) for f in frames])
    truth = np.concatenate([f.labels.reshape(-1) for f in frames])
    scores = []
    for label in (*(int(c) for c in PRIORITY), ROBOT, OTHER):
        mine = truth == label
        n = int(np.count_nonzero(mine))
        if label in (ROBOT, OTHER):
            good = np.count_nonzero(predicted[mine] == int(UNFITTED)) if n else 0
        else:
            good = np.count_nonzero(predicted[mine] == label) if n else 0
        scores.append(ClassScore(TRUTH_NAMES[label], n, good / n if n else float("nan")))
    return tuple(scores)


def command_source(frames: int, seed: int, camera_profile: str = CALIBRATION_PROFILE) -> str:
    """The command that fits these thresholds again, naming the profile (the default may change)."""
    return f"robotstadium calibrate-colors --frames {frames} --seed {seed} --camera-profile {camera_profile}"


def calibrate_colors(frames: int, seed: int, holdout_frames: int | None = None,
                     camera_profile: str = CALIBRATION_PROFILE) -> CalibrationResult:
    """Render ``frames`` frames through ``camera_profile``, fit the thresholds, score them there and on
    held-out frames.

    ``holdout_frames`` (default a third of ``frames``, at least 1) are rendered from
    another seed; 0 skips them.
    """
    if holdout_frames is None:
        holdout_frames = max(1, frames // 3)
    if not isinstance(holdout_frames, int) or holdout_frames < 0:
        raise ValueError(f"holdout_frames must be an integer >= 0; got {holdout_frames!r}")
    start = time.perf_counter()
    fit_frames = render_truth_frames(frames, seed, camera_profile)
    thresholds = fit_thresholds(fit_frames, command_source(frames, seed, camera_profile))
    fit_scores = evaluate(thresholds, fit_frames)
    held = render_truth_frames(holdout_frames, seed + HOLDOUT_SEED_OFFSET, camera_profile) if holdout_frames else []
    holdout_scores = evaluate(thresholds, held) if held else ()
    seconds = time.perf_counter() - start
    log.info("calibrated colours on %d frames (+%d held out) in %.1f s", frames, holdout_frames, seconds)
    return CalibrationResult(thresholds, frames, holdout_frames, seed, fit_scores, holdout_scores, seconds)


def report_path(thresholds_path: Path) -> Path:
    """Where the report of a threshold file goes: ``<stem>_report.json`` beside it."""
    path = Path(thresholds_path)
    return path.with_name(f"{path.stem}_report.json")


def write_calibration(result: CalibrationResult, path: Path) -> tuple[Path, Path]:
    """Write the thresholds to ``path`` and the report beside it; return both paths."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    result.thresholds.save(path)
    return path, write_json(report_path(path), result.to_json(), allow_nan=True)


def format_scores(result: CalibrationResult) -> str:
    """A plain-text table of the scores, one truth class per row, in percent."""
    held = {s.name: s for s in result.holdout_scores}
    lines = [f"{'class':<8} {'pixels':>8} {'correct %':>10} {'held-out px':>12} {'held-out %':>11}  range (RGB low .. high)"]
    for score in result.fit_scores:
        h = held.get(score.name)
        try:
            box = result.thresholds.box(ColorClass[score.name.upper()])
        except KeyError:
            box = None
        span = f"{box.low} .. {box.high}" if box else "(unfitted: correct unless coloured)"
        h_px = f"{h.pixels:>12d}" if h else f"{'-':>12}"
        h_pc = f"{100 * h.correct:>11.2f}" if h else f"{'-':>11}"
        lines.append(f"{score.name:<8} {score.pixels:>8d} {100 * score.correct:>10.2f} {h_px} {h_pc}  {span}")
    return "\n".join(lines)
