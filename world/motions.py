"""The predefined motions (RobotStadium style), their nominal displacements and their noise.

Pure Python. A motion's *nominal* displacement is what the robot is told it did (its
odometry may use it); its *real* displacement, drawn here from a seeded generator, is what
the locomotion controller then tries to achieve through physics, where collisions change it
further. Displacements are in the robot frame at the motion's start: forward (+x), left
(+y), turn CCW positive.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

import numpy as np

from world.errors import InvalidCommandError, UnknownMotionError


class Motion(enum.Enum):
    STAND = "stand"
    FORWARD = "forward"
    BACKWARD = "backward"
    SIDE_STEP_LEFT = "side_step_left"
    SIDE_STEP_RIGHT = "side_step_right"
    TURN_LEFT_20 = "turn_left_20"
    TURN_LEFT_40 = "turn_left_40"
    TURN_LEFT_60 = "turn_left_60"
    TURN_LEFT_180 = "turn_left_180"
    TURN_RIGHT_20 = "turn_right_20"
    TURN_RIGHT_40 = "turn_right_40"
    TURN_RIGHT_60 = "turn_right_60"
    TURN_RIGHT_180 = "turn_right_180"
    KICK_LEFT = "kick_left"
    KICK_RIGHT = "kick_right"
    STAND_UP_FROM_FRONT = "stand_up_from_front"
    STAND_UP_FROM_BACK = "stand_up_from_back"
    WALK = "walk"  # continuous (vx, vy, omega) command; lasts until replaced

    @classmethod
    def parse(cls, name: object) -> Motion:
        """The motion of a name (case-insensitive) or the motion itself."""
        if isinstance(name, Motion):
            return name
        if isinstance(name, str):
            try:
                return cls(name.lower())
            except ValueError:
                pass
        raise UnknownMotionError(f"unknown motion {name!r}; expected one of {[m.value for m in cls]}")

    @property
    def is_kick(self) -> bool:
        return self in (Motion.KICK_LEFT, Motion.KICK_RIGHT)

    @property
    def is_stand_up(self) -> bool:
        return self in (Motion.STAND_UP_FROM_FRONT, Motion.STAND_UP_FROM_BACK)


@dataclass(frozen=True)
class Displacement:
    """A planar displacement in the robot frame at the motion's start (m, m, rad)."""

    forward_m: float = 0.0
    left_m: float = 0.0
    turn_rad: float = 0.0

    def scaled(self, factor: float) -> Displacement:
        return Displacement(self.forward_m * factor, self.left_m * factor, self.turn_rad * factor)

    def plus(self, other: Displacement) -> Displacement:
        """Compose: ``other`` expressed in the frame reached after ``self``."""
        c, s = math.cos(self.turn_rad), math.sin(self.turn_rad)
        return Displacement(
            self.forward_m + c * other.forward_m - s * other.left_m,
            self.left_m + s * other.forward_m + c * other.left_m,
            self.turn_rad + other.turn_rad,
        )


@dataclass(frozen=True)
class MotionSpec:
    duration_s: float
    nominal: Displacement


def _turn(deg: float, duration_s: float) -> MotionSpec:
    return MotionSpec(duration_s, Displacement(turn_rad=math.radians(deg)))


