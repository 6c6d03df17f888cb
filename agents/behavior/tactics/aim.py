"""Where a striker plays the ball: at the opponent goal, or cleared to the side from its own goal mouth.

A ball just in front of the own goal cannot be reached from behind on the line to the
opponent goal: the spot behind it lies in or beside the own goal, and a robot coming at it
from the field pushes it over its own line. Such a ball is cleared instead, toward the
nearer side of the field, turned from the goal line toward the opponent goal by
:data:`CLEAR_MIN_TURN_RAD` plus :data:`CLEAR_TURN_PER_M` per metre of depth, and more where
a kick's roll would otherwise leave the field and the spot behind the ball still lies in
front of the line. Within :data:`PUSH_DEPTH_M` of the line the ball is pushed there, not
kicked: a kick that goes astray so near the goal is a goal.

A ball on the opponent goal line (within :data:`GOAL_LINE_BAND_M`) is no shot for the goal's
centre: the line to it runs along the goal line, so the spot behind the ball lies beside it and
the striker circles the ball, where an opponent at the post can block it for good. Between the
posts, far enough inside them for the ball to pass (:data:`POST_CLEARANCE_M`), it is pushed
into the goal toward a point inside it (:data:`GOAL_LINE_AIM_DEPTH_M`), which the robot faces
from the field; beside the goal, where no line into it passes the post, it is pushed back out
in front of the goal (:data:`CUTBACK_M`), from a spot behind the ball on the carpet beyond the
end line.

A throw-in's first touch (:func:`restart_aim`) is played the way the robot already goes (the
way it comes at the ball from afar, the way it faces near it), turned only as far as needed
to keep it from going along or out over the near side line, and from going back toward the
own goal in the own half: the quick touch that puts the ball back in play, where walking
round the ball to face the opponent goal takes a slow robot (0.15-0.2 m/s) ten seconds or
more. In the opponent half the touch may go back along the line (a push moves the ball half
a metre): a robot that comes from the opponent's side no longer walks round the ball first.

Computed in the frame where the own goal is at x = -3 (``attack`` = +1 when the robot
defends the blue goal, -1 otherwise) and mirrored; field frame, m and rad.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from agents.behavior.skills import BEHIND_BALL_M, KICK_ROLL_M, SIDELINE_MARGIN_M
from world.field import FIELD

CLEAR_DEPTH_M = 0.8  # ours: a ball nearer its own goal line than this ...
CLEAR_HALF_WIDTH_M = FIELD.goal_area_width / 2 + 0.2  # ... and this near the goal's axis is cleared
CLEAR_MIN_TURN_RAD = math.radians(40.0)  # ours: a clearing turns at least this far from the goal line ...
CLEAR_TURN_PER_M = math.radians(40.0)  # ... and this much more per metre of depth ...
CLEAR_MAX_TURN_RAD = math.radians(80.0)  # ... and more, up to this, to keep the roll in the field
BEHIND_MIN_DEPTH_M = 0.05  # ... as long as the spot behind the ball stays this far in front of the line
PUSH_DEPTH_M = 0.4  # ours: nearer the line, a kick gone astray (back between the feet) is a goal: push
AIM_DISTANCE_M = 2.0  # the aim point of a clearing lies this far from the ball
CENTRE_BAND_M = 0.2  # a ball this near the goal's axis is cleared away from the robot's side
GOAL_LINE_BAND_M = 0.1  # theirs: a ball nearer their goal line than this is on it ...
POST_CLEARANCE_M = FIELD.goal_post_diameter / 2 + FIELD.ball_radius  # ... pushed in when it passes a post by this
GOAL_LINE_AIM_DEPTH_M = 0.25  # ... toward the goal's axis this deep inside the goal ...
CUTBACK_M = 0.5  # ... or, beside the goal, pushed back to the goal's axis this far in front of its line
RESTART_OFF_LINE_RAD = math.radians(10.0)  # ours: a throw-in's first touch turns at least this far off the line ...
RESTART_INTO_FIELD_RAD = math.radians(90.0)  # ... and at most square into the field (never back toward the own goal) ...
RESTART_BACK_RAD = math.radians(170.0)  # ... or, this far from the own goal line at least, back along the line
RESTART_BACK_MIN_M = FIELD.half_length


@dataclass(frozen=True)
class Aim:
    """Where to play the ball (field frame, m); whether it is a clearing (played along the aim,
    not shot), and whether the ball lies so near a goal line (:data:`PUSH_DEPTH_M`,
    :data:`GOAL_LINE_BAND_M`) that it is pushed, not kicked."""

    x: float
    y: float
    clearing: bool
    push: bool = False

    @property
    def xy(self) -> tuple[float, float]:
        return (self.x, self.y)


def kick_aim(ball_xy: tuple[float, float], attack: float, robot_y: float) -> Aim:
    """The aim for a ball at ``ball_xy``: the opponent goal's centre, or a clearing point when the
    ball lies in front of the own goal (see the module). ``robot_y``: the robot's y, which decides
    the side a ball on the goal's axis is cleared to (away from the robot)."""
    bx, by = ball_xy
    if on_their_goal_line(ball_xy, attack):
        return _goal_line_aim(by, attack)
    depth = attack * bx + FIELD.half_length  # from the own goal line into the field
    if depth >= CLEAR_DEPTH_M or abs(by) > CLEAR_HALF_WIDTH_M:
        return Aim(attack * FIELD.half_length, 0.0, False)
    if abs(by) >= CENTRE_BAND_M:
        side = math.copysign(1.0, by)
    else:
        side = 1.0 if by >= robot_y else -1.0
    return Aim(*_clearing_point(bx, by, depth, attack, side), True, depth < PUSH_DEPTH_M)


