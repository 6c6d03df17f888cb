"""The locomotion controller's arithmetic per physics substep, compiled.

:class:`world.locomotion.LocomotionController` decides what a robot does (motions starting and
ending, falls, stand-ups); :func:`control` computes what it applies in the substep: the drive
force and yaw torque that make the torso follow its reference pose, the balance torque, and the
joint setpoints moved toward the motion's targets. Every operation is the one the Python
controller made, in the same order, with the same C library functions, so a match plays to the
bit as it did: :func:`py_hypot` is the two-argument ``math.hypot`` of CPython 3.11 (its
``vector_norm``, not the C library's ``hypot``; later versions compute it another way),
:func:`py_max` and :func:`py_min` are Python's ``max`` and ``min`` of two floats.
:func:`joint_targets` holds the motions' targets as functions of time (their constants are in
:mod:`world.gaits`).

Joint slots are :data:`world.robot_model.ACTUATED_JOINTS` in order: head yaw, head pitch, left
and right shoulder, left hip, knee, ankle, right hip, knee, ankle.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from world import gaits
from world.robot_model import ACTUATED_JOINTS, Joint

# The motions' joint targets (mode for :func:`joint_targets`).
STANDING, WALKING, KICK_LEFT, KICK_RIGHT, STAND_UP = 0, 1, 2, 3, 4
SLOTS = len(ACTUATED_JOINTS)
_HEAD_YAW, _HEAD_PITCH = ACTUATED_JOINTS.index(Joint.HEAD_YAW), ACTUATED_JOINTS.index(Joint.HEAD_PITCH)
_HEAD_SLOTS = 2  # yaw, pitch first: driven toward the head goals, not the motion's targets
_L_SHOULDER, _R_SHOULDER = ACTUATED_JOINTS.index(Joint.L_SHOULDER), ACTUATED_JOINTS.index(Joint.R_SHOULDER)
_L_HIP, _R_HIP = ACTUATED_JOINTS.index(Joint.L_HIP), ACTUATED_JOINTS.index(Joint.R_HIP)  # knee and ankle follow
assert (_HEAD_YAW, _HEAD_PITCH) == (0, 1) and all(
    ACTUATED_JOINTS[hip + 1] == knee and ACTUATED_JOINTS[hip + 2] == ankle
    for hip, knee, ankle in ((_L_HIP, Joint.L_KNEE, Joint.L_ANKLE), (_R_HIP, Joint.R_KNEE, Joint.R_ANKLE)))
_STANDING = np.array([gaits.STANDING.get(joint, 0.0) for joint in ACTUATED_JOINTS])
_KICK_KEYS = np.array(gaits.KICK_KEYS, np.float64)
_STEP_PERIOD_S = gaits.STEP_PERIOD_S
_STEP_LIFT_RAD = gaits.STEP_LIFT_RAD
_REST = gaits.SHOULDER_REST_RAD
_T27 = 134217729.0  # 2**27 + 1, Dekker's split
_TWO_PI = 2.0 * math.pi


@njit(cache=True)
def py_max(a, b):
    """Python's ``max(a, b)``: ``b`` only when it is greater."""
    return b if b > a else a


@njit(cache=True)
def py_min(a, b):
    """Python's ``min(a, b)``: ``b`` only when it is smaller."""
    return b if b < a else a


@njit(cache=True)
def py_hypot(x, y):
    """CPython 3.11's ``math.hypot(x, y)`` (``vector_norm`` of two coordinates): exact squares by Dekker's
    split, compensated sums and one correction of the square root."""
    a, b = abs(x), abs(y)
    if math.isinf(a) or math.isinf(b):
        return math.inf
    if math.isnan(a) or math.isnan(b):
        return math.nan
    largest = py_max(a, b)
    if largest == 0.0:
        return largest
    exponent = math.frexp(largest)[1]
    if exponent < -1023:
        return _small_hypot(a, b, largest)
    scale = math.ldexp(1.0, -exponent)
    csum, frac1, frac2, frac3 = 1.0, 0.0, 0.0, 0.0
    for value in (a, b):
        x = value * scale
        t = x * _T27
        hi = t - (t - x)
        lo = x - hi
        x = hi * hi
        old = csum
        csum += x
        frac1 += (old - csum) + x
        x = 2.0 * hi * lo
        old = csum
        csum += x
        frac2 += (old - csum) + x
        frac3 += lo * lo
    h = math.sqrt(csum - 1.0 + (frac1 + frac2 + frac3))
    t = h * _T27
    hi = t - (t - h)
    lo = h - hi
    x = -hi * hi
    old = csum
    csum += x
    frac1 += (old - csum) + x
    x = -2.0 * hi * lo
    old = csum
    csum += x
    frac2 += (old - csum) + x
    x = -lo * lo
    old = csum
    csum += x
    frac3 += (old - csum) + x
    x = csum - 1.0 + (frac1 + frac2 + frac3)
    return (h + x / (2.0 * h)) / scale


