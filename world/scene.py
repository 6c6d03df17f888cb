"""The static scene: carpet with painted lines, goals, the floor, walls and banners around.

Static geometry is merged into few bodies (one per colour), because TinyRenderer's cost
grows with the number of shapes and with the screen area each triangle's box covers.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import pybullet as pb

from world.field import FieldGeometry, GoalColor
from world.textures import carpet_texture_file

GOAL_RGBA = {GoalColor.BLUE: (0.1, 0.25, 0.95, 1.0), GoalColor.YELLOW: (0.95, 0.85, 0.1, 1.0)}
FLOOR_RGBA = (0.45, 0.42, 0.4, 1.0)
WALL_RGBA = (0.28, 0.3, 0.38, 1.0)
BANNER_RGBA = (0.93, 0.93, 0.9, 1.0)

WALL_GAP_M = 1.2  # from the carpet edge to the walls
WALL_HEIGHT_M = 4.0
BANNER_HEIGHT_M = 0.5
BANNER_BOTTOM_M = 0.35
CARPET_TILES = (4, 3)  # smaller triangles cut TinyRenderer's per-triangle bounding-box cost
GOAL_FRAME_RADIUS_M = 0.02


@dataclass(frozen=True)
class SceneBodies:
    ground: int
    carpet: int
    goals: dict[GoalColor, int]
    surroundings: int
    banners: int


def build_scene(client: int, field: FieldGeometry) -> SceneBodies:
    """Create the static bodies of the field in ``client``."""
    ground_shape = pb.createCollisionShape(pb.GEOM_PLANE, physicsClientId=client)
    ground = pb.createMultiBody(0, ground_shape, -1, physicsClientId=client)
    pb.changeDynamics(ground, -1, lateralFriction=0.8, restitution=0.0, physicsClientId=client)
    # Collision only: the carpet and floor are drawn; a visible plane would double the fill.
    pb.changeVisualShape(ground, -1, rgbaColor=(0, 0, 0, 0), physicsClientId=client)
    return SceneBodies(
        ground=ground,
        carpet=_build_carpet(client, field),
        goals={color: _build_goal(client, field, color) for color in GoalColor},
        surroundings=_build_surroundings(client, field),
        banners=_build_banners(client, field),
    )


def _build_carpet(client: int, field: FieldGeometry) -> int:
    hx, hy = field.carpet_half_length, field.carpet_half_width
    nx, ny = CARPET_TILES
    vertices, uvs, indices = [], [], []
    for j in range(ny + 1):
        for i in range(nx + 1):
            u, v = i / nx, j / ny
            vertices.append((-hx + 2 * hx * u, -hy + 2 * hy * v, 0.0))
            uvs.append((u, v))  # v = 1 is the texture's top row, the +y edge
    for j in range(ny):
        for i in range(nx):
            a = j * (nx + 1) + i
            b, c, d = a + 1, a + nx + 1, a + nx + 2
            indices += [a, b, d, a, d, c]
    visual = pb.createVisualShape(
        pb.GEOM_MESH,
        vertices=vertices,
        indices=indices,
        uvs=uvs,
        normals=[(0.0, 0.0, 1.0)] * len(vertices),
        physicsClientId=client,
    )
    carpet = pb.createMultiBody(0, -1, visual, physicsClientId=client)
    texture = pb.loadTexture(str(carpet_texture_file(field)), physicsClientId=client)
    pb.changeVisualShape(carpet, -1, textureUniqueId=texture, rgbaColor=(1, 1, 1, 1), physicsClientId=client)
    return carpet


def _cylinder_between(p0, p1):
    """Frame position, orientation and length of a cylinder from point p0 to p1."""
    dx, dy, dz = (b - a for a, b in zip(p0, p1))
    length = math.sqrt(dx * dx + dy * dy + dz * dz)
    mid = tuple((a + b) / 2.0 for a, b in zip(p0, p1))
    pitch = math.acos(max(-1.0, min(1.0, dz / length)))
    yaw = math.atan2(dy, dx)
    return mid, pb.getQuaternionFromEuler((0.0, pitch, yaw)), length


def _build_goal(client: int, field: FieldGeometry, color: GoalColor) -> int:
    """Posts and crossbar (collide) plus a thin back frame, merged into one body."""
    sign = color.sign
    x_line = field.goal_line_x(color)
    x_back = x_line + sign * field.goal_depth
    post_r, height, post_y = field.goal_post_radius, field.goal_height, field.goal_post_y
    bar_z = height - post_r
    frame_r = GOAL_FRAME_RADIUS_M
    pieces: list[tuple[tuple, tuple, float]] = []  # (start, end, radius)
    for y in (-post_y, post_y):
        pieces.append(((x_line, y, 0.0), (x_line, y, height), post_r))
        pieces.append(((x_back, y, 0.0), (x_back, y, bar_z), frame_r))
        pieces.append(((x_line, y, bar_z), (x_back, y, bar_z), frame_r))
        pieces.append(((x_line, y, frame_r), (x_back, y, frame_r), frame_r))
    pieces.append(((x_line, -post_y, bar_z), (x_line, post_y, bar_z), post_r))
    pieces.append(((x_back, -post_y, bar_z), (x_back, post_y, bar_z), frame_r))
    pieces.append(((x_back, -post_y, frame_r), (x_back, post_y, frame_r), frame_r))
    frames = [_cylinder_between(a, b) for a, b, _ in pieces]
    kwargs = dict(
        shapeTypes=[pb.GEOM_CYLINDER] * len(pieces),
        radii=[r for _, _, r in pieces],
        lengths=[f[2] for f in frames],
        physicsClientId=client,
    )
    positions = [f[0] for f in frames]
    orientations = [f[1] for f in frames]
    visual = pb.createVisualShapeArray(
        visualFramePositions=positions,
        visualFrameOrientations=orientations,
        rgbaColors=[GOAL_RGBA[color]] * len(pieces),
        **kwargs,
    )
    collision = pb.createCollisionShapeArray(
        collisionFramePositions=positions, collisionFrameOrientations=orientations, **kwargs
    )
    goal = pb.createMultiBody(0, collision, visual, physicsClientId=client)
    pb.changeDynamics(goal, -1, restitution=0.6, lateralFriction=0.4, physicsClientId=client)
    return goal


def _build_surroundings(client: int, field: FieldGeometry) -> int:
    """Floor around the carpet and the four walls of the hall (visual only)."""
    hx, hy = field.carpet_half_length, field.carpet_half_width
    gap = WALL_GAP_M
    ox, oy = hx + gap, hy + gap
    floor_z, floor_t = -0.002, 0.001
    boxes = [  # (half extents, centre)
        ((ox, gap / 2, floor_t), (0.0, hy + gap / 2, floor_z)),
        ((ox, gap / 2, floor_t), (0.0, -hy - gap / 2, floor_z)),
        ((gap / 2, hy, floor_t), (hx + gap / 2, 0.0, floor_z)),
        ((gap / 2, hy, floor_t), (-hx - gap / 2, 0.0, floor_z)),
    ]
    wall_t, wall_h = 0.05, WALL_HEIGHT_M / 2
    boxes += [
        ((ox, wall_t, wall_h), (0.0, oy + wall_t, wall_h)),
        ((ox, wall_t, wall_h), (0.0, -oy - wall_t, wall_h)),
        ((wall_t, oy, wall_h), (ox + wall_t, 0.0, wall_h)),
        ((wall_t, oy, wall_h), (-ox - wall_t, 0.0, wall_h)),
    ]
    rgba = [FLOOR_RGBA] * 4 + [WALL_RGBA] * 4
    return _static_boxes(client, boxes, rgba)


def _build_banners(client: int, field: FieldGeometry) -> int:
    """Light advertising boards on the walls, which a camera can mistake for white."""
    ox = field.carpet_half_length + WALL_GAP_M
    oy = field.carpet_half_width + WALL_GAP_M
    z = BANNER_BOTTOM_M + BANNER_HEIGHT_M / 2
    t = 0.01
    boxes = []
    for x in (-3.0, -1.0, 1.0, 3.0):
        boxes.append(((0.7, t, BANNER_HEIGHT_M / 2), (x, oy - t, z)))
        boxes.append(((0.7, t, BANNER_HEIGHT_M / 2), (x, -oy + t, z)))
    for y in (-2.2, 2.2):
        boxes.append(((t, 0.8, BANNER_HEIGHT_M / 2), (ox - t, y, z)))
        boxes.append(((t, 0.8, BANNER_HEIGHT_M / 2), (-ox + t, y, z)))
    return _static_boxes(client, boxes, [BANNER_RGBA] * len(boxes))


def _static_boxes(client: int, boxes, rgba) -> int:
    visual = pb.createVisualShapeArray(
        shapeTypes=[pb.GEOM_BOX] * len(boxes),
        halfExtents=[h for h, _ in boxes],
        visualFramePositions=[c for _, c in boxes],
        rgbaColors=list(rgba),
        physicsClientId=client,
    )
    return pb.createMultiBody(0, -1, visual, physicsClientId=client)
