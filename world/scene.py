"""The static scene: carpet with painted lines, goals, the floor, walls and banners around.

Static geometry is merged into few bodies (one per colour), because TinyRenderer's cost
grows with the number of shapes and with the screen area each triangle's box covers. The
hall's quads (walls, roof, banners) come from functions that :mod:`world.backdrop` reads
too, so the analytic drawing and TinyRenderer's draw the same geometry.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import pybullet as pb

from world.field import FieldGeometry, GoalColor
from world.meshes import goal_mesh, goal_pieces
from world.textures import carpet_texture_file

GOAL_RGBA = {GoalColor.BLUE: (0.1, 0.25, 0.95, 1.0), GoalColor.YELLOW: (0.95, 0.85, 0.1, 1.0)}
FLOOR_RGBA = (0.451, 0.42, 0.4, 1.0)  # red: 255 * 0.451 truncates to 115, not 114
WALL_RGBA = (0.28, 0.3, 0.38, 1.0)
BANNER_RGBA = (0.93, 0.93, 0.9, 1.0)
SKY_RGBA = (0.55, 0.62, 0.75, 1.0)

WALL_GAP_M = 1.2  # from the carpet edge to the walls
WALL_HEIGHT_M = 4.0
BANNER_HEIGHT_M = 0.5
BANNER_BOTTOM_M = 0.35
CARPET_TILES = (4, 3)  # smaller triangles cut TinyRenderer's per-triangle bounding-box cost
WALL_OVERLAP_M = 0.05  # walls reach this far below the floor and past the corners: no cracks
BANNER_INSET_M = 0.01  # banners hang this far in front of their wall

Quad = tuple[tuple[float, float, float], ...]
"""Four corners (x, y, z) m, counter-clockwise seen from the front (the side that is drawn)."""


@dataclass(frozen=True)
class SceneBodies:
    ground: int
    carpet: int
    floor: int
    goals: dict[GoalColor, int]
    surroundings: int
    roof: int
    banners: int

    floor_half_extent: tuple[float, float]

    @property
    def ground_visuals(self) -> tuple[int, ...]:
        """Bodies that :mod:`world.ground` draws analytically instead: ground, walls, roof, banners."""
        return self.carpet, self.floor, self.surroundings, self.roof, self.banners


def hall_half_extent(field: FieldGeometry) -> tuple[float, float]:
    """Half length and half width (m) of the hall's floor, out to the walls."""
    return field.carpet_half_length + WALL_GAP_M, field.carpet_half_width + WALL_GAP_M


