"""Odometry and posture: the last step's walk moves the beliefs; the inertial sensors tell falls.

The translation is the walk as commanded (nominal), the turn as the gyro measured it (it also feels
pushes and collisions), while the robot is upright: the accelerometer's torso z reads g cos(tilt),
low-passed (``posture.upright_smoothing``; walking shakes single readings), below
``posture.upright_acceleration_mps2`` it is falling. The self-locator, the ball model and the obstacle
model are moved; the sonars' echoes go into the obstacle model; a fall widens the pose's uncertainty.
"""

from __future__ import annotations

import math

from agents.behavior import skills
from agents.modelling.ball_model import BallModel
from agents.modelling.obstacle_model import ObstacleModel
from agents.modelling.self_locator import SelfLocator
from agents.observation import Observation
from agents.team.modelling.representations import Odometry, Posture
from agents.team.params import TeamParams
from match.protocol import Displacement, Motion

DT_S = skills.CONTROL_STEP_S


class OdometryProvider:
    """Provides :class:`Odometry` and :class:`Posture`, moving the models it is given."""

    def __init__(self, locator: SelfLocator, ball: BallModel, obstacles: ObstacleModel, params: TeamParams):
        self.locator, self.ball, self.obstacles, self.params = locator, ball, obstacles, params
        self._acceleration_z = 9.81
        self._was_fallen = False
        self._fall_sequence = 0  # the finished-motion count when it last went down

    def update(self, obs: Observation, walk: tuple[float, float, float]) -> tuple[Odometry, Posture]:
        """``walk``: the walk (vx m/s, vy m/s, omega rad/s) commanded last step."""
        p = self.params.posture
        walking = obs.motion is Motion.WALK
        vx, vy, _ = walk if walking else skills.STILL
        self._acceleration_z += p.upright_smoothing * (obs.accelerometer_mps2[2] - self._acceleration_z)
        standing_up = obs.motion is not None and obs.motion.is_stand_up
        upright = not obs.fallen and not standing_up and self._acceleration_z > p.upright_acceleration_mps2
        omega = obs.gyro_radps[2] if upright else 0.0
        moved = arc(vx, vy, omega, DT_S)
        self.locator.move(moved)
        self.ball.predict(DT_S, moved)
        self.obstacles.predict(moved, DT_S)
        self.obstacles.hear_sonar(obs.sonar_m)
        if obs.fallen and not self._was_fallen:
            self.locator.fell(p.fall_sigma_m, p.fall_sigma_rad)
            self._fall_sequence = obs.last_motion_sequence
        self._was_fallen = obs.fallen
        last = obs.last_motion
        tried = last is not None and last.is_stand_up and obs.last_motion_sequence > self._fall_sequence
        odometry = Odometry(upright, walk[2] if walking else 0.0, omega)
        posture = Posture(obs.motion, obs.fallen, standing_up, tried, last if tried else None,
                          tuple(obs.gyro_radps), obs.accelerometer_mps2[0], tuple(obs.sonar_m))
        return odometry, posture


def arc(vx: float, vy: float, omega: float, dt: float) -> Displacement:
    """The displacement of walking at (vx, vy, omega) for ``dt`` (robot frame at the start)."""
    turn = omega * dt
    if abs(turn) < 1e-9:
        return Displacement(vx * dt, vy * dt, 0.0)
    s, c = math.sin(turn), math.cos(turn)
    forward = (vx * s + vy * (c - 1.0)) / omega
    left = (vx * (1.0 - c) + vy * s) / omega
    return Displacement(forward, left, turn)
