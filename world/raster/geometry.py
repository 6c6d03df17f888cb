"""The bodies a world's cameras see, as triangle meshes in their bodies' frames, and where they are now.

Shapes are listed in the order TinyRenderer draws them (the order the world creates them:
the ball, each robot's torso then its links, the goals), each with its mesh in the frame of
its body or link's centre of mass (the frame pybullet hands the renderer), its material
colour (TinyRenderer's ``int(255 * rgba)``) and its label in pybullet's segmentation mask
(``body + ((link + 1) << 24)``). An instance is one body or link; its model matrix is the
float32 cast of its centre-of-mass pose, as TinyRenderer receives it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pybullet as pb
from numba import njit

from world.field import FieldGeometry, GoalColor
from world.meshes import Mesh, box_mesh, goal_mesh, icosphere_mesh
from world.robot_model import BODY_RGBA, TORSO_SIZE_M, robot_link_shapes
from world.scene import GOAL_RGBA
from world.shading import material_rgb
from world.teams import TeamColor

BASE = -1  # pybullet's link index of a body's base


@dataclass(frozen=True)
class Instance:
    """A body (``link`` -1) or one of its links, whose pose moves its shapes."""

    body: int
    link: int


@dataclass(frozen=True)
class RasterGeometry:
    """All shapes' triangles and the tables that say whose they are (see the module docstring).

    ``vertices``/``normals`` (v, 3) float32 and ``triangles`` (t, 3) int64 are every mesh's,
    concatenated; shape ``s`` is triangles ``first[s]:first[s] + count[s]`` of instance
    ``instance[s]``, coloured ``rgb[s]`` (uint8), labelled ``label[s]``, and lies within
    ``radius[s]`` m of ``centre[s]`` (instance frame). ``team_shapes`` maps a robot's body to its
    waistband shape, whose colour is the robot's team's. ``static_models`` (i, 4, 4) float32 holds the
    model matrices of the instances that never move; the others are ``moving``, as (body, links)
    whose poses are read base first then links, filling the instances ``moving_instances`` in order.
    """

    vertices: np.ndarray
    normals: np.ndarray
    triangles: np.ndarray
    instance: np.ndarray
    first: np.ndarray
    count: np.ndarray
    rgb: np.ndarray
    label: np.ndarray
    centre: np.ndarray
    radius: np.ndarray
    instances: tuple[Instance, ...]
    static_models: np.ndarray
    moving: tuple[tuple[int, tuple[int, ...]], ...]
    moving_instances: np.ndarray
    team_shapes: dict[int, int]


class _Builder:
    def __init__(self) -> None:
        self.meshes: list[Mesh] = []
        self.rows: list[tuple[int, tuple[int, int, int], int]] = []
        self.instances: list[Instance] = []
        self.team_shapes: dict[int, int] = {}

    def add(self, body: int, link: int, mesh: Mesh, rgba: tuple[float, ...]) -> int:
        instance = Instance(body, link)
        if instance not in self.instances:
            self.instances.append(instance)
        rgb = tuple(int(c) for c in material_rgb(rgba))
        self.meshes.append(mesh)
        self.rows.append((self.instances.index(instance), rgb, body + ((link + 1) << 24)))
        return len(self.rows) - 1

    def build(self, static_bodies: set[int]) -> RasterGeometry:
        counts = np.array([len(m.triangles) for m in self.meshes], np.int64)
        merged = Mesh.concatenate(self.meshes)
        centres, radii = [], []
        for mesh in self.meshes:
            low, high = mesh.vertices.min(axis=0).astype(float), mesh.vertices.max(axis=0).astype(float)
            centre = (low + high) / 2.0
            centres.append(centre)
            radii.append(float(np.linalg.norm(mesh.vertices.astype(float) - centre, axis=1).max()))
        static_models = np.tile(np.eye(4, dtype=np.float32), (len(self.instances), 1, 1))
        moving, moving_instances = [], []
        for body in dict.fromkeys(instance.body for instance in self.instances if instance.body not in static_bodies):
            links = [(i, instance.link) for i, instance in enumerate(self.instances)
                     if instance.body == body and instance.link != BASE]
            base = [i for i, instance in enumerate(self.instances) if instance == Instance(body, BASE)]
            if len(base) != 1:
                raise ValueError(f"body {body} is drawn without its base: the renderer reads links after the base")
            moving.append((body, tuple(link for _, link in links)))
            moving_instances += base + [i for i, _ in links]
        return RasterGeometry(
            vertices=merged.vertices, normals=merged.normals, triangles=merged.triangles.astype(np.int64),
            instance=np.array([row[0] for row in self.rows], np.int64),
            first=np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.int64), count=counts,
            rgb=np.array([row[1] for row in self.rows], np.uint8).reshape(-1, 3),
            label=np.array([row[2] for row in self.rows], np.int32),
            centre=np.array(centres, np.float64).reshape(-1, 3), radius=np.array(radii, np.float64),
            instances=tuple(self.instances), static_models=static_models, moving=tuple(moving),
            moving_instances=np.array(moving_instances, np.int64), team_shapes=dict(self.team_shapes),
        )


def raster_geometry(field: FieldGeometry, ball: int, robots: dict[int, TeamColor], goals: dict[GoalColor, int],
                    ball_rgba: tuple[float, ...]) -> RasterGeometry:
    """The shapes of a world built by :class:`world.world.World`: ``ball`` and ``goals`` are body ids,
    ``robots`` maps each robot's body id to its team, in creation order."""
    builder = _Builder()
    builder.add(ball, BASE, icosphere_mesh(field.ball_radius), ball_rgba)
    for body, team in robots.items():
        builder.add(body, BASE, box_mesh(tuple(s / 2.0 for s in TORSO_SIZE_M)), BODY_RGBA)
        for link, half_extents, rgba, waistband in robot_link_shapes():
            shape = builder.add(body, link, box_mesh(half_extents), team.rgba if waistband else rgba)
            if waistband:
                builder.team_shapes[body] = shape
    for color, body in goals.items():
        builder.add(body, BASE, goal_mesh(field, color), GOAL_RGBA[color])
    return builder.build(set(goals.values()))  # the goals stand at the origin, unturned


