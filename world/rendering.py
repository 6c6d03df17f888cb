"""Rendering with pybullet's TinyRenderer (CPU): robot cameras and overview images."""

from __future__ import annotations

import math

import numpy as np
import pybullet as pb

from world.camera_model import CAMERA_TO_BODY_AXES, NAO_CAMERA, NAO_HEAD, CameraIntrinsics, CameraPosition, rotation_y
from world.config import RenderConfig
from world.robot_model import Joint


def camera_pose(client: int, body: int, camera: CameraPosition) -> tuple[np.ndarray, np.ndarray]:
    """World pose of a robot's camera: (rotation camera->world 3x3, position (3,) m)."""
    state = pb.getLinkState(body, int(Joint.HEAD_PITCH), computeForwardKinematics=True, physicsClientId=client)
    head_position = np.asarray(state[4])
    head_rotation = np.asarray(pb.getMatrixFromQuaternion(state[5])).reshape(3, 3)
    mount = NAO_HEAD.mount(camera)
    position = head_position + head_rotation @ np.array([mount.forward_m, 0.0, mount.up_m])
    rotation = head_rotation @ rotation_y(mount.pitch_rad) @ CAMERA_TO_BODY_AXES
    return rotation, position


def projection_matrix(intrinsics: CameraIntrinsics, render: RenderConfig) -> tuple[float, ...]:
    return pb.computeProjectionMatrixFOV(
        fov=math.degrees(intrinsics.vertical_fov_rad),
        aspect=intrinsics.width_px / intrinsics.height_px,
        nearVal=render.near_m,
        farVal=render.far_m,
    )


def view_matrix(rotation: np.ndarray, position: np.ndarray) -> tuple[float, ...]:
    forward, down = rotation[:, 2], rotation[:, 1]
    return pb.computeViewMatrix(
        cameraEyePosition=position.tolist(),
        cameraTargetPosition=(position + forward).tolist(),
        cameraUpVector=(-down).tolist(),
    )


def render(
    client: int,
    view: tuple[float, ...],
    projection: tuple[float, ...],
    width_px: int,
    height_px: int,
    render_config: RenderConfig,
) -> np.ndarray:
    """Render one RGB image (height, width, 3) uint8 with TinyRenderer."""
    _, _, rgba, _, _ = pb.getCameraImage(
        width_px,
        height_px,
        viewMatrix=view,
        projectionMatrix=projection,
        lightDirection=render_config.light_direction,
        lightAmbientCoeff=render_config.ambient,
        lightDiffuseCoeff=render_config.diffuse,
        lightSpecularCoeff=render_config.specular,
        shadow=0,
        renderer=pb.ER_TINY_RENDERER,
        flags=pb.ER_NO_SEGMENTATION_MASK,
        physicsClientId=client,
    )
    return np.ascontiguousarray(np.reshape(rgba, (height_px, width_px, 4))[:, :, :3], dtype=np.uint8)


def render_robot_camera(
    client: int, body: int, camera: CameraPosition, render_config: RenderConfig, projection: tuple[float, ...]
) -> np.ndarray:
    rotation, position = camera_pose(client, body, camera)
    return render(client, view_matrix(rotation, position), projection, NAO_CAMERA.width_px, NAO_CAMERA.height_px, render_config)


def render_overview(
    client: int,
    render_config: RenderConfig,
    eye: tuple[float, float, float] = (0.0, -3.7, 4.4),
    target: tuple[float, float, float] = (0.0, -0.2, 0.0),
    width_px: int = 640,
    height_px: int = 480,
    fov_deg: float = 62.0,
) -> np.ndarray:
    """A broadcast-style image of the whole field; straight down with ``eye`` above ``target``."""
    dx, dy = target[0] - eye[0], target[1] - eye[1]
    up = (0.0, 1.0, 0.0) if abs(dx) < 1e-9 and abs(dy) < 1e-9 else (0.0, 0.0, 1.0)
    view = pb.computeViewMatrix(eye, target, up)
    projection = pb.computeProjectionMatrixFOV(fov_deg, width_px / height_px, 0.1, 50.0)
    return render(client, view, projection, width_px, height_px, render_config)
