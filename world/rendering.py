"""Rendering with pybullet's TinyRenderer (CPU): robot cameras and overview images."""

from __future__ import annotations

import functools
import math
from typing import TYPE_CHECKING

import cv2
import numpy as np
import pybullet as pb

from world.camera_model import CAMERA_TO_BODY_AXES, NAO_CAMERA, NAO_HEAD, CameraPosition, rotation_y
from world.config import RenderConfig
from world.ground import GroundRenderer
from world.robot_model import Joint

if TYPE_CHECKING:
    from world.raster.renderer import CompiledRenderer
    from world.static_scene import StaticScene
    from world.teams import TeamColor


def camera_pose(client: int, body: int, camera: CameraPosition) -> tuple[np.ndarray, np.ndarray]:
    """World pose of a robot's camera: (rotation camera->world 3x3, position (3,) m)."""
    state = pb.getLinkState(body, int(Joint.HEAD_PITCH), computeForwardKinematics=True, physicsClientId=client)
    head_position = np.asarray(state[4])
    head_rotation = np.asarray(pb.getMatrixFromQuaternion(state[5])).reshape(3, 3)
    mount = NAO_HEAD.mount(camera)
    position = head_position + head_rotation @ np.array([mount.forward_m, 0.0, mount.up_m])
    rotation = head_rotation @ rotation_y(mount.pitch_rad) @ CAMERA_TO_BODY_AXES
    return rotation, position


def view_matrix(rotation: np.ndarray, position: np.ndarray) -> tuple[float, ...]:
    forward, down = rotation[:, 2], rotation[:, 1]
    return pb.computeViewMatrix(
        cameraEyePosition=position.tolist(),
        cameraTargetPosition=(position + forward).tolist(),
        cameraUpVector=(-down).tolist(),
    )


def look_at(eye, target, up) -> tuple[np.ndarray, np.ndarray]:
    """Camera pose (rotation camera->world, position) looking from ``eye`` at ``target``."""
    position = np.asarray(eye, float)
    forward = np.asarray(target, float) - position
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, np.asarray(up, float))
    right /= np.linalg.norm(right)
    down = np.cross(forward, right)
    return np.stack([right, down, forward], axis=1), position


@functools.lru_cache(maxsize=16)
def projection_matrix(vertical_fov_rad: float, aspect: float, near_m: float, far_m: float) -> tuple[float, ...]:
    """pybullet's projection matrix (16 floats, column-major) of a camera of this field of view and aspect."""
    fov_deg = math.degrees(vertical_fov_rad)
    return pb.computeProjectionMatrixFOV(fov=fov_deg, aspect=aspect, nearVal=near_m, farVal=far_m)


def tiny_renderer_buffers(
    client: int,
    rotation: np.ndarray,
    position: np.ndarray,
    width_px: int,
    height_px: int,
    vertical_fov_rad: float,
    render_config: RenderConfig,
    segmentation: bool = False,
) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """TinyRenderer's buffers for a camera pose, square pixels: RGBA (h, w, 4) uint8, depth (h, w)
    float32 and, with ``segmentation``, pybullet's object-and-link mask (h, w) (else None)."""
    _, _, rgba, depth, mask = pb.getCameraImage(
        width_px,
        height_px,
        viewMatrix=view_matrix(rotation, position),
        projectionMatrix=projection_matrix(vertical_fov_rad, width_px / height_px, render_config.near_m, render_config.far_m),
        lightDirection=render_config.light_direction,
        lightAmbientCoeff=render_config.ambient,
        lightDiffuseCoeff=render_config.diffuse,
        lightSpecularCoeff=render_config.specular,
        shadow=0,
        renderer=pb.ER_TINY_RENDERER,
        flags=pb.ER_SEGMENTATION_MASK_OBJECT_AND_LINKINDEX if segmentation else pb.ER_NO_SEGMENTATION_MASK,
        physicsClientId=client,
    )
    rgba = np.reshape(rgba, (height_px, width_px, 4))
    labels = np.reshape(mask, (height_px, width_px)) if segmentation else None
    return rgba, np.reshape(depth, (height_px, width_px)), labels