@njit(cache=True)
def _model_matrices(poses: np.ndarray, static_models: np.ndarray, moving_instances: np.ndarray) -> np.ndarray:
    """``static_models`` with each moving instance's matrix from its pose (x, y, z, qx, qy, qz, qw), the
    rotation as Bullet's ``setRotation`` makes it, computed in float64 and then cast."""
    models = static_models.copy()
    for k in range(poses.shape[0]):
        x, y, z, w = poses[k, 3], poses[k, 4], poses[k, 5], poses[k, 6]
        s = 2.0 / (x * x + y * y + z * z + w * w)
        xs, ys, zs = x * s, y * s, z * s
        wx, wy, wz = w * xs, w * ys, w * zs
        xx, xy, xz = x * xs, x * ys, x * zs
        yy, yz, zz = y * ys, y * zs, z * zs
        rotation = ((1.0 - (yy + zz), xy - wz, xz + wy), (xy + wz, 1.0 - (xx + zz), yz - wx),
                    (xz - wy, yz + wx, 1.0 - (xx + yy)))
        m = models[moving_instances[k]]
        for i in range(3):
            for j in range(3):
                m[i, j] = np.float32(rotation[i][j])
            m[i, 3] = np.float32(poses[k, i])
            m[3, i] = np.float32(0.0)
        m[3, 3] = np.float32(1.0)
    return models


def model_matrices(client: int, geometry: RasterGeometry) -> np.ndarray:
    """Every instance's model matrix now (n, 4, 4) float32: its centre-of-mass pose in the world."""
    poses = []  # (x, y, z, qx, qy, qz, qw) of the moving instances, in the order of geometry.moving
    for body, links in geometry.moving:
        position, orientation = pb.getBasePositionAndOrientation(body, physicsClientId=client)
        poses.append((*position, *orientation))
        if links:
            poses += [(*state[0], *state[1]) for state in pb.getLinkStates(body, links, computeForwardKinematics=True,
                                                                           physicsClientId=client)]
    return _model_matrices(np.array(poses), geometry.static_models, geometry.moving_instances)
