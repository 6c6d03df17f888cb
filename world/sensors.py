"""What a robot's own sensors read: the proprioceptive part of an observation."""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pybullet as pb

from world.camera_model import CameraPosition
from world.config import SonarConfig
from world.locomotion import MotionStatus
from world.robot_model import FEET, TORSO_CENTER_HEIGHT_M, Joint

GRAVITY_MPS2 = 9.81


@dataclass(frozen=True)
class SensorReading:
    """One robot's sensors after a control step (torso frame: x forward, y left, z up).

    ``accelerometer_mps2`` is the specific force (acceleration minus gravity), so an upright
    robot at rest reads about (0, 0, +9.81), one lying on its back about (+9.81, 0, 0) and
    one lying on its front about (-9.81, 0, 0).
    Sonars: upper-left, upper-right, lower-left, lower-right, in metres, ``max_range_m``
    when nothing is in range. Bumpers: left foot (left, right), right foot (left, right).
    """

    head_yaw_rad: float
    head_pitch_rad: float
    camera: CameraPosition
    accelerometer_mps2: tuple[float, float, float]
    gyro_radps: tuple[float, float, float]
    sonar_m: tuple[float, float, float, float]
    bumpers: tuple[bool, bool, bool, bool]
    motion: MotionStatus

    @property
    def fallen(self) -> bool:
        return self.motion.fallen


def to_torso(m: tuple[float, ...], vector: tuple[float, float, float]) -> tuple[float, float, float]:
    """Express a world vector in the torso frame (``m`` row-major torso->world rotation)."""
    x, y, z = vector
    return (m[0] * x + m[3] * y + m[6] * z, m[1] * x + m[4] * y + m[7] * z, m[2] * x + m[5] * y + m[8] * z)


def mean_angular_velocity(
    previous: tuple[float, float, float, float], current: tuple[float, float, float, float], dt_s: float
) -> tuple[float, float, float]:
    """The mean angular velocity (rad/s, torso frame) of a body that turned from orientation
    ``previous`` to ``current`` (pybullet quaternions x, y, z, w; torso->world) in ``dt_s``: the
    rotation vector of the turn between them over the time. The turn's axis is the same in the
    torso frame at the start and at the end."""
    px, py, pz, pw = previous
    cx, cy, cz, cw = current
    # conjugate(previous) * current: the turn in the torso frame at the start
    w = pw * cw + px * cx + py * cy + pz * cz
    x = pw * cx - px * cw - py * cz + pz * cy
    y = pw * cy + px * cz - py * cw - pz * cx
    z = pw * cz - px * cy + py * cx - pz * cw
    if w < 0.0:  # the same turn, the short way round
        w, x, y, z = -w, -x, -y, -z
    sine = math.sqrt(x * x + y * y + z * z)
    if sine < 1e-12:
        return (0.0, 0.0, 0.0)
    scale = 2.0 * math.atan2(sine, w) / sine / dt_s
    return (x * scale, y * scale, z * scale)


def sonar_rays(client: int, body: int, config: SonarConfig) -> list[tuple[tuple, tuple]]:
    """Rays (start, end) of one robot's four sonars, ``len(config.cone_offsets_rad)`` each.

    Each sonar is a fan of rays across its cone, starting just outside the torso; the
    sonar reads the nearest hit of its fan.
    """
    starts, ends = sonar_rays_batch(client, (body,), config)
    return [(tuple(start), tuple(end)) for start, end in zip(starts.tolist(), ends.tolist())]


def sonar_rays_batch(client: int, bodies: Sequence[int], config: SonarConfig) -> tuple[np.ndarray, np.ndarray]:
    """The sonar rays of several robots at once, as :func:`sonar_rays` in body order: starts and
    ends (n, 3), m, world frame (the same numbers, computed in the same order, for all robots)."""
    local_starts, local_directions = _sonar_layout(config)
    positions, rotations = [], []
    for body in bodies:
        position, orientation = pb.getBasePositionAndOrientation(body, physicsClientId=client)
        positions.append(position)
        rotations.append(pb.getMatrixFromQuaternion(orientation))
    m = np.asarray(rotations, float).reshape(-1, 1, 3, 3)  # torso -> world, row-major
    starts = np.asarray(positions, float)[:, None, :] + _rotate(m, local_starts)
    ends = starts + config.max_range_m * _rotate(m, local_directions)
    return starts.reshape(-1, 3), ends.reshape(-1, 3)


@functools.lru_cache(maxsize=4)
def _sonar_layout(config: SonarConfig) -> tuple[np.ndarray, np.ndarray]:
    """Every ray's start and unit direction in the torso frame (centre), sonar by sonar: (rays, 3) each."""
    starts, directions = [], []
    for height in (config.upper_height_m, config.lower_height_m):
        for side in (1.0, -1.0):
            for offset in config.cone_offsets_rad:
                yaw = side * config.yaw_rad + offset
                starts.append((0.06, side * 0.03, height - TORSO_CENTER_HEIGHT_M))
                directions.append((math.cos(yaw), math.sin(yaw), 0.0))
    return np.array(starts), np.array(directions)


def _rotate(m: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``m @ v`` for (robots, 1, 3, 3) rotations and (rays, 3) vectors, summed left to right: (robots, rays, 3)."""
    return m[..., 0] * v[None, :, 0:1] + m[..., 1] * v[None, :, 1:2] + m[..., 2] * v[None, :, 2:3]


def sonar_distances(hits, config: SonarConfig) -> tuple[float, ...]:
    """Distances of the four sonars from the rayTestBatch results of their rays."""
    per_sonar = len(config.cone_offsets_rad)
    out = []
    for i in range(4):
        nearest = config.max_range_m
        for hit in hits[i * per_sonar : (i + 1) * per_sonar]:
            if hit[0] >= 0:
                nearest = min(nearest, hit[2] * config.max_range_m)
        out.append(max(config.min_range_m, nearest))
    return tuple(out)


def bumpers(client: int, body: int, ground_ids: tuple[int, ...]) -> tuple[bool, bool, bool, bool]:
    """Foot bumpers: pressed by a contact on the front half of a foot with anything but the floor."""
    pressed = []
    for foot in FEET:
        left = right = False
        others = [c for c in pb.getContactPoints(bodyA=body, linkIndexA=int(foot), physicsClientId=client)
                  if c[2] not in ground_ids]
        if others:  # where the foot is matters only then
            state = pb.getLinkState(body, int(foot), physicsClientId=client)
            foot_position, foot_orientation = state[4], state[5]
            m = pb.getMatrixFromQuaternion(foot_orientation)
        for contact in others:
            rel = tuple(c - f for c, f in zip(contact[5], foot_position))
            local = to_torso(m, rel)
            if local[0] > 0.02:
                left, right = left or local[1] >= 0.0, right or local[1] < 0.0
        pressed += [left, right]
    return tuple(pressed)


def head_angles(client: int, body: int) -> tuple[float, float]:
    states = pb.getJointStates(body, [int(Joint.HEAD_YAW), int(Joint.HEAD_PITCH)], physicsClientId=client)
    return states[0][0], states[1][0]
