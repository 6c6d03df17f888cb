"""The ball model: a Kalman filter of the ball's position and velocity relative to the robot.

The state is kept in the robot's torso frame (x forward, y left; m and m/s), where the ball
is measured and where approaching and kicking need it, and moved by the robot's own
odometry every step; :meth:`BallModel.in_field` gives it in the field frame through the
robot's pose estimate, with the pose's uncertainty added. The ball rolls on with a
velocity that decays (rolling friction: a 1.5 m/s ball rolls about 3 m). A measurement far
from the prediction (a kick, the referee placing the ball) resets the filter after
:data:`JUMP_CONFIRMATIONS` such measurements in a row.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from agents.modelling.spread import largest_eigenvalue
from match.protocol import Displacement

ROLL_DECAY_S = 2.0  # velocity time constant: 1.5 m/s * 2 s = 3 m of roll
ACCELERATION_SIGMA_MPS2 = 1.5  # process noise: unmodelled pushes and kicks
INITIAL_VELOCITY_SIGMA_MPS = 1.0
MEASUREMENT_SIGMA_M = 0.03  # at close range
MEASUREMENT_SIGMA_PER_M = 0.08  # grows with the distance (a pixel row covers more ground)
BEARING_SIGMA_RAD = math.radians(2.0)
JUMP_GATE = 16.0  # squared Mahalanobis distance beyond which a measurement does not fit
JUMP_CONFIRMATIONS = 2
MAX_SPEED_MPS = 4.0


@dataclass(frozen=True)
class BallEstimate:
    """Where the ball is believed to be: ``x``, ``y`` (m) and ``vx``, ``vy`` (m/s) in one frame,
    ``sigma_m`` the larger standard deviation of the position, ``age_s`` the time since the
    last measurement."""

    x: float
    y: float
    vx: float
    vy: float
    sigma_m: float
    age_s: float

    @property
    def distance_m(self) -> float:
        return math.hypot(self.x, self.y)

    @property
    def bearing_rad(self) -> float:
        return math.atan2(self.y, self.x)

    @property
    def left_m(self) -> float:
        return self.y


class BallModel:
    """The filter. ``predict(dt, displacement)`` every step, ``measure(distance, bearing)`` when seen."""

    def __init__(self) -> None:
        self.x: np.ndarray | None = None  # [x, y, vx, vy], torso frame
        self.p = np.zeros((4, 4))
        self.age_s = math.inf
        self._misfits = 0

    @property
    def known(self) -> bool:
        return self.x is not None

    def reset(self) -> None:
        self.x = None
        self.age_s = math.inf
        self._misfits = 0

    def predict(self, dt_s: float, moved: Displacement) -> None:
        """Let ``dt_s`` pass while the robot moved by ``moved`` (its frame at the start of the step)."""
        self.age_s += dt_s
        if self.x is None:
            return
        f, q = _transition(dt_s)
        self.x = f @ self.x
        self.p = f @ self.p @ f.T + q
        # Into the robot's new frame: shift by the displacement, rotate by -turn.
        c, s = math.cos(moved.turn_rad), math.sin(moved.turn_rad)
        rotation = np.array([[c, s], [-s, c]])
        position = rotation @ (self.x[:2] - (moved.forward_m, moved.left_m))
        velocity = rotation @ self.x[2:]
        self.x = np.concatenate([position, velocity])
        block = np.zeros((4, 4))
        block[:2, :2] = rotation
        block[2:, 2:] = rotation
        self.p = block @ self.p @ block.T

    def measure(self, distance_m: float, bearing_rad: float) -> None:
        """A sighting: ground distance (m) and bearing (rad, CCW) in the torso frame."""
        z = np.array([distance_m * math.cos(bearing_rad), distance_m * math.sin(bearing_rad)])
        r = _measurement_noise(distance_m, bearing_rad)
        if self.x is None:
            self._start(z, r)
            return
        h = np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0]])
        innovation = z - h @ self.x
        s = h @ self.p @ h.T + r
        if float(innovation @ np.linalg.solve(s, innovation)) > JUMP_GATE:
            self._misfits += 1
            if self._misfits >= JUMP_CONFIRMATIONS:
                self._start(z, r)
            return
        self._misfits = 0
        gain = self.p @ h.T @ np.linalg.inv(s)
        self.x = self.x + gain @ innovation
        self.p = (np.eye(4) - gain @ h) @ self.p
        speed = math.hypot(self.x[2], self.x[3])
        if speed > MAX_SPEED_MPS:
            self.x[2:] *= MAX_SPEED_MPS / speed
        self.age_s = 0.0

    def relative(self) -> BallEstimate | None:
        """The ball in the torso frame, or None when never seen."""
        if self.x is None:
            return None
        sigma = math.sqrt(largest_eigenvalue(self.p[0, 0], self.p[0, 1], self.p[1, 1]))
        return BallEstimate(*(float(v) for v in self.x), sigma, self.age_s)

    def in_field(self, pose: tuple[float, float, float], pose_sigma_m: float, pose_sigma_rad: float) -> BallEstimate | None:
        """The ball in the field frame, seen from ``pose`` (x, y, theta) known to the given sigmas."""
        rel = self.relative()
        return None if rel is None else to_field(rel, pose, pose_sigma_m, pose_sigma_rad)

    def _start(self, z: np.ndarray, r: np.ndarray) -> None:
        self.x = np.array([z[0], z[1], 0.0, 0.0])
        self.p = np.zeros((4, 4))
        self.p[:2, :2] = r
        self.p[2, 2] = self.p[3, 3] = INITIAL_VELOCITY_SIGMA_MPS**2
        self.age_s = 0.0
        self._misfits = 0


@functools.lru_cache(maxsize=8)
def _transition(dt_s: float) -> tuple[np.ndarray, np.ndarray]:
    """The state transition over ``dt_s`` (the roll decays) and its process noise, read-only: every step
    of a robot lasts the same, so they are built once."""
    decay = math.exp(-dt_s / ROLL_DECAY_S)
    f = np.array([[1, 0, dt_s, 0], [0, 1, 0, dt_s], [0, 0, decay, 0], [0, 0, 0, decay]], float)
    q = _process_noise(dt_s)
    f.flags.writeable = q.flags.writeable = False
    return f, q


def _process_noise(dt_s: float) -> np.ndarray:
    a2 = ACCELERATION_SIGMA_MPS2**2
    q = np.zeros((4, 4))
    for i in (0, 1):
        q[i, i] = a2 * dt_s**4 / 4
        q[i, i + 2] = q[i + 2, i] = a2 * dt_s**3 / 2
        q[i + 2, i + 2] = a2 * dt_s**2
    return q


def _measurement_noise(distance_m: float, bearing_rad: float) -> np.ndarray:
    """Covariance of a sighting in the torso frame: along the ray and across it."""
    along = MEASUREMENT_SIGMA_M + MEASUREMENT_SIGMA_PER_M * distance_m
    across = max(MEASUREMENT_SIGMA_M, distance_m * BEARING_SIGMA_RAD)
    c, s = math.cos(bearing_rad), math.sin(bearing_rad)
    rotation = np.array([[c, -s], [s, c]])
    return rotation @ np.diag([along**2, across**2]) @ rotation.T


def to_field(rel: BallEstimate, pose: tuple[float, float, float], pose_sigma_m: float,
             pose_sigma_rad: float) -> BallEstimate:
    """A torso-frame estimate in the field frame, seen from ``pose`` (x m, y m, theta rad) known to the given
    sigmas (m, rad): the pose's uncertainty adds to the ball's, its heading's by the ball's distance."""
    px, py, theta = pose
    c, s = math.cos(theta), math.sin(theta)
    x = px + c * rel.x - s * rel.y
    y = py + s * rel.x + c * rel.y
    vx, vy = c * rel.vx - s * rel.vy, s * rel.vx + c * rel.vy
    sigma = math.sqrt(rel.sigma_m**2 + pose_sigma_m**2 + (rel.distance_m * pose_sigma_rad) ** 2)
    return BallEstimate(x, y, vx, vy, sigma, rel.age_s)
