"""Oracle percepts: what a five-frame head scan would report, derived from the true pose.

The harness side of localization tests and measurements (it knows the true pose; agents
never import this). A landmark is seen when it is within ``max_range_m`` of the robot,
within ``scan_half_angle_rad`` of its heading (the scan of thesis Figure 5.1 covers about
206 degrees) and not nearer than ``min_range_m`` (by default :data:`MIN_RANGE_M`, where the
ground leaves the bottom of the scan frames). What each percept carries follows the vision
pipeline:

- goal posts come with their id (a post seen alone is told left or right by the crossbar
  frame; with ``lone_post_sides=False`` it stays without id, ``PostSide.UNKNOWN``);
- a goal centre is reported when both posts of its goal fall in one frame (yaws of
  :data:`agents.vision.head_scan.SCAN_YAWS_RAD`, 46 degrees wide);
- the centre circle comes with its id;
- L corners come without id, with the :class:`CornerShape` their two lines make in the
  frame whose yaw is nearest the corner: both lines leaving to the right is a left corner
  ("<"), both to the left a right corner (">"), otherwise up ("^") when the vertex lies
  above the chord of the two arms and down ("v") when below -- the continuous form of the
  pipeline's FindCorner rules (arms taken ``ARM_LENGTH_M`` long on the ground);
- T junctions come without id.

Distances are to the landmark's point (post centres), bearings CCW positive in the torso
frame. Noise: distance times ``1 + N(0, distance_sigma_rel)``, bearing plus
``N(0, bearing_sigma_rad)``. Percepts are ordered by bearing, left to right, as the scan's
frames come.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from agents.vision.head_scan import SCAN_PITCH_RAD, SCAN_YAWS_RAD
from agents.vision.percepts import CornerShape, LandmarkPercept, PostSide
from world.camera_model import NAO_CAMERA, NAO_HEAD, CameraPosition, world_to_camera
from world.field import FIELD, FieldGeometry, GoalColor, Landmark, LandmarkId, LandmarkKind, Pose2D, normalize_angle

CAMERA_MODEL_NAME = "oracle"
ARM_LENGTH_M = 0.2  # how far along each line of an L corner its image direction is taken
SCAN_HALF_ANGLE_RAD = math.radians(103.0)  # thesis 5: the scan covers 206 degrees


def _nearest_ground_m() -> float:
    """Ground distance (from the torso) of the image's bottom row at the scan's head pitch."""
    rotation, position = NAO_HEAD.camera_in_torso(0.0, SCAN_PITCH_RAD, CameraPosition.TOP)
    centre_u = NAO_CAMERA.principal_point[0] - 0.5
    ray = rotation @ NAO_CAMERA.pixel_ray(centre_u, NAO_CAMERA.height_px - 1.0)
    ground = position - position[2] / ray[2] * ray
    return float(math.hypot(ground[0], ground[1]))


MIN_RANGE_M = _nearest_ground_m()  # about 0.79 m: nearer ground is below every scan frame


def to_torso(pose: Pose2D, x: float, y: float) -> tuple[float, float]:
    """A field point in the torso frame of a robot at ``pose`` (x forward, y left), metres."""
    dx, dy = x - pose.x, y - pose.y
    c, s = math.cos(pose.theta), math.sin(pose.theta)
    return c * dx + s * dy, -s * dx + c * dy


def corner_arms(landmark: Landmark, field: FieldGeometry = FIELD) -> tuple[tuple[float, float], tuple[float, float]]:
    """Unit directions (field frame) of the two painted lines leaving an L corner."""
    sx, sy = math.copysign(1.0, landmark.x), math.copysign(1.0, landmark.y)
    if math.isclose(abs(landmark.x), field.half_length):
        return (-sx, 0.0), (0.0, -sy)  # along the end line and the side line, into the field
    return (sx, 0.0), (0.0, -sy)  # goal area: toward the end line, and along its front line


def nearest_frame_yaw(bearing_rad: float, yaws_rad: tuple[float, ...] = SCAN_YAWS_RAD) -> float:
    return min(yaws_rad, key=lambda yaw: abs(normalize_angle(bearing_rad - yaw)))


def _project(points_torso: np.ndarray, yaw_rad: float) -> np.ndarray:
    rotation, position = NAO_HEAD.camera_in_torso(yaw_rad, SCAN_PITCH_RAD, CameraPosition.TOP)
    ground = np.column_stack([points_torso, np.zeros(len(points_torso))])
    return NAO_CAMERA.project(world_to_camera(ground, rotation, position))


def corner_shape(
    pose: Pose2D, landmark: Landmark, field: FieldGeometry = FIELD
) -> tuple[CornerShape | None, tuple[float, float]]:
    """The shape an L corner makes in the scan frame nearest it, and its pixel (module docstring)."""
    vx, vy = to_torso(pose, landmark.x, landmark.y)
    yaw = nearest_frame_yaw(math.atan2(vy, vx))
    arms = []
    for ax, ay in corner_arms(landmark, field):
        length = ARM_LENGTH_M
        for _ in range(8):  # shorten an arm that reaches behind the camera
            end = to_torso(pose, landmark.x + length * ax, landmark.y + length * ay)
            pixels = _project(np.array([[vx, vy], end]), yaw)
            if np.isfinite(pixels).all():
                break
            length /= 2.0
        else:
            return None, (math.nan, math.nan)
        arms.append(pixels[1] - pixels[0])
    vertex = (float(pixels[0][0]), float(pixels[0][1]))
    du1, du2 = arms[0][0], arms[1][0]
    if du1 > 0 and du2 > 0:
        return CornerShape.LEFT, vertex
    if du1 < 0 and du2 < 0:
        return CornerShape.RIGHT, vertex
    (dul, dvl), (dur, dvr) = sorted(arms, key=lambda arm: arm[0])
    if dul == 0.0 or dur == 0.0:
        return None, vertex
    return (CornerShape.UP if dvl / dul < dvr / dur else CornerShape.DOWN), vertex


def _in_one_frame(bearings: list[float], yaws_rad: tuple[float, ...] = SCAN_YAWS_RAD) -> bool:
    half = NAO_CAMERA.horizontal_fov_rad / 2.0
    return any(all(abs(normalize_angle(b - yaw)) <= half for b in bearings) for yaw in yaws_rad)


def _pixel(pose: Pose2D, landmark: Landmark) -> tuple[float, float]:
    vx, vy = to_torso(pose, landmark.x, landmark.y)
    u, v = _project(np.array([[vx, vy]]), nearest_frame_yaw(math.atan2(vy, vx)))[0]
    return float(u), float(v)


def oracle_percepts(
    pose: Pose2D,
    rng: np.random.Generator | None,
    distance_sigma_rel: float = 0.0,
    bearing_sigma_rad: float = 0.0,
    max_range_m: float = 4.0,
    scan_half_angle_rad: float = SCAN_HALF_ANGLE_RAD,
    min_range_m: float = MIN_RANGE_M,
    lone_post_sides: bool = True,
    field: FieldGeometry = FIELD,
) -> tuple[LandmarkPercept, ...]:
    """The percepts of one head scan from ``pose`` (module docstring); ``rng`` may be None without noise."""
    if (distance_sigma_rel or bearing_sigma_rad) and rng is None:
        raise ValueError("oracle_percepts needs an rng for noise; got rng=None")
    seen: dict[LandmarkId, tuple[float, float]] = {}
    for lm in field.landmarks:
        tx, ty = to_torso(pose, lm.x, lm.y)
        distance, bearing = math.hypot(tx, ty), math.atan2(ty, tx)
        if min_range_m <= distance <= max_range_m and abs(bearing) <= scan_half_angle_rad:
            seen[lm.id] = (distance, bearing)

    found: list[LandmarkPercept] = []
    for color in GoalColor:
        left, right = LandmarkId[f"{color.name}_GOAL_LEFT_POST"], LandmarkId[f"{color.name}_GOAL_RIGHT_POST"]
        pair = left in seen and right in seen and _in_one_frame([seen[left][1], seen[right][1]])
        for post in (left, right):
            if post in seen:
                side = PostSide.PAIR if pair else PostSide.CROSSBAR if lone_post_sides else PostSide.UNKNOWN
                known = side is not PostSide.UNKNOWN
                found.append(_percept(pose, field.landmark(post), seen[post], post if known else None, post_side=side))
        center = LandmarkId[f"{color.name}_GOAL_CENTER"]
        if pair:
            cx, cy = to_torso(pose, field.landmark(center).x, field.landmark(center).y)
            found.append(_percept(pose, field.landmark(center), (math.hypot(cx, cy), math.atan2(cy, cx)), center))
    for landmark_id, measured in seen.items():
        lm = field.landmark(landmark_id)
        if lm.kind is LandmarkKind.CENTER_CIRCLE:
            found.append(_percept(pose, lm, measured, landmark_id))
        elif lm.kind is LandmarkKind.T_JUNCTION:
            found.append(_percept(pose, lm, measured, None))
        elif lm.kind is LandmarkKind.L_CORNER:
            shape, pixel = corner_shape(pose, lm, field)
            if shape is not None:
                found.append(_percept(pose, lm, measured, None, corner=shape, pixel=pixel))
    if rng is not None and (distance_sigma_rel or bearing_sigma_rad):
        found = [_noisy(p, rng, distance_sigma_rel, bearing_sigma_rad) for p in found]
    return tuple(sorted(found, key=lambda p: -p.bearing_rad))


def _percept(
    pose: Pose2D,
    landmark: Landmark,
    measured: tuple[float, float],
    landmark_id: LandmarkId | None,
    corner: CornerShape | None = None,
    post_side: PostSide | None = None,
    pixel: tuple[float, float] | None = None,
) -> LandmarkPercept:
    distance, bearing = measured
    return LandmarkPercept(
        landmark.kind,
        pixel if pixel is not None else _pixel(pose, landmark),
        bearing,
        distance,
        CAMERA_MODEL_NAME,
        landmark_id=landmark_id,
        goal=landmark.goal if landmark.kind in (LandmarkKind.GOAL_POST, LandmarkKind.GOAL_CENTER) else None,
        corner=corner,
        post_side=post_side,
    )


def _noisy(percept: LandmarkPercept, rng: np.random.Generator, sigma_rel: float, sigma_rad: float) -> LandmarkPercept:
    distance = percept.distance_m * (1.0 + sigma_rel * float(rng.normal()))
    bearing = normalize_angle(percept.bearing_rad + sigma_rad * float(rng.normal()))
    return dataclasses.replace(percept, distance_m=max(distance, 0.0), bearing_rad=bearing)