def build_scene(client: int, field: FieldGeometry) -> SceneBodies:
    """Create the static bodies of the field in ``client``."""
    ground_shape = pb.createCollisionShape(pb.GEOM_PLANE, physicsClientId=client)
    ground = pb.createMultiBody(0, ground_shape, -1, physicsClientId=client)
    pb.changeDynamics(ground, -1, lateralFriction=0.8, restitution=0.0, physicsClientId=client)
    # Collision only: the carpet and floor are drawn; a visible plane would double the fill.
    pb.changeVisualShape(ground, -1, rgbaColor=(0, 0, 0, 0), physicsClientId=client)
    carpet = _build_carpet(client, field)
    floor = _build_floor(client, field)
    goals = {color: _build_goal(client, field, color) for color in GoalColor}
    roof = _static_quads(client, [roof_quad(field)], SKY_RGBA)
    return SceneBodies(
        ground=ground,
        carpet=carpet,
        floor=floor,
        goals=goals,
        surroundings=_build_walls(client, field),
        roof=roof,
        banners=_static_quads(client, banner_quads(field), BANNER_RGBA),
        floor_half_extent=hall_half_extent(field),
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
    """Posts, crossbar and the thin back frame as one body: they collide as cylinders and boxes, and are
    drawn as one explicit mesh (:func:`world.meshes.goal_mesh`), which the compiled renderer draws too."""
    pieces = goal_pieces(field, color)
    frames = [_cylinder_between(start, end) for start, end, _, _ in pieces]
    collision = pb.createCollisionShapeArray(
        shapeTypes=[pb.GEOM_CYLINDER if round_piece else pb.GEOM_BOX for *_, round_piece in pieces],
        radii=[radius for _, _, radius, _ in pieces],
        lengths=[length for _, _, length in frames],
        halfExtents=[(radius, radius, length / 2) for (_, _, radius, _), (_, _, length) in zip(pieces, frames)],
        collisionFramePositions=[position for position, _, _ in frames],
        collisionFrameOrientations=[orientation for _, orientation, _ in frames],
        physicsClientId=client,
    )
    visual = pb.createVisualShape(pb.GEOM_MESH, rgbaColor=GOAL_RGBA[color], physicsClientId=client,
                                  **goal_mesh(field, color).pybullet_arguments())
    goal = pb.createMultiBody(0, collision, visual, physicsClientId=client)
    pb.changeDynamics(goal, -1, restitution=0.6, lateralFriction=0.4, physicsClientId=client)
    return goal


def _build_floor(client: int, field: FieldGeometry) -> int:
    """The hall's floor between the carpet and the walls: four strips facing up."""
    hx, hy = field.carpet_half_length, field.carpet_half_width
    ox, oy = hall_half_extent(field)
    floor_z = -0.002
    floor = [  # four strips between the carpet edge and the walls, facing up
        ((-ox, hy, floor_z), (ox, hy, floor_z), (ox, oy, floor_z), (-ox, oy, floor_z)),
        ((-ox, -oy, floor_z), (ox, -oy, floor_z), (ox, -hy, floor_z), (-ox, -hy, floor_z)),
        ((hx, -hy, floor_z), (ox, -hy, floor_z), (ox, hy, floor_z), (hx, hy, floor_z)),
        ((-ox, -hy, floor_z), (-hx, -hy, floor_z), (-hx, hy, floor_z), (-ox, hy, floor_z)),
    ]
    return _static_quads(client, floor, FLOOR_RGBA)


def wall_quads(field: FieldGeometry) -> list[Quad]:
    """The hall's four walls, facing the field, from below the floor to ``WALL_HEIGHT_M``."""
    ox, oy = hall_half_extent(field)
    top, low, e = WALL_HEIGHT_M, -WALL_OVERLAP_M, WALL_OVERLAP_M
    return [
        ((-ox - e, oy, low), (ox + e, oy, low), (ox + e, oy, top), (-ox - e, oy, top)),
        ((ox + e, -oy, low), (-ox - e, -oy, low), (-ox - e, -oy, top), (ox + e, -oy, top)),
        ((ox, oy + e, low), (ox, -oy - e, low), (ox, -oy - e, top), (ox, oy + e, top)),
        ((-ox, -oy - e, low), (-ox, oy + e, low), (-ox, oy + e, top), (-ox, -oy - e, top)),
    ]


def roof_quad(field: FieldGeometry) -> Quad:
    """The hall's roof, facing down, so a camera looking up sees sky colour, not TinyRenderer's white."""
    ox, oy = hall_half_extent(field)
    top, e = WALL_HEIGHT_M, WALL_OVERLAP_M
    return (-ox - e, oy + e, top), (ox + e, oy + e, top), (ox + e, -oy - e, top), (-ox - e, -oy - e, top)


def banner_quads(field: FieldGeometry) -> list[Quad]:
    """Light advertising boards on the walls, which a camera can mistake for white."""
    ox, oy = (half - BANNER_INSET_M for half in hall_half_extent(field))
    z0, z1 = BANNER_BOTTOM_M, BANNER_BOTTOM_M + BANNER_HEIGHT_M
    quads: list[Quad] = []
    for x in (-3.0, -1.0, 1.0, 3.0):
        quads.append(((x - 0.7, oy, z0), (x + 0.7, oy, z0), (x + 0.7, oy, z1), (x - 0.7, oy, z1)))
        quads.append(((x + 0.7, -oy, z0), (x - 0.7, -oy, z0), (x - 0.7, -oy, z1), (x + 0.7, -oy, z1)))
    for y in (-2.2, 2.2):
        quads.append(((ox, y + 0.8, z0), (ox, y - 0.8, z0), (ox, y - 0.8, z1), (ox, y + 0.8, z1)))
        quads.append(((-ox, y - 0.8, z0), (-ox, y + 0.8, z0), (-ox, y + 0.8, z1), (-ox, y - 0.8, z1)))
    return quads


def _build_walls(client: int, field: FieldGeometry) -> int:
    """The four walls as one-sided quads (boxes would add faces never seen); they collide, so a ball stays in."""
    ox, oy = hall_half_extent(field)
    top, wall_t = WALL_HEIGHT_M, 0.05
    collision = pb.createCollisionShapeArray(
        shapeTypes=[pb.GEOM_BOX] * 4,
        halfExtents=[(ox, wall_t, top / 2), (ox, wall_t, top / 2), (wall_t, oy, top / 2), (wall_t, oy, top / 2)],
        collisionFramePositions=[
            (0, oy + wall_t, top / 2), (0, -oy - wall_t, top / 2), (ox + wall_t, 0, top / 2), (-ox - wall_t, 0, top / 2)
        ],
        physicsClientId=client,
    )
    return _static_quads(client, wall_quads(field), WALL_RGBA, collision)


def _static_quads(client: int, quads, rgba, collision: int = -1) -> int:
    """One static body showing the given quads (corners counter-clockwise seen from the front)."""
    vertices, normals, indices = [], [], []
    for quad in quads:
        a, b, c = quad[0], quad[1], quad[2]
        u = [b[i] - a[i] for i in range(3)]
        v = [c[i] - a[i] for i in range(3)]
        n = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
        length = math.sqrt(sum(x * x for x in n))
        base = len(vertices)
        vertices += list(quad)
        normals += [tuple(x / length for x in n)] * 4
        indices += [base, base + 1, base + 2, base, base + 2, base + 3]
    visual = pb.createVisualShape(
        pb.GEOM_MESH,
        vertices=vertices,
        indices=indices,
        normals=normals,
        uvs=[(0.0, 0.0)] * len(vertices),
        rgbaColor=rgba,
        physicsClientId=client,
    )
    return pb.createMultiBody(0, collision, visual, physicsClientId=client)
