"""The vision of a camera frame gives what it gave before it was made faster: pinned results.

The frames are painted here from the field's geometry, without the renderer: the ground
point of every pixel's ray is carpet or painted line, goal posts are cylinders, the ball a
sphere, and waistbands pixel patches, each in the centre colour of its calibrated class.
The pinned percepts, ball and robots were computed by the vision code of commit e58ec10
(before the speed work); floats must agree to 1e-9 (relative). The field-line fits now agree
with exact arithmetic where the old ``lstsq`` was off by up to 1e-9 px, so a fit landing
exactly on a threshold of Table 4.3 may classify differently; these frames have none.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pytest

from agents.vision.ball import ball_in_mask
from agents.vision.colors import ColorClass
from agents.vision.frame import CameraFrame
from agents.vision.percepts import LandmarkPercept
from agents.vision.pipeline import VisionPipeline
from agents.vision.robots import find_robots
from agents.vision.segmentation import load_thresholds
from match.protocol import TeamColor
from world.camera_model import NAO_CAMERA, NAO_HEAD, CameraPosition
from world.field import FIELD, GoalColor, LineSegment

OWN_TEAM = TeamColor.BLUE


@dataclass(frozen=True)
class Case:
    """A painted frame: robot pose on the field (m, rad), head angles (rad), camera, accelerometer
    (m/s^2), the ball's field position (m) and waistband patches (class, left, top, right, bottom px)."""

    pose: tuple[float, float, float]
    head_yaw_rad: float
    head_pitch_rad: float = math.radians(17.0)
    camera: CameraPosition = CameraPosition.TOP
    accelerometer_mps2: tuple[float, float, float] | None = None
    ball_xy: tuple[float, float] | None = None
    bands: tuple[tuple[ColorClass, int, int, int, int], ...] = ()
    model: str = "exact"


TILT = math.radians(15.0)
LEANING = (9.81 * math.sin(TILT), 0.0, 9.81 * math.cos(TILT))  # the torso leaning forward: the tilt correction
BANDS = ((ColorClass.MAGENTA, 10, 20, 30, 24), (ColorClass.CYAN, 100, 30, 106, 33), (ColorClass.CYAN, 110, 30, 116, 33))
CASES = {
    "circle and goal": Case((1.8, -0.7, 2.2), math.radians(40.0)),
    "goal and L corner": Case((1.3, -1.9, -0.7), math.radians(80.0)),
    "goal and T junction": Case((1.8, -2.0, 2.7), 0.0),
    "L corner and T junction": Case((-1.5, 0.2, -1.3), math.radians(-40.0)),
    "thesis model": Case((-1.5, 0.2, -1.3), math.radians(-40.0), model="thesis"),
    "tilted body": Case((1.3, -1.9, -0.7), math.radians(80.0), accelerometer_mps2=LEANING),
    "lone post": Case((0.8, 1.6, 1.7), math.radians(80.0)),
    "ball cut by the image side": Case((0.0, 0.0, 0.0), 0.1, 0.3, CameraPosition.BOTTOM, ball_xy=(0.2, 0.2)),
    "ball and robots": Case((0.0, 0.0, 0.0), 0.1, 0.3, CameraPosition.BOTTOM, ball_xy=(0.45, 0.05), bands=BANDS),
}