@njit(cache=True)
def _small_hypot(a, b, largest):
    """``vector_norm``'s way for subnormal coordinates, where the scale would overflow: divide by the largest."""
    csum, frac1 = 1.0, 0.0
    for value in (a, b):
        x = value / largest
        x = x * x
        old = csum
        csum += x
        frac1 += (old - csum) + x
    return largest * math.sqrt(csum - 1.0 + frac1)


@njit(cache=True)
def normalize_angle(angle_rad):
    """:func:`world.field.normalize_angle`: ``angle_rad`` wrapped into (-pi, pi]. The C library's ``fmod``
    is exact, and within one turn it is the angle itself."""
    wrapped = angle_rad if abs(angle_rad) < _TWO_PI else np.fmod(angle_rad, _TWO_PI)
    if wrapped <= -math.pi:
        wrapped += _TWO_PI
    elif wrapped > math.pi:
        wrapped -= _TWO_PI
    return wrapped


@njit(cache=True)
def joint_targets(mode, t_s, duration_s, out):
    """The limbs' targets (rad) of motion ``mode``, ``t_s`` into it, into their slots of ``out`` (the head's are
    left alone); ``duration_s``: the stand-up's duration.

    ``STANDING``: :data:`world.gaits.STANDING`. ``WALKING``: alternating steps of
    :data:`~world.gaits.STEP_PERIOD_S`, the left foot rising in the first half-period and the right in the
    second, lifted by flexing hip and knee with the sole level, the arms swinging. ``KICK_LEFT`` and
    ``KICK_RIGHT``: the kicking leg's keyframes (:data:`~world.gaits.KICK_KEYS`) linearly interpolated, the
    other arm swinging against it. ``STAND_UP``: arms push and legs tuck, then straighten."""
    for k in range(_HEAD_SLOTS, SLOTS):
        out[k] = _STANDING[k]
    if mode == WALKING:
        phase = (t_s % _STEP_PERIOD_S) / _STEP_PERIOD_S
        hip = _L_HIP if phase < 0.5 else _R_HIP
        amount = _STEP_LIFT_RAD * math.sin(math.pi * ((phase * 2) % 1.0))
        out[hip], out[hip + 1], out[hip + 2] = -amount, 2 * amount, -amount
        swing = 0.25 * math.sin(2 * math.pi * phase)
        out[_L_SHOULDER] = _REST + swing
        out[_R_SHOULDER] = _REST - swing
    elif mode == KICK_LEFT or mode == KICK_RIGHT:
        hip_angle, knee_angle, ankle_angle = _kick_keyframe(t_s)
        hip = _L_HIP if mode == KICK_LEFT else _R_HIP
        out[hip], out[hip + 1], out[hip + 2] = hip_angle, knee_angle, ankle_angle
        out[_R_SHOULDER if mode == KICK_LEFT else _L_SHOULDER] = _REST - 0.6 * (hip_angle - 0.0)
    elif mode == STAND_UP:
        s = py_min(py_max(t_s / duration_s, 0.0), 1.0)
        tuck = math.sin(math.pi * s)
        for hip in (_L_HIP, _R_HIP):
            out[hip], out[hip + 1], out[hip + 2] = -0.8 * tuck, 1.4 * tuck, -0.6 * tuck
        out[_L_SHOULDER] = _REST - 1.2 * tuck
        out[_R_SHOULDER] = _REST - 1.2 * tuck


@njit(cache=True)
def _kick_keyframe(t_s):
    """The kicking leg's (hip, knee, ankle) at ``t_s``, linearly interpolated between the keyframes."""
    keys = _KICK_KEYS
    if t_s <= keys[0, 0]:
        return keys[0, 1], keys[0, 2], keys[0, 3]
    for i in range(keys.shape[0] - 1):
        t0, t1 = keys[i, 0], keys[i + 1, 0]
        if t_s <= t1:
            w = (t_s - t0) / (t1 - t0)
            return (keys[i, 1] + w * (keys[i + 1, 1] - keys[i, 1]), keys[i, 2] + w * (keys[i + 1, 2] - keys[i, 2]),
                    keys[i, 3] + w * (keys[i + 1, 3] - keys[i, 3]))
    last = keys.shape[0] - 1
    return keys[last, 1], keys[last, 2], keys[last, 3]


