"""The joint targets of the predefined motions (radians, Nao signs): the standing pose, the
step's period and lift, the kick's keyframes.

The targets as functions of time are compiled in
:func:`world.locomotion_kernels.joint_targets`: alternating steps, the left foot rising in the
first half-period and the right in the second, each lifted by flexing hip and knee with the sole
kept level and the arms swinging; the kick's keyframes linearly interpolated, the other arm
swinging against the kicking leg; the stand-up's arms pushing and legs tucking, then
straightening. Pitch joints are positive when the limb tips backward at the hip and when the knee
bends; see :mod:`world.robot_model`.
"""

from __future__ import annotations

from world.robot_model import Joint

STEP_PERIOD_S = 0.5
STEP_LIFT_RAD = 0.4
SHOULDER_REST_RAD = 0.15  # the arms' pitch standing, about which they swing

JointTargets = dict[Joint, float]

STANDING: JointTargets = {
    Joint.L_SHOULDER: SHOULDER_REST_RAD,
    Joint.R_SHOULDER: SHOULDER_REST_RAD,
    Joint.L_HIP: 0.0,
    Joint.L_KNEE: 0.0,
    Joint.L_ANKLE: 0.0,
    Joint.R_HIP: 0.0,
    Joint.R_KNEE: 0.0,
    Joint.R_ANKLE: 0.0,
}


# (time s, hip, knee, ankle) of the kicking leg; the swing from 0.45 to 0.57 s is fast. Its
# follow-through stops at hip -0.45 rad: swung on to -0.75, the leg pitched the robot back and
# lifted the foot over a ball 0.13-0.17 m ahead, and it came down in front of the ball and
# squeezed it back between the feet (28 of 360 kicks right after a walk, ball 0.13-0.19 m ahead).
KICK_KEYS: tuple[tuple[float, float, float, float], ...] = (
    (0.0, 0.0, 0.0, 0.0),
    (0.35, 0.45, 0.9, -0.45),
    (0.45, 0.45, 0.9, -0.45),
    (0.57, -0.45, 0.1, 0.1),
    (0.95, -0.45, 0.1, 0.1),
    (1.45, 0.0, 0.0, 0.0),
)
KICK_SWING_START_S = 0.45