def camera_buffers(
    client: int,
    rotation: np.ndarray,
    position: np.ndarray,
    width_px: int,
    height_px: int,
    vertical_fov_rad: float,
    render_config: RenderConfig,
    segmentation: bool = False,
) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """As :func:`tiny_renderer_buffers`, with the image as RGB (h, w, 3) uint8."""
    rgba, depth, labels = tiny_renderer_buffers(
        client, rotation, position, width_px, height_px, vertical_fov_rad, render_config, segmentation
    )
    return cv2.cvtColor(np.ascontiguousarray(rgba, np.uint8), cv2.COLOR_RGBA2RGB), depth, labels


def focal_length_px(height_px: int, vertical_fov_rad: float) -> float:
    return (height_px / 2.0) / math.tan(vertical_fov_rad / 2.0)


def render(
    client: int,
    rotation: np.ndarray,
    position: np.ndarray,
    width_px: int,
    height_px: int,
    vertical_fov_rad: float,
    render_config: RenderConfig,
    ground: GroundRenderer | None = None,
) -> np.ndarray:
    """Render one RGB image (height, width, 3) uint8 from a camera pose, square pixels.

    With ``ground``, TinyRenderer draws the bodies and the static scene is composited in
    analytically (the scene's visuals must then be hidden, see :mod:`world.ground`).
    """
    if ground is None:
        return camera_buffers(client, rotation, position, width_px, height_px, vertical_fov_rad, render_config)[0]
    rgba, depth, _ = tiny_renderer_buffers(
        client, rotation, position, width_px, height_px, vertical_fov_rad, render_config
    )
    return ground.composite(rgba, depth, rotation, position, focal_length_px(height_px, vertical_fov_rad))


def render_robot_camera(
    client: int, body: int, camera: CameraPosition, render_config: RenderConfig, ground: GroundRenderer | None
) -> np.ndarray:
    rotation, position = camera_pose(client, body, camera)
    cam = NAO_CAMERA
    return render(client, rotation, position, cam.width_px, cam.height_px, cam.vertical_fov_rad, render_config, ground)


OVERVIEW_EYE_M = (0.0, -3.7, 4.4)
OVERVIEW_TARGET_M = (0.0, -0.2, 0.0)


def overview_pose(eye, target) -> tuple[np.ndarray, np.ndarray]:
    """The broadcast camera's pose (rotation camera->world, position m) looking from ``eye`` at ``target``;
    straight down with north (+y) up when ``eye`` is above ``target``."""
    dx, dy = target[0] - eye[0], target[1] - eye[1]
    up = (0.0, 1.0, 0.0) if abs(dx) < 1e-9 and abs(dy) < 1e-9 else (0.0, 0.0, 1.0)
    return look_at(eye, target, up)


def compiled_overview(
    renderer: CompiledRenderer,
    teams: dict[int, TeamColor],
    eye: tuple[float, float, float] = OVERVIEW_EYE_M,
    target: tuple[float, float, float] = OVERVIEW_TARGET_M,
    width_px: int = 640,
    height_px: int = 480,
    fov_deg: float = 62.0,
    poses_key: object = None,
) -> np.ndarray:
    """As :func:`render_overview`, drawn by the compiled renderer (``teams``: each robot body's team;
    ``poses_key``: see :meth:`world.raster.renderer.CompiledRenderer.frames`)."""
    images, _ = renderer.frames([overview_pose(eye, target)], width_px, height_px, math.radians(fov_deg), teams,
                                fixed_camera=True, poses_key=poses_key)
    return images[0]


def render_overview(
    client: int,
    render_config: RenderConfig,
    ground: GroundRenderer | None,
    eye: tuple[float, float, float] = OVERVIEW_EYE_M,
    target: tuple[float, float, float] = OVERVIEW_TARGET_M,
    width_px: int = 640,
    height_px: int = 480,
    fov_deg: float = 62.0,
    static: StaticScene | None = None,
) -> np.ndarray:
    """A broadcast-style image of the whole field; straight down with ``eye`` above ``target``.

    With ``static`` (the world's :class:`world.static_scene.StaticScene`, which needs ``ground``),
    the hall and the goals are drawn once per camera pose, and TinyRenderer draws only the
    robots and the ball: the same image, faster."""
    rotation, position = overview_pose(eye, target)
    if static is not None and ground is not None:
        return static.render(rotation, position, width_px, height_px, math.radians(fov_deg))
    return render(client, rotation, position, width_px, height_px, math.radians(fov_deg), render_config, ground)
