"""A picture tour of the world: robot camera frames from known poses, overviews, a kick.

:func:`run_world_demo` builds one world with four blue (home) and four red (away) robots,
puts them in a kick-off-like formation and writes PNG images plus an ``index.md`` that
says, for every image, from where it was taken and what it should show. It is the quickest
way to check by eye that the field, the goals, the robots and the motions look right.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

from agents.vision.head_scan import SCAN_PITCH_RAD
from world.camera_model import NAO_HEAD, CameraPosition
from world.config import RobotSpec
from world.field import Pose2D
from world.motions import MOTION_SPECS, Motion
from world.robot_model import TeamColor
from world.world import World

log = logging.getLogger(__name__)

CAMERA_SCALE = 4
"""Robot camera frames are enlarged this many times with nearest-neighbour, 160x120 -> 640x480."""

SETTLE_STEPS = 5
"""Control steps after placing robots, so they stand still and the head reaches its pitch."""

KICK_FRAME_INTERVAL_S = 0.2
KICK_TILE_SIZE_PX = (320, 240)


def team_roster() -> list[RobotSpec]:
    """Four blue home robots and four red away robots (player 0 keeps goal)."""
    home = [RobotSpec(f"home_{i}", TeamColor.BLUE) for i in range(4)]
    away = [RobotSpec(f"away_{i}", TeamColor.RED) for i in range(4)]
    return home + away


FORMATION: dict[str, Pose2D] = {
    "home_0": Pose2D(-2.7, 0.0, 0.0),
    "home_1": Pose2D(-1.8, 1.2, 0.0),
    "home_2": Pose2D(-1.8, -1.2, 0.0),
    "home_3": Pose2D(-0.9, -0.6, 0.0),
    "away_0": Pose2D(2.7, 0.0, math.pi),
    "away_1": Pose2D(1.8, -1.2, math.pi),
    "away_2": Pose2D(1.8, 1.2, math.pi),
    "away_3": Pose2D(0.9, 0.6, math.pi),
}
"""Kick-off-like positions: home (blue) defends the blue goal at x = -3, away the yellow one."""

FORMATION_BALL = (0.0, 0.0)


@dataclass(frozen=True)
class CameraShot:
    """One robot camera frame: who looks from where, with which camera, at what."""

    name: str
    robot_id: str
    pose: Pose2D
    shows: str
    camera: CameraPosition = CameraPosition.TOP
    head_pitch_rad: float = SCAN_PITCH_RAD
    ball: tuple[float, float] = FORMATION_BALL


CAMERA_SHOTS: tuple[CameraShot, ...] = (
    CameraShot(
        "camera_blue_goal",
        "away_3",
        Pose2D(-0.5, 0.0, math.pi),
        "the blue goal 2.5 m ahead, both posts in view (the crossbar is above the image at this pitch), "
        "the blue goalkeeper home_0 in front of it, the goal line and the goal-area front line on the carpet",
    ),
    CameraShot(
        "camera_yellow_goal",
        "home_3",
        Pose2D(0.5, 0.0, 0.0),
        "the yellow goal 2.5 m ahead, both posts in view (the crossbar is above the image at this pitch), "
        "the red goalkeeper away_0 in front of it, the goal line and the goal-area front line on the carpet",
    ),
    CameraShot(
        "camera_center_circle",
        "home_1",
        Pose2D(-1.7, 0.0, 0.0),
        "the centre circle and the middle line, the ball on the centre spot, the red robots and the "
        "yellow goal beyond",
    ),
    CameraShot(
        "camera_field_corner",
        "away_2",
        Pose2D(2.0, 1.0, math.pi / 4),
        "the field corner at (3, 2) (the yellow goal's left corner): the yellow end line and the "
        "left side line meeting in an L, the hall wall beyond",
    ),
    CameraShot(
        "camera_bottom_ball",
        "home_3",
        Pose2D(-0.33, 0.0, 0.0),
        "the ball close up, 0.33 m ahead on the middle line, seen with the bottom camera",
        camera=CameraPosition.BOTTOM,
    ),
)


@dataclass(frozen=True)
class OverviewShot:
    name: str
    eye: tuple[float, float, float]
    target: tuple[float, float, float]
    fov_deg: float
    shows: str


OVERVIEW_SHOTS: tuple[OverviewShot, ...] = (
    OverviewShot(
        "overview",
        (0.0, -3.7, 4.4),
        (0.0, -0.2, 0.0),
        62.0,
        "broadcast view of the whole field from the right side line: blue goal on the left, yellow goal "
        "on the right, the eight robots in formation (blue team with cyan waistbands left, red team with magenta waistbands right), ball on the centre spot",
    ),
    OverviewShot(
        "top_view",
        (0.0, 0.0, 9.0),
        (0.0, 0.0, 0.0),
        44.0,
        "straight down from 9 m: +x (toward the yellow goal) to the right, +y up; the field lines, "
        "both goals, the robots in formation and the ball",
    ),
)

KICKER = "home_3"
KICKER_POSE = Pose2D(-0.5, 0.2, 0.0)
KICK_BALL_OFFSET = (0.13, -0.05)  # forward, left of the kicker, m: ahead of its right foot


def run_world_demo(out_dir: Path, seed: int = 0) -> list[Path]:
    """Write the demo images and ``index.md`` into ``out_dir``; return the written paths."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    written: list[Path] = []
    index_rows: list[str] = []
    with World(team_roster(), seed=seed) as world:
        for shot in CAMERA_SHOTS:
            image = _camera_frame(world, shot)
            path = _write_png(out_dir / f"{shot.name}.png", _enlarge(image, CAMERA_SCALE))
            written.append(path)
            index_rows.append(_camera_index_row(path, shot))
        _place_formation(world)
        for overview in OVERVIEW_SHOTS:
            image = world.render_overview(eye=overview.eye, target=overview.target, fov_deg=overview.fov_deg)
            path = _write_png(out_dir / f"{overview.name}.png", image)
            written.append(path)
            index_rows.append(
                f"| [{path.name}]({path.name}) | overview {image.shape[1]}x{image.shape[0]}, "
                f"eye {_fmt_xyz(overview.eye)} m, target {_fmt_xyz(overview.target)} m, "
                f"vertical FOV {overview.fov_deg:.0f} deg | {overview.shows} |"
            )
        strip, times = _kick_strip(world)
        path = _write_png(out_dir / "kick_strip.png", strip)
        written.append(path)
        index_rows.append(_kick_index_row(path, times))
    index = out_dir / "index.md"
    index.write_text(_index_text(index_rows, seed), encoding="utf-8")
    written.append(index)
    for path in written:
        log.info("wrote %s", path)
    return written


