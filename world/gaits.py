"""Joint targets of the predefined motions as functions of time (radians, Nao signs).

Pure Python. Pitch joints are positive when the limb tips backward at the hip and when
the knee bends; see :mod:`world.robot_model`.
"""

from __future__ import annotations

import math

from world.motions import Motion
from world.robot_model import Joint

STEP_PERIOD_S = 0.5
STEP_LIFT_RAD = 0.4

JointTargets = dict[Joint, float]

STANDING: JointTargets = {
    Joint.L_SHOULDER: 0.15,
    Joint.R_SHOULDER: 0.15,
    Joint.L_HIP: 0.0,
    Joint.L_KNEE: 0.0,
    Joint.L_ANKLE: 0.0,
    Joint.R_HIP: 0.0,
    Joint.R_KNEE: 0.0,
    Joint.R_ANKLE: 0.0,
}


_LEGS = {side: (Joint[f"{side}_HIP"], Joint[f"{side}_KNEE"], Joint[f"{side}_ANKLE"]) for side in ("L", "R")}


def _lift(side: str, amount: float) -> JointTargets:
    """Raise one foot by flexing hip and knee while keeping the sole level."""
    hip, knee, ankle = _LEGS[side]
    return {hip: -amount, knee: 2 * amount, ankle: -amount}


def walking_targets(t_s: float) -> JointTargets:
    """Alternating steps: the left foot rises in the first half-period, the right in the second."""
    targets = dict(STANDING)
    phase = (t_s % STEP_PERIOD_S) / STEP_PERIOD_S
    side = "L" if phase < 0.5 else "R"
    amount = STEP_LIFT_RAD * math.sin(math.pi * ((phase * 2) % 1.0))
    targets.update(_lift(side, amount))
    swing = 0.25 * math.sin(2 * math.pi * phase)
    targets[Joint.L_SHOULDER] = 0.15 + swing
    targets[Joint.R_SHOULDER] = 0.15 - swing
    return targets


# (time s, hip, knee, ankle) of the kicking leg; the swing from 0.45 to 0.57 s is fast. Its
# follow-through stops at hip -0.45 rad: swung on to -0.75, the leg pitched the robot back and
# lifted the foot over a ball 0.13-0.17 m ahead, and it came down in front of the ball and
# squeezed it back between the feet (28 of 360 kicks right after a walk, ball 0.13-0.19 m ahead).
_KICK_KEYS: tuple[tuple[float, float, float, float], ...] = (
    (0.0, 0.0, 0.0, 0.0),
    (0.35, 0.45, 0.9, -0.45),
    (0.45, 0.45, 0.9, -0.45),
    (0.57, -0.45, 0.1, 0.1),
    (0.95, -0.45, 0.1, 0.1),
    (1.45, 0.0, 0.0, 0.0),
)
KICK_SWING_START_S = 0.45


def kick_targets(motion: Motion, t_s: float) -> JointTargets:
    """Keyframes of a kick with the left or right foot, linearly interpolated."""
    side = "L" if motion is Motion.KICK_LEFT else "R"
    hip, knee, ankle = _interpolate(_KICK_KEYS, t_s)
    targets = dict(STANDING)
    targets.update({Joint[f"{side}_HIP"]: hip, Joint[f"{side}_KNEE"]: knee, Joint[f"{side}_ANKLE"]: ankle})
    arm = Joint.R_SHOULDER if side == "L" else Joint.L_SHOULDER
    targets[arm] = 0.15 - 0.6 * (hip - 0.0)
    return targets


def stand_up_targets(t_s: float, duration_s: float) -> JointTargets:
    """Arms push and legs tuck, then straighten, over the stand-up motion."""
    s = min(max(t_s / duration_s, 0.0), 1.0)
    tuck = math.sin(math.pi * s)
    targets = dict(STANDING)
    for side in ("L", "R"):
        targets[Joint[f"{side}_SHOULDER"]] = 0.15 - 1.2 * tuck
        targets[Joint[f"{side}_HIP"]] = -0.8 * tuck
        targets[Joint[f"{side}_KNEE"]] = 1.4 * tuck
        targets[Joint[f"{side}_ANKLE"]] = -0.6 * tuck
    return targets


def _interpolate(keys, t_s: float) -> tuple[float, ...]:
    if t_s <= keys[0][0]:
        return keys[0][1:]
    for (t0, *a), (t1, *b) in zip(keys, keys[1:]):
        if t_s <= t1:
            w = (t_s - t0) / (t1 - t0)
            return tuple(x + w * (y - x) for x, y in zip(a, b))
    return keys[-1][1:]
