"""Which field landmarks one robot's camera truly shows: ground truth from the world.

Visibility, from the TRUE camera pose (:meth:`World.camera_pose`), the pinhole model
(:data:`world.camera_model.NAO_CAMERA`) and pybullet ray tests:

- a point landmark (L corner, T junction, goal post) is visible when its ground point
  projects into the image, lies within ``max_range_m`` of the robot, and the ray from the
  camera to ``RAY_TARGET_HEIGHT_M`` above that point hits no robot first. For a post the
  ground point is the point of the post's base facing the camera (the centre moved one
  post radius toward it), the pixel the post detector uses; its position for scoring is
  the post centre, which the detector's distance refers to;
- a goal centre is visible when both posts of its goal are;
- the centre circle is visible when its centre spot is within ``max_range_m`` and at least
  ``CIRCLE_MIN_FRACTION`` of ``CIRCLE_SAMPLES`` points along the painted circle are in the
  image and unoccluded (the pipeline fits the circle to its visible arc).
"""

from __future__ import annotations

import math

import numpy as np
import pybullet as pb

from scenarios.perception.scoring import TrueLandmark
from world.camera_model import NAO_CAMERA, world_to_camera
from world.field import FIELD, LandmarkKind, Pose2D
from world.world import World

RAY_TARGET_HEIGHT_M = 0.03  # ray end above the ground: a landmark is seen if its ground paint is
CIRCLE_SAMPLES = 64
CIRCLE_MIN_FRACTION = 0.25


def to_torso(pose: Pose2D, x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Field points (x, y) in the torso frame of a robot at ``pose`` (x forward, y left)."""
    dx, dy = np.asarray(x, float) - pose.x, np.asarray(y, float) - pose.y
    c, s = math.cos(pose.theta), math.sin(pose.theta)
    return c * dx + s * dy, -s * dx + c * dy


def _occluded(world: World, origin: np.ndarray, targets: np.ndarray, robot_bodies: frozenset[int]) -> np.ndarray:
    """For each target (N, 3), whether the ray from ``origin`` hits a robot body before it."""
    if len(targets) == 0:
        return np.zeros(0, bool)
    hits = pb.rayTestBatch([origin.tolist()] * len(targets), targets.tolist(), physicsClientId=world.client)
    return np.array([hit[0] in robot_bodies for hit in hits], bool)


def true_landmarks(world: World, robot_id: str, max_range_m: float) -> tuple[TrueLandmark, ...]:
    """All 17 landmarks in the torso frame of ``robot_id``, each marked visible or not (module docstring)."""
    pose = world.robot_truth(robot_id).pose
    rotation, position = world.camera_pose(robot_id)
    robot_bodies = frozenset(world.body_id(r) for r in world.robot_ids)
    landmarks = FIELD.landmarks
    lx = np.array([lm.x for lm in landmarks])
    ly = np.array([lm.y for lm in landmarks])
    # The ground point each landmark is seen by: posts by their base facing the camera.
    gx, gy = lx.copy(), ly.copy()
    for i, lm in enumerate(landmarks):
        if lm.kind is LandmarkKind.GOAL_POST:
            toward = np.array([position[0] - lm.x, position[1] - lm.y])
            toward /= max(float(np.linalg.norm(toward)), 1e-9)
            gx[i] += FIELD.goal_post_radius * toward[0]
            gy[i] += FIELD.goal_post_radius * toward[1]
    ground = np.stack([gx, gy, np.zeros_like(gx)], axis=1)
    in_image = NAO_CAMERA.in_image(NAO_CAMERA.project(world_to_camera(ground, rotation, position)))
    in_range = np.hypot(lx - pose.x, ly - pose.y) <= max_range_m
    point_kinds = (LandmarkKind.GOAL_POST, LandmarkKind.L_CORNER, LandmarkKind.T_JUNCTION)
    candidates = np.array([lm.kind in point_kinds for lm in landmarks]) & in_image & in_range

    circle = FIELD.center_circle
    angles = np.linspace(0.0, 2.0 * math.pi, CIRCLE_SAMPLES, endpoint=False)
    arc = np.stack(
        [circle.cx + circle.radius * np.cos(angles), circle.cy + circle.radius * np.sin(angles), np.zeros_like(angles)],
        axis=1,
    )
    arc_in_image = NAO_CAMERA.in_image(NAO_CAMERA.project(world_to_camera(arc, rotation, position)))
    circle_in_range = math.hypot(circle.cx - pose.x, circle.cy - pose.y) <= max_range_m
    if not circle_in_range or arc_in_image.mean() < CIRCLE_MIN_FRACTION:
        arc_in_image[:] = False  # no use ray-testing a circle that cannot be visible

    targets = np.concatenate([ground[candidates], arc[arc_in_image]])
    targets[:, 2] = RAY_TARGET_HEIGHT_M
    occluded = _occluded(world, np.asarray(position, float), targets, robot_bodies)
    point_visible = np.zeros(len(landmarks), bool)
    point_visible[candidates] = ~occluded[: int(candidates.sum())]
    arc_seen = int((~occluded[int(candidates.sum()) :]).sum())
    circle_visible = circle_in_range and arc_seen >= CIRCLE_MIN_FRACTION * CIRCLE_SAMPLES

    visible_ids = {lm.id for lm, seen in zip(landmarks, point_visible) if seen}
    tx, ty = to_torso(pose, lx, ly)
    found = []
    for i, lm in enumerate(landmarks):
        if lm.kind is LandmarkKind.GOAL_CENTER:
            posts = [p.id for p in landmarks if p.kind is LandmarkKind.GOAL_POST and p.goal is lm.goal]
            seen = all(p in visible_ids for p in posts)
        elif lm.kind is LandmarkKind.CENTER_CIRCLE:
            seen = circle_visible
        else:
            seen = bool(point_visible[i])
        found.append(TrueLandmark(lm, float(tx[i]), float(ty[i]), seen))
    return tuple(found)


def project_landmarks(world: World, robot_id: str, truths: tuple[TrueLandmark, ...]) -> list[tuple[float, float] | None]:
    """Pixel (u, v) of each landmark's ground point in the robot's true camera, or None outside the image."""
    rotation, position = world.camera_pose(robot_id)
    points = np.array([[t.landmark.x, t.landmark.y, 0.0] for t in truths])
    pixels = NAO_CAMERA.project(world_to_camera(points, rotation, position))
    inside = NAO_CAMERA.in_image(pixels)
    return [(float(p[0]), float(p[1])) if ok else None for p, ok in zip(pixels, inside)]