# ---- shots -------------------------------------------------------------------------------


def _place_formation(world: World, ball: tuple[float, float] = FORMATION_BALL) -> None:
    for robot_id, pose in FORMATION.items():
        world.place_robot(robot_id, pose)
    world.place_ball(*ball)


def _camera_frame(world: World, shot: CameraShot) -> np.ndarray:
    _place_formation(world, shot.ball)
    world.place_robot(shot.robot_id, shot.pose)
    world.set_camera(shot.robot_id, shot.camera)
    world.set_head(shot.robot_id, 0.0, shot.head_pitch_rad)
    world.step(SETTLE_STEPS)
    log.debug("%s: %s at %s, camera %s", shot.name, shot.robot_id, world.robot_pose(shot.robot_id), shot.camera.value)
    image = world.render_camera(shot.robot_id)
    world.set_camera(shot.robot_id, CameraPosition.TOP)
    return image


def _kick_strip(world: World) -> tuple[np.ndarray, list[float]]:
    """Overview frames of a right-foot kick every 0.2 s over its 1.6 s, tiled into one image."""
    _place_formation(world)
    world.place_robot(KICKER, KICKER_POSE)
    forward, left = KICK_BALL_OFFSET
    c, s = math.cos(KICKER_POSE.theta), math.sin(KICKER_POSE.theta)
    ball_x = KICKER_POSE.x + c * forward - s * left
    ball_y = KICKER_POSE.y + s * forward + c * left
    world.place_ball(ball_x, ball_y)
    world.step(SETTLE_STEPS)
    world.place_ball(ball_x, ball_y)  # the settle steps may have nudged it
    duration_s = MOTION_SPECS[Motion.KICK_RIGHT].duration_s
    control_s = world.config.physics.control_step_s
    steps_per_frame = max(1, round(KICK_FRAME_INTERVAL_S / control_s))
    frames = int(round(duration_s / (steps_per_frame * control_s)))
    eye = (KICKER_POSE.x - 0.5, KICKER_POSE.y - 1.7, 0.9)
    target = (KICKER_POSE.x + 0.6, KICKER_POSE.y, 0.1)
    width, height = KICK_TILE_SIZE_PX
    if not world.command_motion(KICKER, Motion.KICK_RIGHT):
        raise RuntimeError(f"{KICKER} refused to kick")
    start_s = world.time_s
    tiles, times = [], []
    for i in range(frames + 1):
        if i:
            world.step(steps_per_frame)
        t = world.time_s - start_s
        tile = world.render_overview(eye=eye, target=target, width_px=width, height_px=height, fov_deg=50.0)
        tiles.append(_label(tile, f"t = {t:.1f} s"))
        times.append(t)
    ball = world.ball()
    log.debug("kick: ball at (%.2f, %.2f) moving (%.2f, %.2f) m/s", ball.x, ball.y, ball.vx, ball.vy)
    return _tile(tiles, columns=3), times


