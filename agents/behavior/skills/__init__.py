"""Skills: the small motion units every player is built from (stand up, turn, approach,
align, kick, orbit, keep the goal, look, sweep the head).

Each maps what the robot believes about the ball, relative to itself, to a motion and a walk
command (vx m/s, vy m/s, omega rad/s; torso frame: x forward, y left, CCW positive) or head
angles (yaw CCW positive, pitch positive looking down). One control step is
:data:`CONTROL_STEP_S`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

from match.protocol import WALK_HIGH, WALK_LOW, Motion, Pose2D
from world.camera_model import NAO_HEAD, CameraPosition
from world.field import FIELD


class RelativeBall(Protocol):
    """The ball relative to the robot (a percept or a filtered estimate): torso frame, m and rad."""

    @property
    def distance_m(self) -> float: ...

    @property
    def bearing_rad(self) -> float: ...

    @property
    def left_m(self) -> float: ...


CONTROL_STEP_S = 0.04

# Head limits with a margin (walk limits: WALK_LOW, WALK_HIGH of the action space).
_HEAD_MARGIN_RAD = 1e-3
YAW_LIMITS_RAD = (NAO_HEAD.yaw_limits_rad[0] + _HEAD_MARGIN_RAD, NAO_HEAD.yaw_limits_rad[1] - _HEAD_MARGIN_RAD)
PITCH_LIMITS_RAD = (NAO_HEAD.pitch_limits_rad[0] + _HEAD_MARGIN_RAD, NAO_HEAD.pitch_limits_rad[1] - _HEAD_MARGIN_RAD)

# Head scanning (ball unknown, or not playing).
SCAN_PITCH_RAD = 0.3
# Every other sweep looks near the feet with the bottom camera (ground about 0.06-0.42 m
# ahead): a ball right in front of the robot (a kick-off, a penalty) is seen there.
NEAR_SCAN_PITCH_RAD = 0.45
# The bottom camera pitched less covers the ground about 0.25-0.9 m ahead: the gap between the
# near look and the top camera's sweep (from about 0.7 m).
MID_SCAN_PITCH_RAD = 0.1
SCAN_AMPLITUDE_RAD = math.radians(100.0)
SEARCH_SCAN_RATE_RADPS = 1.5
IDLE_SCAN_RATE_RADPS = 0.5
FULL_SWEEP_REVERSALS = 2  # one end and then the other: the whole range was looked at
SEARCH_TURN_RADPS = 0.8
# A search starts with a quick look near the feet (bottom camera, +-NEAR_SWEEP_AMPLITUDE_RAD):
# a ball lost from view is most often one the robot stands next to.
NEAR_SWEEP_AMPLITUDE_RAD = math.radians(60.0)
NEAR_SWEEP_RATE_RADPS = 3.0
SEARCH_TURN_STEPS = 50  # about 90 degrees at SEARCH_TURN_RADPS
# While turning, look ahead with the bottom camera: it covers the ground 0.25-0.9 m ahead,
# which the top camera at SCAN_PITCH_RAD (from about 0.7 m) misses.
SEARCH_TURN_HEAD = (0.0, 0.1)

# Cameras.
BOTTOM_CAMERA_BELOW_M = 0.6  # the top camera cannot see the ground nearer than about 0.5 m
TOP_CAMERA_BEYOND_M = 0.8  # hysteresis

# Field player.
TURN_IN_PLACE_RAD = 0.35
TURN_GAIN_PER_S = 2.0  # omega = gain * bearing
MIN_TURN_RADPS = 0.4
APPROACH_GAIN_PER_S = 1.2  # vx = gain * (distance - APPROACH_STOP_M)
APPROACH_STOP_M = 0.12
MIN_APPROACH_MPS = 0.08
ALIGN_WITHIN_M = 0.4  # nearer than this, side-step to put the ball in front of a foot
ALIGN_GAIN_PER_S = 1.5  # vy = gain * lateral error
FOOT_OFFSET_M = 0.05  # lateral offset of a foot from the torso centre
FOOT_BAND_M = (0.025, 0.085)  # |lateral offset| of a ball in front of a foot (m)
KICK_DISTANCE_M = 0.19  # kicks are strongest with the ball 0.12-0.17 m ahead, 0.03-0.08 m to the side
KICK_SPOT_M = 0.14  # where step_to_ball puts the ball: this far ahead
KICK_HEADING_TOLERANCE_RAD = math.radians(60.0)
KICK_ROLL_M = 3.0  # a kick rolls the ball about this far ...
SIDELINE_MARGIN_M = 0.25  # ... and it must not end nearer the side line than this (or beyond it), unless it is a shot
PUSH_MPS = 0.2  # dribbling: the walk's top forward speed
ORBIT_RADPS = 0.5
ORBIT_DISTANCE_M = 0.15
ORBIT_WITHIN_M = 0.3  # a ball this near but the aim off: orbit at once (approaching first would chatter)
ORBIT_DISTANCE_GAIN_PER_S = 0.5

# Goalkeeper.
KEEPER_PLAYER = 0
LONE_SILENCE_S = 4.0  # ours: a keeper that has heard no teammate this long plays the field (a team of one)
KEEPER_REACT_DISTANCE_M = 2.5
KEEPER_KICK_DISTANCE_M = 0.25
KEEPER_KICK_BEARING_RAD = 0.5
KEEPER_SIDE_GAIN_PER_S = 1.0  # vy = gain * ball lateral offset
KEEPER_HEADING_GAIN_PER_S = 1.0
KEEPER_MAX_TURN_RADPS = 0.5

STILL = (0.0, 0.0, 0.0)


def plays_alone(player: int, silent_for_s: float) -> bool:
    """The lone-goalkeeper rule of the built-in policies: player 0 that has heard no teammate for
    :data:`LONE_SILENCE_S` (``silent_for_s``: since the last one it heard, or since its reset) plays
    alone, a team of one or with every teammate silent: it plays the field, since a team of one that
    only keeps its goal can never score."""
    return player == KEEPER_PLAYER and silent_for_s >= LONE_SILENCE_S


def stand_up_for(accelerometer_x_mps2: float) -> Motion:
    """Lying on the back reads about +9.81 m/s^2 on torso x, on the front about -9.81."""
    return Motion.STAND_UP_FROM_BACK if accelerometer_x_mps2 > 0.0 else Motion.STAND_UP_FROM_FRONT


def walk_command(vx: float, vy: float, omega: float) -> tuple[float, float, float]:
    """(vx, vy, omega) clipped to the walk limits."""
    return tuple(float(min(max(v, lo), hi)) for v, lo, hi in zip((vx, vy, omega), WALK_LOW, WALK_HIGH))


def clip_head(yaw_rad: float, pitch_rad: float) -> tuple[float, float]:
    return (
        min(max(yaw_rad, YAW_LIMITS_RAD[0]), YAW_LIMITS_RAD[1]),
        min(max(pitch_rad, PITCH_LIMITS_RAD[0]), PITCH_LIMITS_RAD[1]),
    )


def look_at(ball: RelativeBall, camera: CameraPosition) -> tuple[float, float]:
    """Head (yaw, pitch) that centres the ball in ``camera`` (approximately; rad)."""
    mount = NAO_HEAD.mount(camera)
    height = NAO_HEAD.neck_height_m + mount.up_m - FIELD.ball_radius
    ahead = max(ball.distance_m - mount.forward_m, 0.01)
    return clip_head(ball.bearing_rad, math.atan2(height, ahead) - mount.pitch_rad)


def turn_toward(bearing_rad: float) -> tuple[float, float, float]:
    """Turn in place toward a bearing."""
    omega = TURN_GAIN_PER_S * bearing_rad
    return walk_command(0.0, 0.0, math.copysign(max(abs(omega), MIN_TURN_RADPS), bearing_rad))


def approach(ball: RelativeBall) -> tuple[float, float, float]:
    """Walk forward to the ball: steer toward it, then, when near, side-step it in front of a foot."""
    vx = max(APPROACH_GAIN_PER_S * (ball.distance_m - APPROACH_STOP_M), MIN_APPROACH_MPS)
    if ball.distance_m >= ALIGN_WITHIN_M:
        return walk_command(vx, 0.0, TURN_GAIN_PER_S * ball.bearing_rad)
    foot = math.copysign(FOOT_OFFSET_M, ball.left_m)
    return walk_command(vx, ALIGN_GAIN_PER_S * (ball.left_m - foot), 0.0)


def orbit(ball: RelativeBall, turn_rad: float) -> tuple[float, float, float]:
    """Side-step around the ball (vy opposite to omega) to turn by ``turn_rad`` while facing it."""
    omega = math.copysign(ORBIT_RADPS, turn_rad)
    vx = ORBIT_DISTANCE_GAIN_PER_S * (ball.distance_m - ORBIT_DISTANCE_M)
    # Keep the ball before the nearer foot, not before the torso: steering it to the centre would
    # turn the robot against the orbit while the ball lies at a foot.
    forward = max(ball.distance_m * math.cos(ball.bearing_rad), ORBIT_DISTANCE_M / 2)
    off_foot = math.atan2(ball.left_m - math.copysign(FOOT_OFFSET_M, ball.left_m), forward)
    return walk_command(vx, -omega * max(ball.distance_m, ORBIT_DISTANCE_M), omega + TURN_GAIN_PER_S * off_foot)


def push(ball: RelativeBall) -> tuple[float, float, float]:
    """Dribble: walk on through the ball at :data:`PUSH_MPS`, keeping it between the feet, so it
    goes where the robot faces (slower than a kick, but never behind the robot)."""
    return walk_command(PUSH_MPS, ALIGN_GAIN_PER_S * ball.left_m, 0.0)


def step_to_ball(ball: RelativeBall, heading_error_rad: float) -> tuple[float, float, float]:
    """Walk and side-step, without turning to the ball, until it lies :data:`KICK_SPOT_M` ahead
    before the nearer foot, turning by ``heading_error_rad`` (the aim minus the heading) on the
    way: for a near ball with the aim about ahead, where turning to the ball first and orbiting
    back to the aim costs seconds."""
    forward = ball.distance_m * math.cos(ball.bearing_rad)
    foot = math.copysign(FOOT_OFFSET_M, ball.left_m)
    return walk_command(APPROACH_GAIN_PER_S * (forward - KICK_SPOT_M), ALIGN_GAIN_PER_S * (ball.left_m - foot),
                        TURN_GAIN_PER_S * heading_error_rad)


def at_kick_spot(ball: RelativeBall) -> bool:
    """Whether the ball lies where a kick takes it: within :data:`KICK_DISTANCE_M`, before a foot."""
    return ball.distance_m < KICK_DISTANCE_M and FOOT_BAND_M[0] <= abs(ball.left_m) <= FOOT_BAND_M[1]


def kick_for(ball: RelativeBall) -> Motion:
    return Motion.KICK_LEFT if ball.left_m > 0.0 else Motion.KICK_RIGHT


def chase(
    ball: RelativeBall, heading_error_rad: float, foot_first: bool = False
) -> tuple[Motion, tuple[float, float, float]]:
    """Field player with the ball in sight: turn to it, walk to it, kick it toward the goal.

    ``heading_error_rad``: attacked direction minus estimated heading, normalized.
    ``foot_first``: at kicking distance, first side-step until the ball lies before a foot
    (:data:`FOOT_BAND_M`), where the kick is strong; a ball between the feet is kicked weakly.
    """
    if abs(ball.bearing_rad) > TURN_IN_PLACE_RAD:
        return Motion.WALK, turn_toward(ball.bearing_rad)
    if abs(heading_error_rad) > KICK_HEADING_TOLERANCE_RAD and ball.distance_m < ORBIT_WITHIN_M:
        return Motion.WALK, orbit(ball, heading_error_rad)
    if ball.distance_m >= KICK_DISTANCE_M:
        return Motion.WALK, approach(ball)
    if foot_first and not at_kick_spot(ball):
        foot = math.copysign(FOOT_OFFSET_M, ball.left_m)
        return Motion.WALK, walk_command(0.0, ALIGN_GAIN_PER_S * (ball.left_m - foot), 0.0)
    if abs(heading_error_rad) <= KICK_HEADING_TOLERANCE_RAD:
        return kick_for(ball), STILL
    return Motion.WALK, orbit(ball, heading_error_rad)


def keep_goal(ball: RelativeBall, heading_error_rad: float) -> tuple[Motion, tuple[float, float, float]]:
    """Goalkeeper with the ball in sight: side-step in front of it, kick it when it is close."""
    if ball.distance_m < KEEPER_KICK_DISTANCE_M and abs(ball.bearing_rad) < KEEPER_KICK_BEARING_RAD:
        return kick_for(ball), STILL
    if ball.distance_m > KEEPER_REACT_DISTANCE_M:
        return Motion.STAND, STILL
    omega = KEEPER_HEADING_GAIN_PER_S * heading_error_rad
    omega = min(max(omega, -KEEPER_MAX_TURN_RADPS), KEEPER_MAX_TURN_RADPS)
    return Motion.WALK, walk_command(0.0, KEEPER_SIDE_GAIN_PER_S * ball.left_m, omega)


@dataclass
class HeadSweep:
    """A triangular head-yaw sweep across +-``amplitude_rad``, counting its reversals."""

    yaw_rad: float = 0.0
    direction: float = 1.0
    reversals: int = 0
    amplitude_rad: float = SCAN_AMPLITUDE_RAD

    def restart(self, yaw_rad: float, direction: float) -> None:
        self.yaw_rad = min(max(yaw_rad, -self.amplitude_rad), self.amplitude_rad)
        self.direction = 1.0 if direction >= 0.0 else -1.0
        self.reversals = 0

    def advance(self, rate_radps: float) -> float:
        """Move the yaw target one control step on; return it (rad)."""
        self.yaw_rad += self.direction * rate_radps * CONTROL_STEP_S
        if abs(self.yaw_rad) >= self.amplitude_rad:
            self.yaw_rad = math.copysign(self.amplitude_rad, self.yaw_rad)
            self.direction = -math.copysign(1.0, self.yaw_rad)
            self.reversals += 1
        return self.yaw_rad

    @property
    def swept(self) -> bool:
        return self.reversals >= FULL_SWEEP_REVERSALS


# ---- walking to a pose, and around what is in the way ------------------------------------

ARRIVED_M = 0.15  # nearer than this to a target position, only turn to its heading
ARRIVED_RAD = math.radians(15.0)
FAR_M = 0.5  # farther than this, face the target and walk forward; nearer, step sideways too
FACE_TARGET_RAD = 0.5  # farther off than this, turn to face it while stepping toward it (not in place)
POSITION_GAIN_PER_S = 0.8
AVOID_BELOW_M = 0.4  # a sonar echo nearer than this in front of a robot walking forward ...
AVOID_SIDE_MPS = 0.08  # ... makes it step aside at this speed and slow down
AVOID_SLOWDOWN = 0.3


def walk_to(pose: Pose2D, target: Pose2D) -> tuple[Motion, tuple[float, float, float]]:
    """Walk from ``pose`` to ``target`` (field frame, m and rad); stand when there."""
    dx, dy = target.x - pose.x, target.y - pose.y
    c, s = math.cos(pose.theta), math.sin(pose.theta)
    forward, left = c * dx + s * dy, -s * dx + c * dy
    distance = math.hypot(forward, left)
    heading_error = math.remainder(target.theta - pose.theta, math.tau)
    if distance < ARRIVED_M:
        if abs(heading_error) < ARRIVED_RAD:
            return Motion.STAND, STILL
        return Motion.WALK, walk_command(0.0, 0.0, TURN_GAIN_PER_S * heading_error)
    bearing = math.atan2(left, forward)
    if distance > FAR_M:
        if abs(bearing) > FACE_TARGET_RAD:
            vx, vy = toward(bearing)
            return Motion.WALK, walk_command(vx, vy, turn_toward(bearing)[2])
        return Motion.WALK, walk_command(WALK_HIGH[0], 0.0, TURN_GAIN_PER_S * bearing)
    return Motion.WALK, walk_command(POSITION_GAIN_PER_S * forward, POSITION_GAIN_PER_S * left,
                                     TURN_GAIN_PER_S * heading_error)


def toward(bearing_rad: float) -> tuple[float, float]:
    """The fastest step (vx, vy; m/s, torso frame) toward ``bearing_rad`` the walk's limits allow: on
    the ellipse of the forward (or backward) and sideways limits. A quarter turn at the turn limit
    takes 1.6 s; stepping sideways all the while, a robot moves 0.14 m in it."""
    c, s = math.cos(bearing_rad), math.sin(bearing_rad)
    along = WALK_HIGH[0] if c >= 0.0 else -WALK_LOW[0]
    scale = 1.0 / math.hypot(c / along, s / WALK_HIGH[1])
    return c * scale, s * scale


def avoid(walk: tuple[float, float, float], sonar_m: tuple[float, ...]) -> tuple[float, float, float]:
    """The walk, changed to step around an obstacle the sonars (upper-left, upper-right,
    lower-left, lower-right) hear close in front while walking forward."""
    vx, vy, omega = walk
    if vx <= 0.0 or len(sonar_m) < 4:
        return walk
    left, right = min(sonar_m[0], sonar_m[2]), min(sonar_m[1], sonar_m[3])
    if min(left, right) >= AVOID_BELOW_M:
        return walk
    side = -AVOID_SIDE_MPS if left < right else AVOID_SIDE_MPS
    return walk_command(vx * AVOID_SLOWDOWN, side, omega)


# ---- going behind the ball ---------------------------------------------------------------

BEHIND_BALL_M = 0.3  # the approach point, this far behind the ball on the line from the aim
GO_BEHIND_RAD = math.radians(40.0)  # go round when robot->ball and ball->aim differ by more
GO_BEHIND_BEYOND_M = 0.45  # ... and the ball is farther than this (nearer: orbit it)
PASS_BALL_SIDE_M = 0.4  # walking round the ball, keep this far from it


def behind_ball(pose: Pose2D, ball_xy: tuple[float, float], aim_xy: tuple[float, float],
                beyond_m: float = GO_BEHIND_BEYOND_M) -> Pose2D | None:
    """Where to walk first so as to reach the ball from behind, facing ``aim_xy`` (field frame,
    m and rad); None when the robot already comes at the ball from behind (or is within
    ``beyond_m`` of it: nearer, it orbits the ball).

    A robot on the far side of the ball walks past it at :data:`PASS_BALL_SIDE_M` on its own
    side first, so that it never walks through the ball toward its own goal.
    """
    bx, by = ball_xy
    if abs(bx) > FIELD.half_length or abs(by) > FIELD.half_width:
        return None  # a ball out of the field: no room behind it, go straight to it
    aim = math.atan2(aim_xy[1] - by, aim_xy[0] - bx)
    dx, dy = bx - pose.x, by - pose.y
    if math.hypot(dx, dy) < beyond_m:
        return None
    if abs(math.remainder(math.atan2(dy, dx) - aim, math.tau)) < GO_BEHIND_RAD:
        return None
    ux, uy = math.cos(aim), math.sin(aim)
    ahead = -(dx * ux + dy * uy)  # how far the robot is on the aim side of the ball
    if ahead > -BEHIND_BALL_M / 2:
        # Past the ball at its side, to level with the spot behind it: from there (well beyond the
        # switch at half that depth, so that the choice does not flip back) straight to that spot.
        side = 1.0 if dx * uy - dy * ux >= 0.0 else -1.0  # the robot is left (+1) or right of the aim line
        return Pose2D(bx - uy * side * PASS_BALL_SIDE_M - ux * BEHIND_BALL_M,
                      by + ux * side * PASS_BALL_SIDE_M - uy * BEHIND_BALL_M, aim)
    return behind_point(ball_xy, aim_xy)


def approach_pose(pose: Pose2D, ball_xy: tuple[float, float], aim_xy: tuple[float, float]) -> Pose2D:
    """Where to walk to reach a ball believed at ``ball_xy`` from behind, facing ``aim_xy`` (field
    frame): the way round it (:func:`behind_ball`), else the spot :data:`BEHIND_BALL_M` behind it."""
    waypoint = behind_ball(pose, ball_xy, aim_xy)
    return behind_point(ball_xy, aim_xy) if waypoint is None else waypoint


def behind_point(ball_xy: tuple[float, float], aim_xy: tuple[float, float]) -> Pose2D:
    """The spot :data:`BEHIND_BALL_M` behind the ball on the line from ``aim_xy``, facing it (field frame)."""
    bx, by = ball_xy
    aim = math.atan2(aim_xy[1] - by, aim_xy[0] - bx)
    return Pose2D(bx - math.cos(aim) * BEHIND_BALL_M, by - math.sin(aim) * BEHIND_BALL_M, aim)
