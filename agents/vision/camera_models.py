"""From a pixel to a direction and a ground distance (thesis section 4.2).

Two models, chosen by name:

- ``thesis``: the thesis' formulas. Angles are linear in the pixel coordinates (horizontal
  field of view 46 degrees, vertical 34), the head angles and the camera's offset angle are
  added, and the ground distance comes from a camera 0.51 m above flat ground.
- ``exact`` (the default): the true pinhole camera of :mod:`world.camera_model`, placed by
  the head yaw and pitch and the camera's mount, tilted with the body as the accelerometer
  says, and the pixel's ray intersected with the ground.

Both return bearings counter-clockwise positive in the torso frame (the thesis measures
clockwise positive; this is the one place where that is converted) and distances in
metres on the ground from the point below the torso. Pixel coordinates are continuous
image coordinates in pixel-index units: ``(u, v)`` is the centre of column ``u``, row
``v``; ``v + 0.5`` is the lower edge of row ``v``.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from agents.vision.errors import VisionConfigError
from agents.vision.frame import CameraFrame
from agents.vision.kernels import ground_points
from world.camera_model import NAO_CAMERA, NAO_HEAD, CameraIntrinsics, CameraPosition, HeadKinematics

GRAVITY_MPS2 = 9.81
MAX_TILT_ACCEL_DEVIATION_MPS2 = 1.0  # trust the accelerometer's tilt only when it reads about 1 g ...
MIN_TILT_RAD = math.radians(10.0)  # ... and only a tilt above the noise of a robot standing still
# (measured: the simulated accelerometer of a standing robot swings up to about 1 m/s^2
# sideways from one step to the next, a 6 degree tilt, while the torso tilts under 0.5 degree)


@dataclass(frozen=True)
class GroundPoints:
    """Bearings (rad, CCW, torso frame) and ground distances (m) of pixels; NaN above the horizon."""

    bearing_rad: np.ndarray
    distance_m: np.ndarray

    @property
    def valid(self) -> np.ndarray:
        return np.isfinite(self.distance_m)

    def xy(self) -> np.ndarray:
        """Ground points (N, 2) in the torso frame (x forward, y left), metres."""
        return np.stack([self.distance_m * np.cos(self.bearing_rad), self.distance_m * np.sin(self.bearing_rad)], -1)


class CameraModel(Protocol):
    name: str

    def locate(self, frame: CameraFrame, u: np.ndarray, v: np.ndarray) -> GroundPoints:
        """Bearing and ground distance of the pixels ``(u, v)`` of ``frame``."""


@dataclass(frozen=True)
class ThesisCameraModel:
    """The thesis' section 4.2 formulas.

    DirectionAngle = (w / width - 0.5) * HFOV and ElevationAngle = -(h / height - 0.5) * VFOV,
    with ``w``, ``h`` continuous image coordinates (``u + 0.5``, ``v + 0.5``), clockwise and
    up positive; Direction = DirectionAngle + head yaw; Elevation = ElevationAngle + head
    vertical angle + camera offset angle; y = 0.51 / tan(-Elevation),
    x = y * tan(-DirectionAngle), d = sqrt(x^2 + y^2).
    """

    name: str = "thesis"
    horizontal_fov_rad: float = math.radians(46.0)  # thesis 3.1
    vertical_fov_rad: float = math.radians(34.0)  # thesis 3.1
    camera_height_m: float = 0.51  # thesis 4.2
    width_px: int = NAO_CAMERA.width_px
    height_px: int = NAO_CAMERA.height_px
    head: HeadKinematics = NAO_HEAD

    def locate(self, frame: CameraFrame, u: np.ndarray, v: np.ndarray) -> GroundPoints:
        u, v = np.broadcast_arrays(np.asarray(u, float), np.asarray(v, float))
        direction_angle = ((u + 0.5) / self.width_px - 0.5) * self.horizontal_fov_rad  # clockwise positive
        elevation_angle = -((v + 0.5) / self.height_px - 0.5) * self.vertical_fov_rad  # up positive
        head_horizontal = -frame.head_yaw_rad  # our yaw is CCW positive
        head_vertical = -frame.head_pitch_rad  # our pitch is positive down
        camera_offset = -self.head.mount(frame.camera).pitch_rad
        elevation = elevation_angle + head_vertical + camera_offset
        direction = direction_angle + head_horizontal
        with np.errstate(divide="ignore", invalid="ignore"):
            y = np.where(elevation < 0.0, self.camera_height_m / np.tan(-elevation), np.nan)
            x = y * np.tan(-direction_angle)
            distance = np.hypot(x, y)
        return GroundPoints(-direction, distance)


@dataclass(frozen=True)
class ExactCameraModel:
    """The pinhole camera on the head kinematics, tilted with the body, rays meeting the ground."""

    name: str = "exact"
    intrinsics: CameraIntrinsics = NAO_CAMERA
    head: HeadKinematics = NAO_HEAD
    min_tilt_rad: float = MIN_TILT_RAD

    def camera_pose(self, frame: CameraFrame) -> tuple[np.ndarray, np.ndarray]:
        """Camera rotation (camera -> level torso frame) and position (m) for ``frame``; read-only, cached."""
        accel = frame.accelerometer_mps2
        if accel is not None and not isinstance(accel, tuple):  # the cache's key must be hashable
            accel = tuple(np.asarray(accel, float).reshape(-1).tolist())
        yaw, pitch = frame.head_yaw_rad, frame.head_pitch_rad
        return level_camera_pose(self.head, yaw, pitch, frame.camera, accel, self.min_tilt_rad)

    def locate(self, frame: CameraFrame, u: np.ndarray, v: np.ndarray) -> GroundPoints:
        """Each pixel's ray (:meth:`~world.camera_model.CameraIntrinsics.rotated_pixel_rays`) met with the
        ground, in compiled code (:func:`agents.vision.kernels.ground_points`)."""
        rotation, position = self.camera_pose(frame)
        u, v = np.broadcast_arrays(np.asarray(u, float), np.asarray(v, float))
        cx, cy = self.intrinsics.principal_point
        bearing, distance = ground_points(np.ascontiguousarray(u.reshape(-1)), np.ascontiguousarray(v.reshape(-1)),
                                          rotation, position, float(cx), float(cy), float(self.intrinsics.focal_px))
        return GroundPoints(bearing.reshape(u.shape), distance.reshape(u.shape))

    def project(self, frame: CameraFrame, points_torso: np.ndarray) -> np.ndarray:
        """Pixels (N, 2) of points (N, 3) given in the level torso frame; NaN behind the camera."""
        rotation, position = self.camera_pose(frame)
        camera_points = (np.asarray(points_torso, float).reshape(-1, 3) - position) @ rotation
        return self.intrinsics.project(camera_points)


@functools.lru_cache(maxsize=64)
def torso_camera_pose(
    head: HeadKinematics, head_yaw_rad: float, head_pitch_rad: float, camera: CameraPosition
) -> tuple[np.ndarray, np.ndarray]:
    """:meth:`HeadKinematics.camera_in_torso` as read-only arrays, cached: every stage of a frame, and its
    ball and robots, locate pixels with one pose."""
    rotation, position = head.camera_in_torso(head_yaw_rad, head_pitch_rad, camera)
    rotation.setflags(write=False)
    position.setflags(write=False)
    return rotation, position


@functools.lru_cache(maxsize=64)
def level_camera_pose(
    head: HeadKinematics,
    head_yaw_rad: float,
    head_pitch_rad: float,
    camera: CameraPosition,
    accelerometer_mps2: tuple[float, float, float] | None,
    min_tilt_rad: float = MIN_TILT_RAD,
) -> tuple[np.ndarray, np.ndarray]:
    """Camera rotation (camera -> level torso frame) and position (m), read-only arrays, cached."""
    rotation, position = torso_camera_pose(head, head_yaw_rad, head_pitch_rad, camera)
    tilt = _tilt_rotation(accelerometer_mps2, min_tilt_rad)
    if tilt is None:
        return rotation, position  # what the product with the identity would be
    rotation, position = tilt @ rotation, tilt @ position
    rotation.setflags(write=False)
    position.setflags(write=False)
    return rotation, position


def level_rotation(accelerometer_mps2: tuple[float, float, float] | None, min_tilt_rad: float = MIN_TILT_RAD) -> np.ndarray:
    """Rotation from the torso frame to a level frame with the same heading.

    The accelerometer of a robot at rest reads gravity's reaction, the world's up direction
    in the torso frame. When it is missing or far from 1 g (the robot is being shaken), the
    torso is taken as upright. So is a tilt below ``min_tilt_rad``: a standing robot's
    accelerometer reads its balance sway as up to a few degrees of tilt.
    """
    tilt = _tilt_rotation(accelerometer_mps2, min_tilt_rad)
    return np.eye(3) if tilt is None else tilt


def _tilt_rotation(accelerometer_mps2: tuple[float, float, float] | None, min_tilt_rad: float) -> np.ndarray | None:
    """:func:`level_rotation`, or None where it is the identity."""
    if accelerometer_mps2 is None:
        return None
    up = np.asarray(accelerometer_mps2, float)
    norm = float(np.linalg.norm(up))
    if not math.isfinite(norm) or abs(norm - GRAVITY_MPS2) > MAX_TILT_ACCEL_DEVIATION_MPS2:
        return None
    up /= norm
    if math.acos(max(-1.0, min(1.0, up[2]))) < min_tilt_rad:
        return None
    # Smallest rotation taking ``up`` to +z (Rodrigues); it keeps the heading of the torso x axis.
    axis = np.cross(up, [0.0, 0.0, 1.0])
    s, c = float(np.linalg.norm(axis)), float(up[2])
    if s < 1e-12:
        return None if c > 0 else np.diag([1.0, -1.0, -1.0])
    k = axis / s
    kx = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + s * kx + (1.0 - c) * (kx @ kx)


CAMERA_MODELS: dict[str, CameraModel] = {"exact": ExactCameraModel(), "thesis": ThesisCameraModel()}
DEFAULT_CAMERA_MODEL = "exact"


def camera_model(name: str) -> CameraModel:
    """The camera model called ``name`` (``exact`` or ``thesis``)."""
    try:
        return CAMERA_MODELS[name]
    except KeyError:
        raise VisionConfigError(f"camera model {name!r} is not one of {sorted(CAMERA_MODELS)}") from None