@njit(cache=True)
def drive_joints(mode, mode_s, duration_s, head_yaw, head_pitch, limb_step, head_step, setpoints, known):
    """Move each setpoint (rad) toward its goal by at most its step in place, as the Python controller did:
    the limbs' toward the targets of motion ``mode`` at ``mode_s`` (:func:`joint_targets`), the head's toward
    the head goals. ``known``: whether the setpoints were ever set (else each starts at its goal). Returns
    (whether any setpoint changed, whether all reached their goal)."""
    goals = np.empty(SLOTS)
    joint_targets(mode, mode_s, duration_s, goals)
    goals[_HEAD_YAW], goals[_HEAD_PITCH] = head_yaw, head_pitch
    changed = not known
    reached = True
    for k in range(SLOTS):
        goal = goals[k]
        step = head_step if k < _HEAD_SLOTS else limb_step
        before = setpoints[k]
        current = before if known else goal
        if current != goal:
            current = goal if abs(goal - current) <= step else current + math.copysign(step, goal - current)
        if known and before != current:
            changed = True
        setpoints[k] = current
        reached = reached and current == goal
    return changed, reached


@njit(cache=True)
def control(px, py, linear_x, linear_y, angular_x, angular_y, angular_z, heading, zx, zy, zz, vx, vy, omega, dt_s,
            ref_x, ref_y, ref_heading, gains):
    """The drive force (N, world frame, applied at the ground below the torso), the balance and yaw torque
    (N m, world frame) and the new reference pose of one substep: ``LocomotionController._track`` and
    ``_balance``. ``(px, py)``: the torso's position (m); ``linear``/``angular``: its velocities (world frame);
    ``heading``: its field heading (rad); ``(zx, zy, zz)``: its z axis in the world; ``(vx, vy, omega)``: the
    motion's real velocity (torso frame); ``gains``: :func:`control_gains`.

    Returns ``(fx, fy, tx, ty, tz, ref_x, ref_y, ref_heading)``."""
    (reanchor_position, reanchor_heading, drive_gain, position_gain, force_max, yaw_gain, heading_gain, yaw_max,
     upright_kp, upright_kd, upright_max) = (gains[0], gains[1], gains[2], gains[3], gains[4], gains[5], gains[6],
                                             gains[7], gains[8], gains[9], gains[10])
    c, s = math.cos(ref_heading), math.sin(ref_heading)
    vwx, vwy = c * vx - s * vy, s * vx + c * vy
    ref_x += vwx * dt_s
    ref_y += vwy * dt_s
    ref_heading = normalize_angle(ref_heading + omega * dt_s)
    ex, ey = ref_x - px, ref_y - py
    if py_hypot(ex, ey) > reanchor_position:
        ref_x, ref_y, ex, ey = px, py, 0.0, 0.0
    eh = normalize_angle(ref_heading - heading)
    if abs(eh) > reanchor_heading:
        ref_heading, eh = heading, 0.0
    fx = drive_gain * (vwx + position_gain * ex - linear_x)
    fy = drive_gain * (vwy + position_gain * ey - linear_y)
    norm = py_hypot(fx, fy)
    if norm > force_max:
        fx, fy = fx * force_max / norm, fy * force_max / norm
    tz = yaw_gain * (omega + heading_gain * eh - angular_z)
    tz = py_max(-yaw_max, py_min(yaw_max, tz))
    sin_tilt = py_hypot(zx, zy)
    tilt = math.atan2(sin_tilt, zz)
    if sin_tilt > 1e-9:
        ax, ay = zy / sin_tilt, -zx / sin_tilt
    else:
        ax, ay = 0.0, 0.0
    tx = upright_kp * tilt * ax - upright_kd * angular_x
    ty = upright_kp * tilt * ay - upright_kd * angular_y
    norm = py_hypot(tx, ty)
    if norm > upright_max:
        tx, ty = tx * upright_max / norm, ty * upright_max / norm
    return fx, fy, tx, ty, tz, ref_x, ref_y, ref_heading