# ---- images ------------------------------------------------------------------------------


def _enlarge(image: np.ndarray, factor: int) -> np.ndarray:
    return cv2.resize(image, None, fx=factor, fy=factor, interpolation=cv2.INTER_NEAREST)


def _label(image: np.ndarray, text: str) -> np.ndarray:
    out = image.copy()
    cv2.putText(out, text, (8, 22), cv2.FONT_HERSHEY_SIMPLEX, 0.6, (0, 0, 0), 3, cv2.LINE_AA)
    cv2.putText(out, text, (8, 22), cv2.FONT_HERSHEY_SIMPLEX, 0.6, (255, 255, 255), 1, cv2.LINE_AA)
    return out


def _tile(images: Sequence[np.ndarray], columns: int) -> np.ndarray:
    """Images of one size in a grid, row by row; empty cells stay black."""
    height, width = images[0].shape[:2]
    rows = math.ceil(len(images) / columns)
    grid = np.zeros((rows * height, columns * width, 3), np.uint8)
    for i, image in enumerate(images):
        r, c = divmod(i, columns)
        grid[r * height : (r + 1) * height, c * width : (c + 1) * width] = image
    return grid


def _write_png(path: Path, rgb: np.ndarray) -> Path:
    if not cv2.imwrite(str(path), cv2.cvtColor(rgb, cv2.COLOR_RGB2BGR)):
        raise OSError(f"could not write image {path}")
    return path


# ---- index -------------------------------------------------------------------------------


def _fmt_pose(pose: Pose2D) -> str:
    return f"x={pose.x:+.2f} m, y={pose.y:+.2f} m, theta={math.degrees(pose.theta):+.0f} deg"


def _fmt_xyz(p: tuple[float, float, float]) -> str:
    return "(" + ", ".join(f"{v:g}" for v in p) + ")"


def _camera_index_row(path: Path, shot: CameraShot) -> str:
    axis_deg = math.degrees(shot.head_pitch_rad + NAO_HEAD.mount(shot.camera).pitch_rad)
    return (
        f"| [{path.name}]({path.name}) | {shot.robot_id} {shot.camera.value} camera, {_fmt_pose(shot.pose)}, "
        f"head yaw 0 deg, head pitch {math.degrees(shot.head_pitch_rad):.0f} deg down "
        f"(optical axis {axis_deg:.0f} deg down) | {shot.shows} |"
    )


def _kick_index_row(path: Path, times: list[float]) -> str:
    forward, left = KICK_BALL_OFFSET
    when = ", ".join(f"{t:.1f}" for t in times)
    return (
        f"| [{path.name}]({path.name}) | {KICKER} at {_fmt_pose(KICKER_POSE)}, ball {forward:.2f} m ahead and "
        f"{-left:.2f} m to its right; close overview frames, seen from its right, at t = {when} s "
        f"| a right-foot kick (`{Motion.KICK_RIGHT.value}`, {MOTION_SPECS[Motion.KICK_RIGHT].duration_s:.1f} s): "
        "wind-up, swing, ball rolling away toward the yellow goal, leg back to standing |"
    )


def _index_text(rows: list[str], seed: int) -> str:
    formation = ", ".join(f"{rid} ({p.x:+.1f}, {p.y:+.1f})" for rid, p in FORMATION.items())
    lines = [
        "# World demo",
        "",
        f"Written by `robotstadium world-demo --seed {seed}`. Field frame: origin at the centre spot, "
        "+x toward the yellow goal, +y to the left facing +x, theta counter-clockwise from +x.",
        "",
        f"Robot camera frames are 160x120 images enlarged {CAMERA_SCALE}x (nearest-neighbour) to "
        f"{160 * CAMERA_SCALE}x{120 * CAMERA_SCALE}. Before each frame every robot is placed in the "
        f"formation ({formation}; ball at the centre spot unless said otherwise), then the viewer is "
        "moved to the pose given.",
        "",
        "| Image | Taken from | Shows |",
        "| --- | --- | --- |",
        *rows,
        "",
    ]
    return "\n".join(lines)
