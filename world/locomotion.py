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
- joint position targets from :mod:`world.gaits`, rate-limited.

The soles have no friction (see :mod:`world.robot_model`); the drive force is the only
thing that holds a standing robot in place, up to ``drive_force_max_n``. Plain floats are
used on purpose: this runs 8 robots x 10 substeps per control step.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass, field

import numpy as np
import pybullet as pb

from world import gaits
from world.camera_model import NAO_HEAD, CameraPosition
from world.field import normalize_angle
from world.motions import MOTION_SPECS, Displacement, Motion, MotionNoise
from world.robot_model import ACTUATED_JOINTS, TORSO_CENTER_HEIGHT_M, TOTAL_MASS_KG, Joint


# Every actuated joint, with the index of its head target (yaw 0, pitch 1) or None for a limb's.
_JOINT_SLOTS = tuple((joint, {Joint.HEAD_YAW: 0, Joint.HEAD_PITCH: 1}.get(joint)) for joint in ACTUATED_JOINTS)


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
    ref: list[float] = field(default_factory=lambda: [0.0, 0.0, 0.0])  # x, y, heading
    joint_setpoints: dict[Joint, float] = field(default_factory=dict)
    _yaw_torque: float = 0.0
    _motors_set: bool = False  # motor targets persist in pybullet until changed
    _standing_at: tuple[float, float] | None = None  # head goals at which every setpoint reached STANDING

    # ---- commands -------------------------------------------------------------------

    def start(self, motion: Motion, now_s: float, rng: np.random.Generator, walk=(0.0, 0.0, 0.0)) -> bool:
        """Start ``motion`` (interrupting another); return False if refused (fallen).

        The motion already playing, commanded again, continues. A walk commanded again with
        another velocity ends the walk so far (its nominal displacement is reported) and
        goes on at the new velocity without breaking step: same gait phase, same reference.
        """
        if self.fallen and not motion.is_stand_up:
            self.refused = motion
            return False
        gait_start = None
        if self.active is not None:
            if self.active.motion is motion:
                if motion is not Motion.WALK or tuple(walk) == self.active.nominal_velocity:
                    return True
                gait_start = self.active.start_time_s if self.active.gait_start_s is None else self.active.gait_start_s
            self._finish(now_s, completed=False, reanchor=gait_start is None)
        self.refused = None
        if motion is Motion.WALK:
            real = self.noise.walk_velocity(*walk, rng)
            self.active = _ActiveMotion(motion, now_s, math.inf, tuple(walk), real, gait_start_s=gait_start)
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
        self.head_yaw_target, self.head_pitch_target = yaw_rad, pitch_rad

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
        self.joint_setpoints = {}
        self._motors_set = False
        self._standing_at = None
        self._anchor()

    # ---- control --------------------------------------------------------------------

    def substep(self, now_s: float, dt_s: float) -> None:
        """Apply forces and joint targets for one physics substep starting at ``now_s``."""
        position, orientation = pb.getBasePositionAndOrientation(self.body, physicsClientId=self.client)
        linear, angular = pb.getBaseVelocity(self.body, physicsClientId=self.client)
        m = pb.getMatrixFromQuaternion(orientation)  # row-major 3x3
        tilt = math.acos(max(-1.0, min(1.0, m[8])))
        heading = torso_heading(m)
        active = self.active
        if active is not None and now_s - active.start_time_s >= active.duration_s:
            self._finish(now_s, completed=True)
            active = None
        if active is not None and active.motion.is_stand_up and active.stand_up_works:
            self._play_stand_up(active, now_s)
            self._drive_joints(gaits.stand_up_targets(now_s - active.start_time_s, active.duration_s), dt_s)
            return
        if not self.fallen and tilt > self.config.fall_tilt_rad:
            self.fall_side = FallSide.FRONT if m[6] < 0.0 else FallSide.BACK
            if active is not None:
                self._finish(now_s, completed=False)
                active = None
        if self.fallen:
            self._drive_joints(gaits.STANDING, dt_s)
            return
        vx, vy, omega = active.real_velocity if active is not None else (0.0, 0.0, 0.0)
        if active is not None and active.motion.is_kick and now_s - active.start_time_s >= gaits.KICK_SWING_START_S:
            omega = 0.0
        self._track(position, linear, angular, heading, (vx, vy, omega), dt_s)
        self._balance(m, angular)
        self._drive_joints(self._joint_targets(active, now_s), dt_s, kick_speed=active.kick_speed if active else 1.0)

    def _track(self, position, linear, angular, heading, velocity, dt_s) -> None:
        cfg = self.config
        vx, vy, omega = velocity
        ref = self.ref
        c, s = math.cos(ref[2]), math.sin(ref[2])
        vwx, vwy = c * vx - s * vy, s * vx + c * vy
        ref[0] += vwx * dt_s
        ref[1] += vwy * dt_s
        ref[2] = normalize_angle(ref[2] + omega * dt_s)
        ex, ey = ref[0] - position[0], ref[1] - position[1]
        if math.hypot(ex, ey) > cfg.reanchor_position_m:
            ref[0], ref[1], ex, ey = position[0], position[1], 0.0, 0.0
        eh = normalize_angle(ref[2] - heading)
        if abs(eh) > cfg.reanchor_heading_rad:
            ref[2], eh = heading, 0.0
        gain = TOTAL_MASS_KG / cfg.drive_time_constant_s
        fx = gain * (vwx + cfg.position_gain_per_s * ex - linear[0])
        fy = gain * (vwy + cfg.position_gain_per_s * ey - linear[1])
        norm = math.hypot(fx, fy)
        if norm > cfg.drive_force_max_n:
            fx, fy = fx * cfg.drive_force_max_n / norm, fy * cfg.drive_force_max_n / norm
        # Applied at the ground below the torso, where feet would grip: a push at torso
        # height then tips the robot as it would a real one.
        grip = (position[0], position[1], 0.0)
        pb.applyExternalForce(self.body, -1, (fx, fy, 0.0), grip, pb.WORLD_FRAME, physicsClientId=self.client)
        tz = cfg.yaw_inertia_kgm2 / cfg.drive_time_constant_s * (omega + cfg.heading_gain_per_s * eh - angular[2])
        self._yaw_torque = max(-cfg.yaw_torque_max_nm, min(cfg.yaw_torque_max_nm, tz))

    def _balance(self, m, angular) -> None:
        """Capped PD torque turning the torso's z axis back to vertical, plus the yaw torque."""
        cfg = self.config
        zx, zy, zz = m[2], m[5], m[8]  # torso z axis in the world frame
        sin_tilt = math.hypot(zx, zy)
        tilt = math.atan2(sin_tilt, zz)
        ax, ay = (zy / sin_tilt, -zx / sin_tilt) if sin_tilt > 1e-9 else (0.0, 0.0)
        tx = cfg.upright_kp * tilt * ax - cfg.upright_kd * angular[0]
        ty = cfg.upright_kp * tilt * ay - cfg.upright_kd * angular[1]
        norm = math.hypot(tx, ty)
        if norm > cfg.upright_torque_max_nm:
            tx, ty = tx * cfg.upright_torque_max_nm / norm, ty * cfg.upright_torque_max_nm / norm
        pb.applyExternalTorque(self.body, -1, (tx, ty, self._yaw_torque), pb.WORLD_FRAME, physicsClientId=self.client)

    def _joint_targets(self, active: _ActiveMotion | None, now_s: float) -> gaits.JointTargets:
        if active is None or active.motion is Motion.STAND:
            return gaits.STANDING
        if active.motion.is_kick:
            return gaits.kick_targets(active.motion, now_s - active.start_time_s)
        if any(abs(v) > 1e-9 for v in active.real_velocity) or active.motion is Motion.WALK:
            return gaits.walking_targets(active.gait_time(now_s))
        return gaits.STANDING

    def _drive_joints(self, targets: gaits.JointTargets, dt_s: float, kick_speed: float = 1.0) -> None:
        """Move each joint's setpoint toward its target at the joint's speed; send if changed. A robot whose
        setpoints all reached the standing targets and these head goals is left as it is (nothing would
        change)."""
        head_goals = (self.head_yaw_target, self.head_pitch_target)
        standing = targets is gaits.STANDING
        if standing and self._motors_set and self._standing_at == head_goals:
            return
        cfg = self.config
        kicking = self.active is not None and self.active.motion.is_kick
        limb_step = (cfg.kick_joint_speed_radps * kick_speed if kicking else cfg.joint_speed_max_radps) * dt_s
        head_step = HEAD_SPEED_RADPS * dt_s
        setpoints = self.joint_setpoints
        changed = False
        reached = True
        for joint, head in _JOINT_SLOTS:
            if head is None:
                goal, step = targets.get(joint, 0.0), limb_step
            else:
                goal, step = head_goals[head], head_step
            before = setpoints.get(joint)
            current = goal if before is None else before
            if current != goal:
                current = goal if abs(goal - current) <= step else current + math.copysign(step, goal - current)
            if before != current:
                setpoints[joint] = current
                changed = True
            reached = reached and current == goal
        if changed or not self._motors_set:
            pb.setJointMotorControlArray(
                self.body,
                _ACTUATED_INDICES,
                pb.POSITION_CONTROL,
                targetPositions=[setpoints[j] for j in ACTUATED_JOINTS],
                forces=[cfg.joint_torque_max_nm] * len(ACTUATED_JOINTS),
                positionGains=[JOINT_POSITION_GAIN] * len(ACTUATED_JOINTS),
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
        self.ref = [position[0], position[1], torso_heading(m)]
        self._yaw_torque = 0.0


HEAD_SPEED_RADPS = math.radians(240.0)
JOINT_POSITION_GAIN = 1.0
_ACTUATED_INDICES = [int(j) for j in ACTUATED_JOINTS]


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
