"""Plays motions through physics: drive force, balance torque, joint keyframes, falls.

Each robot has one :class:`LocomotionController`. Every physics substep it reads the torso
state and applies

- a horizontal drive force, applied at the ground below the torso where feet would grip,
  that makes the torso follow a reference pose, integrated from
  the motion's *real* velocity (re-anchored at the actual pose when a push moves the robot
  further than ``reanchor_position_m``, so pushes are not undone);
- a yaw torque that follows the reference heading the same way;
- a capped balance torque that keeps the torso upright: a push or collision that tilts the
  robot beyond what the cap can recover makes it fall;
- joint position targets of the motion (:func:`world.locomotion_kernels.joint_targets`), rate-limited.

The soles have no friction (see :mod:`world.robot_model`); the drive force is the only
thing that holds a standing robot in place, up to ``drive_force_max_n``. The arithmetic of a
substep is compiled (:mod:`world.locomotion_kernels`, the same bits as the Python it replaced):
this runs 8 robots x 5 substeps per control step.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass, field

import numpy as np
import pybullet as pb

from world import gaits
from world import locomotion_kernels as kernels
from world.camera_model import NAO_HEAD, CameraPosition
from world.motions import MOTION_SPECS, Displacement, Motion, MotionNoise
from world.robot_model import ACTUATED_JOINTS, TORSO_CENTER_HEIGHT_M, TOTAL_MASS_KG


@dataclass(frozen=True)
class BalanceConfig:
    """Gains and limits of the locomotion controller (SI units)."""

    fall_tilt_rad: float = math.radians(50.0)
    upright_kp: float = 90.0  # N m / rad
    upright_kd: float = 6.0  # N m s / rad
    upright_torque_max_nm: float = 6.0
    drive_time_constant_s: float = 0.06
    drive_force_max_n: float = 40.0
    position_gain_per_s: float = 5.0
    heading_gain_per_s: float = 5.0
    reanchor_position_m: float = 0.05
    reanchor_heading_rad: float = 0.2
    yaw_inertia_kgm2: float = 0.05
    yaw_torque_max_nm: float = 4.0
    joint_torque_max_nm: float = 25.0
    joint_speed_max_radps: float = 7.0
    kick_joint_speed_radps: float = 16.0
    stand_up_rise_fraction: float = 0.7


class FallSide(enum.Enum):
    NONE = "none"
    FRONT = "front"
    BACK = "back"


@dataclass(frozen=True)
class FinishedMotion:
    """A motion that ended; ``nominal`` is what the robot may feed its odometry.

    ``completed`` is False when the motion was cut short (a fall, another command); its
    nominal displacement is then the nominal one scaled by the fraction played.
    """

    motion: Motion
    nominal: Displacement
    completed: bool
    end_time_s: float
    sequence: int


@dataclass(frozen=True)
class MotionStatus:
    current: Motion | None
    elapsed_s: float
    remaining_s: float
    last_finished: FinishedMotion | None
    fallen: bool
    fall_side: FallSide
    refused: Motion | None  # the last command refused (e.g. walking while fallen)


@dataclass
class _ActiveMotion:
    motion: Motion
    start_time_s: float
    duration_s: float  # inf for WALK
    nominal_velocity: tuple[float, float, float]  # body frame vx, vy, omega
    real_velocity: tuple[float, float, float]
    kick_speed: float = 1.0
    stand_up_from: tuple | None = None  # (position, orientation) at the start of a stand-up
    stand_up_works: bool = False
    gait_start_s: float | None = None  # a walk whose speed changed keeps the gait phase of the first

    def gait_time(self, now_s: float) -> float:
        return now_s - (self.start_time_s if self.gait_start_s is None else self.gait_start_s)


@dataclass
class LocomotionController:
    """Motion state and control of one robot body (mutable; the World snapshots it)."""

    client: int
    body: int
    config: BalanceConfig
    noise: MotionNoise
    head_yaw_target: float = 0.0
    head_pitch_target: float = 0.0
    camera: CameraPosition = CameraPosition.TOP
    active: _ActiveMotion | None = None
    fall_side: FallSide = FallSide.NONE
    last_finished: FinishedMotion | None = None
    refused: Motion | None = None
    sequence: int = 0
    ref: tuple[float, float, float] = (0.0, 0.0, 0.0)  # x, y, heading
    # the actuated joints' setpoints (rad, in ACTUATED_JOINTS order), once sent (else each starts at its goal)
    joint_setpoints: np.ndarray = field(default_factory=lambda: np.zeros(kernels.SLOTS))
    _setpoints_known: bool = False
    _motors_set: bool = False  # motor targets persist in pybullet until changed
    _standing_at: tuple[float, float] | None = None  # head goals at which every setpoint reached STANDING
    _gains: np.ndarray = field(init=False, repr=False)  # control_gains(config)

    def __post_init__(self) -> None:
        self._gains = control_gains(self.config)

    # ---- commands -------------------------------------------------------------------

    def start(self, motion: Motion, now_s: float, rng: np.random.Generator, walk=(0.0, 0.0, 0.0)) -> bool:
        """Start ``motion`` (interrupting another); return False if refused (fallen).

        The motion already playing, commanded again, continues. A walk commanded again with
        another velocity ends the walk so far (its nominal displacement is reported) and
        goes on at the new velocity without breaking step: same gait phase, same reference.
        """
        walk = (float(walk[0]), float(walk[1]), float(walk[2]))  # plain floats, as the compiled control takes
        if self.fallen and not motion.is_stand_up:
            self.refused = motion
            return False
        gait_start = None
        if self.active is not None:
            if self.active.motion is motion:
                if motion is not Motion.WALK or walk == self.active.nominal_velocity:
                    return True
                gait_start = self.active.start_time_s if self.active.gait_start_s is None else self.active.gait_start_s
            self._finish(now_s, completed=False, reanchor=gait_start is None)
        self.refused = None
        if motion is Motion.WALK:
            real = self.noise.walk_velocity(*walk, rng)
            self.active = _ActiveMotion(motion, now_s, math.inf, walk, real, gait_start_s=gait_start)
            if gait_start is not None:
                return True
        else:
            spec = MOTION_SPECS[motion]
            real = self.noise.real_displacement(spec.nominal, rng)
            active_s = gaits.KICK_SWING_START_S if motion.is_kick else spec.duration_s
            nominal = spec.nominal.scaled(1.0 / spec.duration_s)
            velocity = real.scaled(1.0 / active_s)
            self.active = _ActiveMotion(
                motion,
                now_s,
                spec.duration_s,
                (nominal.forward_m, nominal.left_m, nominal.turn_rad),
                (velocity.forward_m, velocity.left_m, velocity.turn_rad),
            )
            if motion.is_kick:
                kick_yaw = rng.normal(0.0, self.noise.kick_yaw_sigma_rad) if self.noise.kick_yaw_sigma_rad else 0.0
                self.active.real_velocity = (0.0, 0.0, kick_yaw / active_s)
                self.active.kick_speed = 1.0 + (rng.normal(0.0, self.noise.kick_speed_sigma) if self.noise.kick_speed_sigma else 0.0)
            if motion.is_stand_up:
                self.active.stand_up_from = pb.getBasePositionAndOrientation(self.body, physicsClientId=self.client)
                wanted = FallSide.FRONT if motion is Motion.STAND_UP_FROM_FRONT else FallSide.BACK
                self.active.stand_up_works = self.fall_side is wanted
        self._anchor()
        return True

    def set_head(self, yaw_rad: float, pitch_rad: float) -> None:
        self.head_yaw_target, self.head_pitch_target = float(yaw_rad), float(pitch_rad)

    def resend_motor_targets(self) -> None:
        """Send the joint setpoints again at the next substep (after a restored state)."""
        self._motors_set = False

    @property
    def fallen(self) -> bool:
        return self.fall_side is not FallSide.NONE

    def status(self, now_s: float) -> MotionStatus:
        if self.active is None:
            current, elapsed, remaining = None, 0.0, 0.0
        else:
            current = self.active.motion
            elapsed = now_s - self.active.start_time_s
            remaining = max(0.0, self.active.duration_s - elapsed)
        return MotionStatus(current, elapsed, remaining, self.last_finished, self.fallen, self.fall_side, self.refused)

    def reset(self) -> None:
        """Forget all motion state (after the robot has been placed somewhere)."""
        self.active = None
        self.fall_side = FallSide.NONE
        self.refused = None
        self._setpoints_known = False
        self._motors_set = False
        self._standing_at = None
        self._anchor()

    # ---- control --------------------------------------------------------------------

    def substep(self, now_s: float, dt_s: float) -> None:
        """Apply forces and joint targets for one physics substep starting at ``now_s``."""
        client = self.client
        position, orientation = pb.getBasePositionAndOrientation(self.body, physicsClientId=client)
        linear, angular = pb.getBaseVelocity(self.body, physicsClientId=client)
        m = pb.getMatrixFromQuaternion(orientation)  # row-major 3x3
        tilt = math.acos(max(-1.0, min(1.0, m[8])))
        heading = torso_heading(m)
        active = self.active
        if active is not None and now_s - active.start_time_s >= active.duration_s:
            self._finish(now_s, completed=True)
            active = None
        if active is not None and active.motion.is_stand_up and active.stand_up_works:
            self._play_stand_up(active, now_s)
            self._drive_joints(kernels.STAND_UP, now_s - active.start_time_s, active.duration_s, dt_s)
            return
        if not self.fallen and tilt > self.config.fall_tilt_rad:
            self.fall_side = FallSide.FRONT if m[6] < 0.0 else FallSide.BACK
            if active is not None:
                self._finish(now_s, completed=False)
                active = None
        if self.fallen:
            self._drive_joints(kernels.STANDING, 0.0, 0.0, dt_s)
            return
        vx, vy, omega = active.real_velocity if active is not None else (0.0, 0.0, 0.0)
        if active is not None and active.motion.is_kick and now_s - active.start_time_s >= gaits.KICK_SWING_START_S:
            omega = 0.0
        fx, fy, tx, ty, tz, *ref = kernels.control(
            position[0], position[1], linear[0], linear[1], angular[0], angular[1], angular[2], heading, m[2], m[5],
            m[8], vx, vy, omega, dt_s, *self.ref, self._gains)
        self.ref = tuple(ref)
        # The drive force is applied at the ground below the torso, where feet would grip: a push at
        # torso height then tips the robot as it would a real one.
        pb.applyExternalForce(self.body, -1, (fx, fy, 0.0), (position[0], position[1], 0.0), pb.WORLD_FRAME,
                              physicsClientId=client)
        pb.applyExternalTorque(self.body, -1, (tx, ty, tz), pb.WORLD_FRAME, physicsClientId=client)
        mode, mode_s = self._joint_mode(active, now_s)
        self._drive_joints(mode, mode_s, 0.0, dt_s, kick_speed=active.kick_speed if active else 1.0)

    @staticmethod
    def _joint_mode(active: _ActiveMotion | None, now_s: float) -> tuple[int, float]:
        """Which targets the limbs follow (a mode of :func:`~world.locomotion_kernels.joint_targets`) and the
        time into them (s)."""
        if active is None or active.motion is Motion.STAND:
            return kernels.STANDING, 0.0
        if active.motion.is_kick:
            mode = kernels.KICK_LEFT if active.motion is Motion.KICK_LEFT else kernels.KICK_RIGHT
            return mode, now_s - active.start_time_s
        if any(abs(v) > 1e-9 for v in active.real_velocity) or active.motion is Motion.WALK:
            return kernels.WALKING, active.gait_time(now_s)
        return kernels.STANDING, 0.0

    def _drive_joints(self, mode: int, mode_s: float, duration_s: float, dt_s: float, kick_speed: float = 1.0) -> None:
        """Move each joint's setpoint toward its target (the limbs' of motion ``mode`` at ``mode_s``, the head's
        goals) at the joint's speed; send if changed. A robot whose setpoints all reached the standing targets
        and these head goals is left as it is (nothing would change)."""
        head_goals = (self.head_yaw_target, self.head_pitch_target)
        standing = mode == kernels.STANDING
        if standing and self._motors_set and self._standing_at == head_goals:
            return
        cfg = self.config
        kicking = self.active is not None and self.active.motion.is_kick
        limb_step = (cfg.kick_joint_speed_radps * kick_speed if kicking else cfg.joint_speed_max_radps) * dt_s
        changed, reached = kernels.drive_joints(mode, mode_s, duration_s, *head_goals, limb_step,
                                                HEAD_SPEED_RADPS * dt_s, self.joint_setpoints, self._setpoints_known)
        self._setpoints_known = True
        if changed or not self._motors_set:
            pb.setJointMotorControlArray(
                self.body,
                _ACTUATED_INDICES,
                pb.POSITION_CONTROL,
                targetPositions=self.joint_setpoints.tolist(),
                forces=[cfg.joint_torque_max_nm] * len(ACTUATED_JOINTS),
                positionGains=_POSITION_GAINS,
                physicsClientId=self.client,
            )
            self._motors_set = True
        self._standing_at = head_goals if standing and reached else None

    def _play_stand_up(self, active: _ActiveMotion, now_s: float) -> None:
        """The matching stand-up moves the torso kinematically upright, then holds it there.

        A stand-up from the wrong side does nothing for a fallen robot; played by a robot
        that stands, it only holds the stance (neither reaches this method).
        """
        (x0, y0, z0), q0 = active.stand_up_from
        s = min(1.0, (now_s - active.start_time_s) / (active.duration_s * self.config.stand_up_rise_fraction))
        m = pb.getMatrixFromQuaternion(q0)
        heading = torso_heading(m) if abs(m[6]) < 0.9 else _lying_heading(m)
        q1 = pb.getQuaternionFromEuler((0.0, 0.0, heading))
        q = _slerp(q0, q1, s)
        z = z0 + (TORSO_CENTER_HEIGHT_M + 0.005 - z0) * s
        pb.resetBasePositionAndOrientation(self.body, (x0, y0, z), q, physicsClientId=self.client)
        pb.resetBaseVelocity(self.body, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), physicsClientId=self.client)
        if s >= 1.0:
            self.fall_side = FallSide.NONE

    def _finish(self, now_s: float, completed: bool, reanchor: bool = True) -> None:
        active = self.active
        assert active is not None
        self.active = None
        elapsed = max(0.0, now_s - active.start_time_s)
        played = elapsed if math.isinf(active.duration_s) else min(elapsed, active.duration_s)
        if completed and active.motion is not Motion.WALK:
            nominal = MOTION_SPECS[active.motion].nominal
        else:
            nominal = _integrate_body_velocity(*active.nominal_velocity, played)
        self.sequence += 1
        self.last_finished = FinishedMotion(active.motion, nominal, completed, now_s, self.sequence)
        if reanchor:
            self._anchor()

    def _anchor(self) -> None:
        position, orientation = pb.getBasePositionAndOrientation(self.body, physicsClientId=self.client)
        m = pb.getMatrixFromQuaternion(orientation)
        self.ref = (position[0], position[1], torso_heading(m))


HEAD_SPEED_RADPS = math.radians(240.0)
JOINT_POSITION_GAIN = 1.0
_ACTUATED_INDICES = [int(j) for j in ACTUATED_JOINTS]
_POSITION_GAINS = [JOINT_POSITION_GAIN] * len(ACTUATED_JOINTS)


def control_gains(config: BalanceConfig) -> np.ndarray:
    """The gains and limits :func:`world.locomotion_kernels.control` takes, from ``config`` (read-only)."""
    gains = np.array([
        config.reanchor_position_m, config.reanchor_heading_rad, TOTAL_MASS_KG / config.drive_time_constant_s,
        config.position_gain_per_s, config.drive_force_max_n, config.yaw_inertia_kgm2 / config.drive_time_constant_s,
        config.heading_gain_per_s, config.yaw_torque_max_nm, config.upright_kp, config.upright_kd,
        config.upright_torque_max_nm,
    ], np.float64)
    gains.flags.writeable = False
    return gains


def _lying_heading(m: tuple[float, ...]) -> float:
    """Field heading (rad) a lying robot faces once up: on its front, toward its head (it pushes
    itself up over its hands); on its back, toward its feet (it sits up, then rises)."""
    toward_head = math.atan2(m[5], m[2])  # the torso's z axis, along the ground
    on_back = m[6] > 0.0  # the torso's x axis (its front) points up
    return math.remainder(toward_head + math.pi, math.tau) if on_back else toward_head


def torso_heading(m: tuple[float, ...]) -> float:
    """Field heading (rad) of the torso's x axis, from a row-major torso->world rotation."""
    return math.atan2(m[3], m[0])