def class_rgb(color: ColorClass) -> np.ndarray:
    """The centre of the calibrated RGB range of ``color``."""
    box = load_thresholds().box(color)
    return np.array([(lo + hi) // 2 for lo, hi in zip(box.low, box.high)], np.uint8)


def _segment_gap(x: np.ndarray, y: np.ndarray, segment: LineSegment) -> np.ndarray:
    """Distance (m) of field points from a line segment."""
    dx, dy = segment.x1 - segment.x0, segment.y1 - segment.y0
    t = np.clip(((x - segment.x0) * dx + (y - segment.y0) * dy) / (dx * dx + dy * dy), 0.0, 1.0)
    return np.hypot(x - segment.x0 - t * dx, y - segment.y0 - t * dy)


def _nearest_hit(origin: np.ndarray, rays: np.ndarray, centre: tuple[float, float, float], radius: float, axis: bool):
    """Ray parameter of the first hit of a sphere (``axis`` False) or a vertical cylinder, inf if none."""
    d = origin - np.asarray(centre)
    keep = [0, 1] if axis else [0, 1, 2]
    a = (rays[..., keep] ** 2).sum(-1)
    b = rays[..., keep] @ d[keep]
    disc = b * b - a * (d[keep] @ d[keep] - radius * radius)
    with np.errstate(divide="ignore", invalid="ignore"):
        hit = np.where(disc >= 0.0, (-b - np.sqrt(np.maximum(disc, 0.0))) / a, np.inf)
    return np.where(hit > 0.0, hit, np.inf)


def painted_image(case: Case) -> np.ndarray:
    """The 160x120 RGB image of ``case`` (module docstring); above the carpet it is white."""
    x, y, theta = case.pose
    rotation, position = NAO_HEAD.camera_in_torso(case.head_yaw_rad, case.head_pitch_rad, case.camera)
    to_field = np.array([[math.cos(theta), -math.sin(theta), 0.0], [math.sin(theta), math.cos(theta), 0.0], [0, 0, 1]])
    v, u = np.mgrid[0 : NAO_CAMERA.height_px, 0 : NAO_CAMERA.width_px].astype(float)
    rays = NAO_CAMERA.pixel_ray(u, v) @ (to_field @ rotation).T
    origin = to_field @ position + np.array([x, y, 0.0])
    image = np.empty(u.shape + (3,), np.uint8)
    image[:] = class_rgb(ColorClass.WHITE)
    with np.errstate(divide="ignore"):
        ground = np.where(rays[..., 2] < -1e-9, -origin[2] / rays[..., 2], np.nan)  # NaN: the ray misses the ground
    gx, gy = origin[0] + ground * rays[..., 0], origin[1] + ground * rays[..., 1]
    carpet = (np.abs(gx) <= FIELD.carpet_half_length) & (np.abs(gy) <= FIELD.carpet_half_width)
    nearest = np.where(carpet, ground, np.inf)
    half = FIELD.line_width / 2.0
    circle = FIELD.center_circle
    painted = np.abs(np.hypot(gx - circle.cx, gy - circle.cy) - circle.radius) <= half
    for segment in FIELD.line_segments:
        painted |= _segment_gap(gx, gy, segment) <= half
    image[carpet] = class_rgb(ColorClass.GREEN)
    image[carpet & painted] = class_rgb(ColorClass.WHITE)
    for goal, color in ((GoalColor.BLUE, ColorClass.BLUE), (GoalColor.YELLOW, ColorClass.YELLOW)):
        for post_y in (-FIELD.goal_post_y, FIELD.goal_post_y):
            post = (FIELD.goal_line_x(goal), post_y, 0.0)
            hit = _nearest_hit(origin, rays, post, FIELD.goal_post_radius, axis=True)
            height = origin[2] + hit * rays[..., 2]
            seen = (hit < nearest) & (height >= 0.0) & (height <= FIELD.goal_height)
            image[seen] = class_rgb(color)
            nearest = np.where(seen, hit, nearest)
    if case.ball_xy is not None:
        hit = _nearest_hit(origin, rays, (*case.ball_xy, FIELD.ball_radius), FIELD.ball_radius, axis=False)
        image[hit < nearest] = class_rgb(ColorClass.ORANGE)
    for color, left, top, right, bottom in case.bands:
        image[top:bottom, left:right] = class_rgb(color)
    return image


def percept_row(p: LandmarkPercept) -> tuple:
    names = tuple(None if e is None else e.name for e in (p.landmark_id, p.goal, p.corner, p.post_side))
    return (p.kind.name, *names, *p.pixel, p.bearing_rad, p.distance_m)


def ball_row(ball) -> tuple | None:
    return None if ball is None else (ball.pixel_u, ball.pixel_v, ball.bearing_rad, ball.distance_m, ball.pixels)


def robot_row(robot) -> tuple:
    return robot.team.name, robot.kind.name, robot.box, *robot.pixel, robot.bearing_rad, robot.distance_m, robot.pixels


# Computed with the vision code of commit e58ec10 (percepts, ball, robots).
PINNED: dict[str, tuple] = {  # name: (percepts, ball, robots)
    'circle and goal': (
        (
            ('GOAL_POST', 'BLUE_GOAL_LEFT_POST', 'BLUE', None, 'PAIR', 28.636363636, 23.5, 0.95483693031, 4.809760786),
            ('GOAL_POST', 'BLUE_GOAL_RIGHT_POST', 'BLUE', None, 'PAIR', 89.5, 21.5, 0.64665074632, 5.1378347542),
            ('GOAL_CENTER', 'BLUE_GOAL_CENTER', 'BLUE', None, None, 59.068181818, 22.5, 0.79562124839, 4.9149283878),
            ('CENTER_CIRCLE', 'CENTER_CIRCLE', None, None, None, 105.0, 74.5, 0.5723844013, 1.9073768775),
        ),
        None,
        (),
    ),
    'goal and L corner': (
        (
            ('GOAL_POST', 'YELLOW_GOAL_LEFT_POST', 'YELLOW', None, 'PAIR', 18.5, 35.5, 1.703989898, 3.1270511656),
            ('GOAL_POST', 'YELLOW_GOAL_RIGHT_POST', 'YELLOW', None, 'PAIR', 99.0, 50.5, 1.2937938517, 2.0640885298),
            ('GOAL_CENTER', 'YELLOW_GOAL_CENTER', 'YELLOW', None, None, 58.75, 43.0, 1.5414619434, 2.5434736727),
            ('L_CORNER', None, None, 'DOWN', None, 91.893966458, 72.208501207, 1.3298377345, 1.3638207733),
        ),
        None,
        (),
    ),
    'goal and T junction': (
        (
            ('GOAL_POST', 'BLUE_GOAL_LEFT_POST', 'BLUE', None, 'PAIR', 42.5, 22.5, 0.1885325501, 4.9680151214),
            ('GOAL_POST', 'BLUE_GOAL_RIGHT_POST', 'BLUE', None, 'PAIR', 95.0, 20.5, -0.079634312391, 5.4252298773),
            ('GOAL_CENTER', 'BLUE_GOAL_CENTER', 'BLUE', None, None, 68.75, 21.5, 0.048515048388, 5.1500697262),
            ('T_JUNCTION', None, None, None, None, 130.0, 45.0, -0.25916253367, 2.3475010085),
        ),
        None,
        (),
    ),
    'L corner and T junction': (
        (
            ('L_CORNER', None, None, 'LEFT', None, 113.82303939, 64.014459122, -0.87912261, 1.5763932406),
            ('T_JUNCTION', None, None, None, None, 155.0, 55.0, -1.0782825327, 1.9676051298),
        ),
        None,
        (),
    ),
    'thesis model': (
        (
            ('L_CORNER', None, None, 'RIGHT', None, 155.0, 55.0, -1.0769772316, 1.9495895365),
            ('L_CORNER', None, None, 'LEFT', None, 113.82303939, 64.014459122, -0.87035858921, 1.5671722601),
        ),
        None,
        (),
    ),
    'tilted body': (
        (
            ('GOAL_POST', 'YELLOW_GOAL_LEFT_POST', 'YELLOW', None, 'PAIR', 18.5, 35.5, 1.7070264055, 2.5832251055),
            ('GOAL_POST', 'YELLOW_GOAL_RIGHT_POST', 'YELLOW', None, 'PAIR', 99.0, 50.5, 1.2834111056, 2.8981819098),
            ('GOAL_CENTER', 'YELLOW_GOAL_CENTER', 'YELLOW', None, None, 58.75, 43.0, 1.4828637812, 2.6796601372),
            ('L_CORNER', None, None, 'DOWN', None, 91.893966458, 72.208501207, 1.3210406924, 1.6438666458),
        ),
        None,
        (),
    ),
    'lone post': (
        (
            ('GOAL_POST', None, 'BLUE', None, 'UNKNOWN', 27.0, 28.5, 1.661853785, 3.9096363725),
        ),
        None,
        (),
    ),
    'ball cut by the image side': (
        (),
        (3.1726060578, 96.619404444, 0.78264563573, 0.28262552856, 421),
        (),
    ),
    'ball and robots': (
        (),
        (77.897849462, 22.911290323, 0.11063153636, 0.45348523932, 372),
        (
            ('RED', 'OPPONENT', (10, 20, 20, 4), 19.5, 21.5, 0.42990796392, 0.29123151444, 80),
            ('BLUE', 'TEAMMATE', (100, 30, 16, 3), 107.5, 31.0, -0.064403495776, 0.26480611813, 36),
        ),
    ),
}


def _assert_rows_equal(got, expected) -> None:
    assert len(got) == len(expected)
    for value, pinned in zip(got, expected):
        if isinstance(pinned, float):
            assert value == pytest.approx(pinned, rel=1e-9, abs=1e-12)
        elif isinstance(pinned, tuple):
            _assert_rows_equal(value, pinned)
        else:
            assert value == pinned


@pytest.mark.parametrize("name", sorted(CASES))
def test_a_painted_frame_gives_its_pinned_results(name: str):
    case = CASES[name]
    yaw, pitch = case.head_yaw_rad, case.head_pitch_rad
    frame = CameraFrame(painted_image(case), yaw, pitch, case.camera, case.accelerometer_mps2)
    result = VisionPipeline(case.model).process(frame)
    ball = ball_in_mask(result.segmented == int(ColorClass.ORANGE), yaw, pitch, case.camera)
    robots = find_robots(result.segmented, yaw, pitch, case.camera, OWN_TEAM)
    percepts, pinned_ball, pinned_robots = PINNED[name]
    _assert_rows_equal(tuple(percept_row(p) for p in result.percepts), percepts)
    assert (ball is None) == (pinned_ball is None)
    if ball is not None:
        _assert_rows_equal(ball_row(ball), pinned_ball)
    _assert_rows_equal(tuple(robot_row(r) for r in robots), pinned_robots)
