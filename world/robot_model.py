"""The Nao-like robot body: a few box primitives on revolute joints, built in a pybullet client.

Base frame = torso centre (``TORSO_CENTER_HEIGHT_M`` above the ground when standing), x
forward, y left, z up. The torso frame of :mod:`world.camera_model` is the base frame moved
down to the ground. Joint angles follow the Nao: head yaw CCW positive, pitch joints
positive when the limb or head tips forward/down.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass

import pybullet as pb

from world.camera_model import NAO_HEAD
from world.teams import TeamColor

TORSO_CENTER_HEIGHT_M = 0.34
TORSO_SIZE_M = (0.09, 0.14, 0.17)
TORSO_MASS_KG = 1.9

BODY_RGBA = (0.92, 0.92, 0.92, 1.0)
LIMB_RGBA = (0.72, 0.72, 0.76, 1.0)


class Joint(enum.IntEnum):
    """Link/joint indices of the robot multibody (pybullet link index = joint index)."""

    WAIST = 0
    HEAD_YAW = 1
    HEAD_PITCH = 2
    L_SHOULDER = 3
    R_SHOULDER = 4
    L_HIP = 5
    L_KNEE = 6
    L_ANKLE = 7
    R_HIP = 8
    R_KNEE = 9
    R_ANKLE = 10


ACTUATED_JOINTS: tuple[Joint, ...] = tuple(j for j in Joint if j is not Joint.WAIST)
FEET: tuple[Joint, Joint] = (Joint.L_ANKLE, Joint.R_ANKLE)


@dataclass(frozen=True)
class _LinkSpec:
    joint: Joint
    parent: Joint | None  # None: the torso (base)
    joint_position: tuple[float, float, float]  # in the parent link frame, m
    axis: tuple[float, float, float]
    mass_kg: float
    box_half_extents: tuple[float, float, float] | None
    box_center: tuple[float, float, float]  # shape centre in the link frame, m
    rgba: tuple[float, float, float, float]
    revolute: bool = True


_NECK_Z = NAO_HEAD.neck_height_m - TORSO_CENTER_HEIGHT_M
_HIP_Z = -0.095
_LEG_SEGMENT_M = 0.10
_FOOT_HALF = (0.08, 0.04, 0.015)

_LINKS: tuple[_LinkSpec, ...] = (
    _LinkSpec(Joint.WAIST, None, (0, 0, -0.07), (0, 0, 1), 0.05, (0.048, 0.073, 0.015), (0, 0, 0), BODY_RGBA, False),
    _LinkSpec(Joint.HEAD_YAW, None, (0, 0, _NECK_Z), (0, 0, 1), 0.05, None, (0, 0, 0), BODY_RGBA),
    _LinkSpec(Joint.HEAD_PITCH, Joint.HEAD_YAW, (0, 0, 0), (0, 1, 0), 0.55, (0.05, 0.065, 0.055), (0, 0, 0.055), BODY_RGBA),
    _LinkSpec(Joint.L_SHOULDER, None, (0, 0.095, 0.06), (0, 1, 0), 0.3, (0.022, 0.022, 0.1), (0, 0, -0.09), LIMB_RGBA),
    _LinkSpec(Joint.R_SHOULDER, None, (0, -0.095, 0.06), (0, 1, 0), 0.3, (0.022, 0.022, 0.1), (0, 0, -0.09), LIMB_RGBA),
    _LinkSpec(Joint.L_HIP, None, (0, 0.05, _HIP_Z), (0, 1, 0), 0.4, (0.03, 0.03, 0.05), (0, 0, -0.05), LIMB_RGBA),
    _LinkSpec(Joint.L_KNEE, Joint.L_HIP, (0, 0, -_LEG_SEGMENT_M), (0, 1, 0), 0.3, (0.027, 0.027, 0.05), (0, 0, -0.05), LIMB_RGBA),
    _LinkSpec(Joint.L_ANKLE, Joint.L_KNEE, (0, 0, -_LEG_SEGMENT_M), (0, 1, 0), 0.2, _FOOT_HALF, (0.02, 0, -0.03), BODY_RGBA),
    _LinkSpec(Joint.R_HIP, None, (0, -0.05, _HIP_Z), (0, 1, 0), 0.4, (0.03, 0.03, 0.05), (0, 0, -0.05), LIMB_RGBA),
    _LinkSpec(Joint.R_KNEE, Joint.R_HIP, (0, 0, -_LEG_SEGMENT_M), (0, 1, 0), 0.3, (0.027, 0.027, 0.05), (0, 0, -0.05), LIMB_RGBA),
    _LinkSpec(Joint.R_ANKLE, Joint.R_KNEE, (0, 0, -_LEG_SEGMENT_M), (0, 1, 0), 0.2, _FOOT_HALF, (0.02, 0, -0.03), BODY_RGBA),
)

TOTAL_MASS_KG = TORSO_MASS_KG + sum(link.mass_kg for link in _LINKS)
FOOT_SOLE_OFFSET_M = TORSO_CENTER_HEIGHT_M  # the soles touch the ground when standing


def robot_link_shapes() -> list[tuple[int, tuple[float, float, float], tuple[float, ...], bool]]:
    """The links drawn as boxes: (link index, half extents m, colour, whether it is the waistband, whose
    colour is the team's). Each box is centred on its link's centre of mass."""
    return [(int(link.joint), link.box_half_extents, link.rgba, link.joint is Joint.WAIST)
            for link in _LINKS if link.box_half_extents is not None]


def build_robot(client: int, team: TeamColor, x: float, y: float, yaw: float) -> int:
    """Create one robot standing at (x, y) facing ``yaw``; return its body id."""
    torso_half = tuple(s / 2.0 for s in TORSO_SIZE_M)
    base_collision = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=torso_half, physicsClientId=client)
    base_visual = pb.createVisualShape(pb.GEOM_BOX, halfExtents=torso_half, rgbaColor=BODY_RGBA, physicsClientId=client)
    collisions, visuals = [], []
    for link in _LINKS:
        if link.box_half_extents is None:
            collisions.append(-1)
            visuals.append(-1)
            continue
        collisions.append(
            pb.createCollisionShape(
                pb.GEOM_BOX,
                halfExtents=link.box_half_extents,
                collisionFramePosition=link.box_center,
                physicsClientId=client,
            )
        )
        visuals.append(
            pb.createVisualShape(
                pb.GEOM_BOX,
                halfExtents=link.box_half_extents,
                visualFramePosition=link.box_center,
                rgbaColor=team.rgba if link.joint is Joint.WAIST else link.rgba,
                physicsClientId=client,
            )
        )
    body = pb.createMultiBody(
        baseMass=TORSO_MASS_KG,
        baseCollisionShapeIndex=base_collision,
        baseVisualShapeIndex=base_visual,
        basePosition=(x, y, TORSO_CENTER_HEIGHT_M),
        baseOrientation=pb.getQuaternionFromEuler((0.0, 0.0, yaw)),
        linkMasses=[link.mass_kg for link in _LINKS],
        linkCollisionShapeIndices=collisions,
        linkVisualShapeIndices=visuals,
        linkPositions=[link.joint_position for link in _LINKS],
        linkOrientations=[(0, 0, 0, 1)] * len(_LINKS),
        linkInertialFramePositions=[link.box_center for link in _LINKS],
        linkInertialFrameOrientations=[(0, 0, 0, 1)] * len(_LINKS),
        linkParentIndices=[0 if link.parent is None else int(link.parent) + 1 for link in _LINKS],
        linkJointTypes=[pb.JOINT_REVOLUTE if link.revolute else pb.JOINT_FIXED for link in _LINKS],
        linkJointAxis=[link.axis for link in _LINKS],
        physicsClientId=client,
    )
    # Soles slide without friction: the walk controller, not carpet friction, holds the
    # robot in place, so pushes and drive forces stay in one place (world.locomotion).
    for foot in FEET:
        pb.changeDynamics(body, int(foot), lateralFriction=0.0, physicsClientId=client)
    for joint in ACTUATED_JOINTS:
        pb.changeDynamics(body, int(joint), jointDamping=0.05, physicsClientId=client)
    return body


def set_team_color(client: int, body: int, team: TeamColor) -> None:
    pb.changeVisualShape(body, int(Joint.WAIST), rgbaColor=team.rgba, physicsClientId=client)

