"""The robot camera as a pinhole model, and the head kinematics that place it.

Pure numpy: no pybullet. These are public facts of the robot (like the field geometry),
so agents may use them to turn pixels into directions and ground distances.

Frames:
- torso frame: origin on the ground below the torso centre when standing upright,
  x forward, y left, z up (so head yaw is CCW positive, head pitch positive looks down);
- camera frame: OpenCV convention, x right, y down, z along the optical axis;
- pixels: ``(u, v)`` with ``u`` the column in [0, 159] (left to right) and ``v`` the row in
  [0, 119] (top to bottom); pixel ``(u, v)`` covers the square [u, u+1) x [v, v+1), so its
  centre is at continuous image coordinates ``(u + 0.5, v + 0.5)``.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

import numpy as np


class CameraPosition(enum.Enum):
    """Which of the two camera positions is in use; they differ by 40 degrees in pitch."""

    TOP = "top"
    BOTTOM = "bottom"


@dataclass(frozen=True)
class CameraIntrinsics:
    """Square-pixel pinhole camera: 160x120, horizontal field of view 46 degrees."""

    width_px: int = 160
    height_px: int = 120
    horizontal_fov_rad: float = math.radians(46.0)

    @property
    def focal_px(self) -> float:
        return (self.width_px / 2.0) / math.tan(self.horizontal_fov_rad / 2.0)

    @property
    def vertical_fov_rad(self) -> float:
        """About 35.3 degrees for square pixels (the thesis rounds it to 34)."""
        return 2.0 * math.atan((self.height_px / 2.0) / self.focal_px)

    @property
    def principal_point(self) -> tuple[float, float]:
        """Continuous image coordinates of the optical axis (the image centre)."""
        return self.width_px / 2.0, self.height_px / 2.0

    def project(self, points_camera: np.ndarray) -> np.ndarray:
        """Project camera-frame points (N, 3) to pixel indices (N, 2) as floats.

        A returned ``(u, v)`` of ``(10.0, 20.0)`` is the centre of pixel column 10, row 20.
        Points at or behind the camera give NaN.
        """
        pts = np.asarray(points_camera, dtype=float).reshape(-1, 3)
        z = pts[:, 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            u = self.focal_px * pts[:, 0] / z + self.principal_point[0] - 0.5
            v = self.focal_px * pts[:, 1] / z + self.principal_point[1] - 0.5
        out = np.stack([u, v], axis=1)
        out[z <= 1e-9] = np.nan
        return out

    def pixel_ray(self, u: float | np.ndarray, v: float | np.ndarray) -> np.ndarray:
        """Unit direction(s) in the camera frame through the centre of pixel(s) ``(u, v)``."""
        cx, cy = self.principal_point
        u_arr, v_arr = np.broadcast_arrays(np.asarray(u, float), np.asarray(v, float))
        rays = np.stack(
            [(u_arr + 0.5 - cx) / self.focal_px, (v_arr + 0.5 - cy) / self.focal_px, np.ones_like(u_arr)],
            axis=-1,
        )
        return rays / np.linalg.norm(rays, axis=-1, keepdims=True)

    def rotated_pixel_rays(
        self, u: float | np.ndarray, v: float | np.ndarray, rotation: np.ndarray
    ) -> tuple[float | np.ndarray, float | np.ndarray, float | np.ndarray]:
        """The unit rays of :meth:`pixel_ray` turned by ``rotation`` (3x3, camera -> another frame), as (x, y, z).

        For many pixels at once without stacking them: each component is a float for float
        ``u``, ``v`` and an array of their broadcast shape for arrays.
        """
        (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = np.asarray(rotation, float).tolist()
        cx, cy = self.principal_point
        x = (u + 0.5 - cx) / self.focal_px
        y = (v + 0.5 - cy) / self.focal_px
        norm = (x * x + y * y + 1.0) ** 0.5
        return (r00 * x + r01 * y + r02) / norm, (r10 * x + r11 * y + r12) / norm, (r20 * x + r21 * y + r22) / norm

    def in_image(self, pixels: np.ndarray) -> np.ndarray:
        """Boolean mask of pixel coordinates (N, 2) that fall inside the image."""
        px = np.asarray(pixels, float).reshape(-1, 2)
        return (
            np.isfinite(px).all(axis=1)
            & (px[:, 0] >= -0.5)
            & (px[:, 0] < self.width_px - 0.5)
            & (px[:, 1] >= -0.5)
            & (px[:, 1] < self.height_px - 0.5)
        )


@dataclass(frozen=True)
class CameraMount:
    """Where one camera position sits on the head, relative to the head pitch joint."""

    forward_m: float
    up_m: float
    pitch_rad: float  # extra downward pitch of the optical axis


@dataclass(frozen=True)
class HeadKinematics:
    """Head joint limits and camera mounts of the simulated Nao (torso frame, standing).

    The head yaw and pitch joints share one point, ``neck_height_m`` above the ground when
    the robot stands upright. With the head level the top camera is 0.51 m above the ground.
    """

    neck_height_m: float = 0.442
    neck_forward_m: float = 0.0
    yaw_limits_rad: tuple[float, float] = (math.radians(-119.5), math.radians(119.5))
    pitch_limits_rad: tuple[float, float] = (math.radians(-38.5), math.radians(29.5))
    top_camera: CameraMount = CameraMount(forward_m=0.054, up_m=0.068, pitch_rad=0.0)
    bottom_camera: CameraMount = CameraMount(forward_m=0.049, up_m=0.023, pitch_rad=math.radians(40.0))

    def mount(self, camera: CameraPosition) -> CameraMount:
        return self.top_camera if camera is CameraPosition.TOP else self.bottom_camera

    def camera_in_torso(
        self, head_yaw_rad: float, head_pitch_rad: float, camera: CameraPosition
    ) -> tuple[np.ndarray, np.ndarray]:
        """Camera pose in the torso frame as (rotation 3x3 camera->torso, position (3,) m).

        The rotation maps camera-frame vectors (x right, y down, z forward) to torso-frame
        vectors (x forward, y left, z up).
        """
        mount = self.mount(camera)
        rot_head = rotation_z(head_yaw_rad) @ rotation_y(head_pitch_rad)
        neck = np.array([self.neck_forward_m, 0.0, self.neck_height_m])
        position = neck + rot_head @ np.array([mount.forward_m, 0.0, mount.up_m])
        rotation = rot_head @ rotation_y(mount.pitch_rad) @ CAMERA_TO_BODY_AXES
        return rotation, position


CAMERA_TO_BODY_AXES = np.array([[0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])
"""Columns: camera x (right) = body -y, camera y (down) = body -z, camera z (forward) = body x."""


def rotation_z(angle_rad: float) -> np.ndarray:
    c, s = math.cos(angle_rad), math.sin(angle_rad)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rotation_y(angle_rad: float) -> np.ndarray:
    """Rotation about +y; with y to the left, a positive angle tips +x (forward) down."""
    c, s = math.cos(angle_rad), math.sin(angle_rad)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def rotation_x(angle_rad: float) -> np.ndarray:
    c, s = math.cos(angle_rad), math.sin(angle_rad)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def world_to_camera(
    points_world: np.ndarray, camera_rotation: np.ndarray, camera_position: np.ndarray
) -> np.ndarray:
    """Express world points (N, 3) in a camera frame given its world pose."""
    pts = np.asarray(points_world, float).reshape(-1, 3)
    return (pts - camera_position) @ camera_rotation


NAO_CAMERA = CameraIntrinsics()
NAO_HEAD = HeadKinematics()
