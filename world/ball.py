"""The ball: an orange sphere with rolling friction, and its ground-truth state."""

from __future__ import annotations

from dataclasses import dataclass

import pybullet as pb

from world.config import BallConfig
from world.field import FieldGeometry
from world.meshes import icosphere_mesh

BALL_RGBA = (1.0, 0.55, 0.0, 1.0)


@dataclass(frozen=True)
class BallState:
    """Ground truth of the ball (field frame, m and m/s), and who touched it last."""

    x: float
    y: float
    z: float
    vx: float
    vy: float
    vz: float
    last_toucher: str | None
    last_touch_time_s: float | None


def build_ball(client: int, field: FieldGeometry, config: BallConfig) -> int:
    radius = field.ball_radius
    collision = pb.createCollisionShape(pb.GEOM_SPHERE, radius=radius, physicsClientId=client)
    # Drawn as an explicit mesh, the same one the compiled renderer draws (world.meshes).
    visual = pb.createVisualShape(pb.GEOM_MESH, rgbaColor=BALL_RGBA, physicsClientId=client,
                                  **icosphere_mesh(radius).pybullet_arguments())
    ball = pb.createMultiBody(field.ball_mass, collision, visual, basePosition=(0.0, 0.0, radius), physicsClientId=client)
    pb.changeDynamics(
        ball,
        -1,
        rollingFriction=config.rolling_friction,
        spinningFriction=config.spinning_friction,
        lateralFriction=config.lateral_friction,
        restitution=config.restitution,
        linearDamping=config.linear_damping,
        angularDamping=0.0,
        physicsClientId=client,
    )
    return ball
