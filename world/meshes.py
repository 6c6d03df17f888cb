"""Triangle meshes of the visual shapes, shared by pybullet's TinyRenderer and :mod:`world.raster`.

Both renderers must draw the same triangles. TinyRenderer turns a box into a fixed 24-vertex
mesh (:func:`box_mesh` reproduces it, faces, corner order and winding included), but it turns
a sphere or a cylinder into a convex hull of support points whose tessellation is an
implementation detail. The ball and the goals are therefore given to pybullet as explicit
meshes (``GEOM_MESH`` with vertices, normals and indices), made here, so the compiled renderer
draws exactly what TinyRenderer draws.

A :class:`Mesh` holds float32 vertices (n, 3) and unit normals (n, 3) in the shape's frame
(m), and int32 triangles (t, 3) counter-clockwise seen from outside (the side that is drawn).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from world.field import FieldGeometry, GoalColor

ICOSPHERE_SUBDIVISIONS = 1  # 42 vertices, 80 triangles: the ball as TinyRenderer's hull of it had
CYLINDER_SIDES = 16
GOAL_FRAME_HALF_M = 0.02  # the back frame's square bars, half their side

# A box's faces as TinyRenderer builds them: outward normal and four corners (signs of the
# half extents), each face two triangles (0, 1, 2) and (0, 2, 3) of its corners, or (2, 1, 0)
# and (3, 2, 0) where ``reversed``.
_BOX_FACES: tuple[tuple[tuple[int, int, int], tuple[tuple[int, int, int], ...], bool], ...] = (
    ((0, 0, 1), ((-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1)), False),
    ((0, 0, -1), ((-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1)), True),
    ((-1, 0, 0), ((-1, -1, -1), (-1, 1, -1), (-1, 1, 1), (-1, -1, 1)), True),
    ((1, 0, 0), ((1, -1, -1), (1, 1, -1), (1, 1, 1), (1, -1, 1)), False),
    ((0, -1, 0), ((-1, -1, -1), (-1, -1, 1), (1, -1, 1), (1, -1, -1)), True),
    ((0, 1, 0), ((-1, 1, -1), (-1, 1, 1), (1, 1, 1), (1, 1, -1)), False),
)


@dataclass(frozen=True)
class Mesh:
    """Vertices (n, 3) float32 m and unit normals (n, 3) float32, shape frame; triangles (t, 3) int32."""

    vertices: np.ndarray
    normals: np.ndarray
    triangles: np.ndarray

    def __post_init__(self) -> None:
        for name in ("vertices", "normals", "triangles"):
            getattr(self, name).flags.writeable = False

    @staticmethod
    def concatenate(meshes: list[Mesh]) -> Mesh:
        """One mesh of several, triangles in the given order."""
        offsets = np.cumsum([0] + [len(m.vertices) for m in meshes])[:-1]
        return Mesh(
            np.concatenate([m.vertices for m in meshes]).astype(np.float32),
            np.concatenate([m.normals for m in meshes]).astype(np.float32),
            np.concatenate([m.triangles + o for m, o in zip(meshes, offsets)]).astype(np.int32),
        )

    def moved(self, rotation: np.ndarray, translation: np.ndarray) -> Mesh:
        """This mesh with its vertices at ``rotation @ v + translation`` and normals turned (float64 maths)."""
        vertices = self.vertices.astype(float) @ rotation.T + translation
        normals = self.normals.astype(float) @ rotation.T
        return Mesh(vertices.astype(np.float32), normals.astype(np.float32), self.triangles.copy())

    def pybullet_arguments(self) -> dict:
        """Keyword arguments of ``pybullet.createVisualShape(GEOM_MESH, ...)`` that draw this mesh."""
        return dict(
            vertices=self.vertices.astype(float).tolist(),
            normals=self.normals.astype(float).tolist(),
            indices=self.triangles.ravel().tolist(),
            uvs=[(0.0, 0.0)] * len(self.vertices),
        )


def box_mesh(half_extents: tuple[float, float, float]) -> Mesh:
    """TinyRenderer's box: 24 vertices (four per face, the face's normal), 12 triangles."""
    vertices, normals, triangles = [], [], []
    for normal, corners, reverse in _BOX_FACES:
        base = len(vertices)
        vertices += [[h * s for h, s in zip(half_extents, corner)] for corner in corners]
        normals += [normal] * 4
        order = ((2, 1, 0), (3, 2, 0)) if reverse else ((0, 1, 2), (0, 2, 3))
        triangles += [[base + i for i in tri] for tri in order]
    return Mesh(np.asarray(vertices, np.float32), np.asarray(normals, np.float32), np.asarray(triangles, np.int32))


def icosphere_mesh(radius_m: float, subdivisions: int = ICOSPHERE_SUBDIVISIONS) -> Mesh:
    """A sphere: an icosahedron with each triangle cut in four ``subdivisions`` times, vertices pushed
    out to ``radius_m``; smooth normals (the vertex directions)."""
    t = (1.0 + math.sqrt(5.0)) / 2.0
    points = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
              (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    directions = [np.asarray(p, float) / np.linalg.norm(p) for p in points]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
             (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5),
             (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(subdivisions):
        midpoints: dict[tuple[int, int], int] = {}

        def midpoint(a: int, b: int) -> int:
            key = (min(a, b), max(a, b))
            if key not in midpoints:
                middle = directions[a] + directions[b]
                directions.append(middle / np.linalg.norm(middle))
                midpoints[key] = len(directions) - 1
            return midpoints[key]

        refined = []
        for a, b, c in faces:
            ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
            refined += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = refined
    unit = np.asarray(directions)
    return Mesh((unit * radius_m).astype(np.float32), unit.astype(np.float32), np.asarray(faces, np.int32))


def _frame_along(p0: np.ndarray, p1: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A right-handed frame (axis, u, v) of unit vectors with ``axis`` from ``p0`` to ``p1``."""
    axis = (p1 - p0) / np.linalg.norm(p1 - p0)
    helper = np.array([0.0, 0.0, 1.0]) if abs(axis[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    u = np.cross(helper, axis)
    u /= np.linalg.norm(u)
    return axis, u, np.cross(axis, u)


def cylinder_mesh(start: tuple[float, float, float], end: tuple[float, float, float], radius_m: float,
                  sides: int = CYLINDER_SIDES) -> Mesh:
    """A closed cylinder from ``start`` to ``end`` (m): ``sides`` quads with smooth radial normals, and two
    flat caps."""
    p0, p1 = np.asarray(start, float), np.asarray(end, float)
    axis, u, v = _frame_along(p0, p1)
    angles = 2.0 * math.pi * np.arange(sides) / sides
    radial = np.cos(angles)[:, None] * u + np.sin(angles)[:, None] * v  # counter-clockwise about the axis
    vertices = [p0 + radius_m * radial, p1 + radial * radius_m]
    normals = [radial, radial]
    triangles = []
    for i in range(sides):
        j = (i + 1) % sides
        triangles += [(i, j, sides + j), (i, sides + j, sides + i)]
    for cap, (centre, normal) in enumerate(((p0, -axis), (p1, axis))):
        base = 2 * sides + cap * (sides + 1)
        vertices += [centre[None, :], centre + radius_m * radial]
        normals += [np.tile(normal, (sides + 1, 1))]
        for i in range(sides):
            j = (i + 1) % sides
            triangles.append((base, base + 1 + j, base + 1 + i) if cap == 0 else (base, base + 1 + i, base + 1 + j))
    return Mesh(np.concatenate(vertices).astype(np.float32), np.concatenate(normals).astype(np.float32),
                np.asarray(triangles, np.int32))


def bar_mesh(start: tuple[float, float, float], end: tuple[float, float, float], half_side_m: float) -> Mesh:
    """A square bar from ``start`` to ``end`` (m), ``2 * half_side_m`` thick, as a box along the segment."""
    p0, p1 = np.asarray(start, float), np.asarray(end, float)
    rotation = np.stack(_frame_along(p0, p1), axis=1)  # box frame -> world: x along the bar
    half_length = float(np.linalg.norm(p1 - p0)) / 2.0
    return box_mesh((half_length, half_side_m, half_side_m)).moved(rotation, (p0 + p1) / 2.0)


def goal_pieces(field: FieldGeometry, color: GoalColor) -> list[tuple[tuple, tuple, float, bool]]:
    """The goal's pieces as (start, end, radius m, round): posts and crossbar are round; the back frame
    (top, bottom and side bars) is of square bars."""
    sign = color.sign
    x_line = field.goal_line_x(color)
    x_back = x_line + sign * field.goal_depth
    post_r, height, post_y = field.goal_post_radius, field.goal_height, field.goal_post_y
    bar_z = height - post_r
    frame = GOAL_FRAME_HALF_M
    pieces = []
    for y in (-post_y, post_y):
        pieces.append(((x_line, y, 0.0), (x_line, y, height), post_r, True))
        pieces.append(((x_back, y, 0.0), (x_back, y, bar_z), frame, False))
        pieces.append(((x_line, y, bar_z), (x_back, y, bar_z), frame, False))
        pieces.append(((x_line, y, frame), (x_back, y, frame), frame, False))
    pieces.append(((x_line, -post_y, bar_z), (x_line, post_y, bar_z), post_r, True))
    pieces.append(((x_back, -post_y, bar_z), (x_back, post_y, bar_z), frame, False))
    pieces.append(((x_back, -post_y, frame), (x_back, post_y, frame), frame, False))
    return pieces


def goal_mesh(field: FieldGeometry, color: GoalColor) -> Mesh:
    """A goal in the field frame (m): round posts and crossbar, the square-barred back frame."""
    return Mesh.concatenate([
        cylinder_mesh(start, end, radius) if round_piece else bar_mesh(start, end, radius)
        for start, end, radius, round_piece in goal_pieces(field, color)
    ])
