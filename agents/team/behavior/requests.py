"""What the behaviour asks for: the body's motion, the head, and what the radio tells the team."""

from __future__ import annotations

from dataclasses import dataclass

from agents.behavior import skills
from agents.radio import Intention
from match.protocol import Motion
from world.camera_model import CameraPosition

Walk = tuple[float, float, float]  # vx (m/s), vy (m/s), omega (rad/s), torso frame


@dataclass(frozen=True)
class MotionRequest:
    """A motion (the walk's command with :data:`Motion.WALK`) and what it means for the team;
    ``intention`` None: as it said last step (a kick under way)."""

    motion: Motion
    walk: Walk = skills.STILL
    intention: Intention | None = None

    @staticmethod
    def of(motion_walk: tuple[Motion, Walk], intention: Intention | None = None) -> MotionRequest:
        return MotionRequest(motion_walk[0], motion_walk[1], intention)


STAND = MotionRequest(Motion.STAND, skills.STILL)


@dataclass(frozen=True)
class HeadRequest:
    """Head angles (torso frame, rad) and the camera that takes the next frame."""

    yaw_rad: float
    pitch_rad: float
    camera: CameraPosition


@dataclass(frozen=True)
class BehaviorOutput:
    """One step's requests: the motion, the head, whether the striker lines up a kick with the ball at its
    feet (every few frames then come from the top camera), and the radio's role, intention and time to
    the ball (s)."""

    motion: MotionRequest
    head: HeadRequest
    lining_up: bool
    role: str
    intention: Intention
    time_to_ball_s: float