MOTION_SPECS: dict[Motion, MotionSpec] = {
    Motion.STAND: MotionSpec(0.4, Displacement()),
    Motion.FORWARD: MotionSpec(2.5, Displacement(forward_m=0.25)),
    Motion.BACKWARD: MotionSpec(2.0, Displacement(forward_m=-0.15)),
    Motion.SIDE_STEP_LEFT: MotionSpec(1.5, Displacement(left_m=0.08)),
    Motion.SIDE_STEP_RIGHT: MotionSpec(1.5, Displacement(left_m=-0.08)),
    Motion.TURN_LEFT_20: _turn(20, 1.0),
    Motion.TURN_LEFT_40: _turn(40, 1.75),
    Motion.TURN_LEFT_60: _turn(60, 2.5),
    Motion.TURN_LEFT_180: _turn(180, 6.5),
    Motion.TURN_RIGHT_20: _turn(-20, 1.0),
    Motion.TURN_RIGHT_40: _turn(-40, 1.75),
    Motion.TURN_RIGHT_60: _turn(-60, 2.5),
    Motion.TURN_RIGHT_180: _turn(-180, 6.5),
    Motion.KICK_LEFT: MotionSpec(1.6, Displacement()),
    Motion.KICK_RIGHT: MotionSpec(1.6, Displacement()),
    Motion.STAND_UP_FROM_FRONT: MotionSpec(4.5, Displacement()),
    Motion.STAND_UP_FROM_BACK: MotionSpec(4.5, Displacement()),
}


@dataclass(frozen=True)
class WalkLimits:
    """Limits of the continuous walk command (Nao-like), m/s and rad/s."""

    max_forward_mps: float = 0.2
    max_backward_mps: float = 0.1
    max_side_mps: float = 0.1
    max_turn_radps: float = 1.0

    def check(self, vx: float, vy: float, omega: float) -> None:
        """Raise :class:`InvalidCommandError` unless the command is finite and within limits."""
        bounds = {
            "vx": (vx, -self.max_backward_mps, self.max_forward_mps),
            "vy": (vy, -self.max_side_mps, self.max_side_mps),
            "omega": (omega, -self.max_turn_radps, self.max_turn_radps),
        }
        for name, (value, lo, hi) in bounds.items():
            if not (math.isfinite(value) and lo <= value <= hi):
                raise InvalidCommandError(f"walk {name}={value!r} outside [{lo}, {hi}]")


@dataclass(frozen=True)
class MotionNoise:
    """Seeded differences between a motion's nominal and real displacement.

    The main component of every motion is scaled by ``1 + e`` with ``e`` normal with
    ``scale_sigma`` and truncated at ``scale_limit``: with the defaults a nominal 40 degree
    turn lands between 35 and 45 degrees (thesis section 5.5). Walks also drift sideways and
    in heading in proportion to the distance walked, and turns drift in position.
    """

    scale_sigma: float = 0.05
    scale_limit: float = 0.125
    lateral_drift_per_m: float = 0.05
    heading_drift_rad_per_m: float = math.radians(4.0)
    turn_position_drift_m: float = 0.01
    kick_speed_sigma: float = 0.1
    kick_yaw_sigma_rad: float = math.radians(4.0)

    @classmethod
    def none(cls) -> MotionNoise:
        return cls(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)

    def _scale(self, rng: np.random.Generator) -> float:
        if self.scale_sigma == 0.0:
            return 1.0
        return 1.0 + float(np.clip(rng.normal(0.0, self.scale_sigma), -self.scale_limit, self.scale_limit))

    def real_displacement(self, nominal: Displacement, rng: np.random.Generator) -> Displacement:
        """Draw the real displacement of one execution of a motion with ``nominal`` effect."""
        scale = self._scale(rng)
        distance = math.hypot(nominal.forward_m, nominal.left_m)
        drift = rng.normal(0.0, 1.0, size=3)
        turn_drift = self.turn_position_drift_m * abs(nominal.turn_rad) / math.pi
        along_x = nominal.forward_m * scale + drift[0] * turn_drift
        along_y = nominal.left_m * scale + drift[1] * (self.lateral_drift_per_m * distance + turn_drift)
        turn = nominal.turn_rad * scale + drift[2] * self.heading_drift_rad_per_m * distance
        return Displacement(along_x, along_y, turn)

    def walk_velocity(self, vx: float, vy: float, omega: float, rng: np.random.Generator) -> tuple[float, float, float]:
        """Real velocity of a continuous walk command: each component scaled by its own noise."""
        return vx * self._scale(rng), vy * self._scale(rng), omega * self._scale(rng)