def _integrate_body_velocity(vx: float, vy: float, omega: float, duration_s: float) -> Displacement:
    """Displacement after moving with constant body-frame velocity for ``duration_s``."""
    turn = omega * duration_s
    if abs(turn) < 1e-9:
        return Displacement(vx * duration_s, vy * duration_s, turn)
    s, c = math.sin(turn), math.cos(turn)
    forward = (vx * s - vy * (1.0 - c)) / omega
    left = (vx * (1.0 - c) + vy * s) / omega
    return Displacement(forward, left, turn)


def _slerp(q0, q1, s: float):
    a, b = np.asarray(q0, float), np.asarray(q1, float)
    dot = float(a @ b)
    if dot < 0.0:
        b, dot = -b, -dot
    if dot > 0.9995:
        q = a + s * (b - a)
    else:
        theta = math.acos(dot)
        q = (math.sin((1 - s) * theta) * a + math.sin(s * theta) * b) / math.sin(theta)
    return tuple(q / np.linalg.norm(q))


def head_limits_check(yaw_rad: float, pitch_rad: float) -> str | None:
    """Return why (yaw, pitch) is outside the head limits, or None if it is inside."""
    for name, value, (lo, hi) in (
        ("head_yaw", yaw_rad, NAO_HEAD.yaw_limits_rad),
        ("head_pitch", pitch_rad, NAO_HEAD.pitch_limits_rad),
    ):
        if not (math.isfinite(value) and lo <= value <= hi):
            return f"{name}={value!r} rad outside [{lo:.4f}, {hi:.4f}]"
    return None