def on_their_goal_line(ball_xy: tuple[float, float], attack: float) -> bool:
    """Whether a ball at ``ball_xy`` lies within :data:`GOAL_LINE_BAND_M` of the opponent goal line."""
    return FIELD.half_length - attack * ball_xy[0] < GOAL_LINE_BAND_M


def _goal_line_aim(by: float, attack: float) -> Aim:
    """A ball on the opponent goal line: pushed in between the posts, or back out in front of the goal."""
    if abs(by) < FIELD.goal_post_y - POST_CLEARANCE_M:
        return Aim(attack * (FIELD.half_length + GOAL_LINE_AIM_DEPTH_M), 0.0, False, True)
    return Aim(attack * (FIELD.half_length - CUTBACK_M), 0.0, True, True)


def _clearing_point(bx: float, by: float, depth: float, attack: float, side: float) -> tuple[float, float]:
    """The clearing's aim: turned from the goal line toward the opponent by the least turn for the
    depth, more if the roll would leave the field and the spot behind the ball has room for it."""
    least = CLEAR_MIN_TURN_RAD + max(depth, 0.0) * CLEAR_TURN_PER_M
    room = (depth - BEHIND_MIN_DEPTH_M) / BEHIND_BALL_M
    most = max(least, min(CLEAR_MAX_TURN_RAD, math.asin(min(max(room, 0.0), 1.0))))
    inside = (FIELD.half_width - SIDELINE_MARGIN_M - abs(by)) / KICK_ROLL_M
    wanted = math.acos(min(max(inside, -1.0), 1.0))
    turn = min(max(wanted, least), most)
    return bx + attack * AIM_DISTANCE_M * math.sin(turn), by + side * AIM_DISTANCE_M * math.cos(turn)


def restart_aim(ball_xy: tuple[float, float], way_rad: float, attack: float, held_rad: float | None = None) -> Aim:
    """The aim of a throw-in's first touch for a robot that would play the ball along ``way_rad``
    (field frame): that way, or the nearer edge of the cone from :data:`RESTART_OFF_LINE_RAD` off
    the side line nearer the ball to :data:`RESTART_INTO_FIELD_RAD` into the field
    (:data:`RESTART_BACK_RAD`, back along the line, with the ball :data:`RESTART_BACK_MIN_M` or
    more from the own goal line); angles from the attack direction, negative into the field.

    ``held_rad`` is the direction of the last step's aim (field frame), if any: outside the cone
    the edge nearer it stays the aim. The way a robot faces near the ball changes as it turns to
    walk round the ball, and one facing away from the cone's middle is about as near to both
    edges: re-chosen every step, turning toward one edge made the other the nearer and back."""
    bx, by = ball_xy
    side = 1.0 if by >= 0.0 else -1.0

    def in_attack_frame(angle_rad: float) -> float:
        return math.atan2(side * math.sin(angle_rad), attack * math.cos(angle_rad))

    way = in_attack_frame(way_rad)
    most = RESTART_BACK_RAD if attack * bx + FIELD.half_length >= RESTART_BACK_MIN_M else RESTART_INTO_FIELD_RAD
    if not -most <= way <= -RESTART_OFF_LINE_RAD:
        edges = (-RESTART_OFF_LINE_RAD, -most)
        toward = way if held_rad is None else in_attack_frame(held_rad)
        way = min(edges, key=lambda edge: abs(math.remainder(toward - edge, math.tau)))
    return Aim(bx + attack * AIM_DISTANCE_M * math.cos(way), by + side * AIM_DISTANCE_M * math.sin(way), False)
