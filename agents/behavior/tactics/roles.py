"""Roles: who plays what, from the team model, and where each role stands.

The goalkeeper is player 0. Among the field players the striker is the robot that reaches
the ball first by an estimated time that counts the walk and the turn. A robot that is the
striker keeps the role unless another is :data:`STRIKER_HYSTERESIS_S` faster, so two robots
do not chase the same ball for long; the bonus goes to every robot that says it is the
striker (itself, or a teammate by its last message), so that two robots that took the role
at once (each with the other's older time) agree on the faster one instead of both keeping
it. Of the others, the lower number defends (between the ball and its own goal) and the
next supports (behind the striker, off to the side). With fewer players the roles degrade:
one field player is always the striker, two are striker and defender, and a goalkeeper that
hears no teammate (``lone``: it plays alone, or every teammate has fallen silent) is the
striker, since a team of one that only keeps its goal can never score.

Positions are in the field frame; they are computed in the frame where the robot's own goal
is at x = -3 (``attack`` = +1 when it defends the blue goal, -1 otherwise) and mirrored.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from agents.radio import Role
from match.protocol import Pose2D
from world.field import FIELD

STRIKER_HYSTERESIS_S = 1.5
WALK_SPEED_MPS = 0.15  # a typical approach speed, for the time to the ball
TURN_SPEED_RADPS = 0.8
FALLEN_PENALTY_S = 6.0  # standing up and finding the ball again
GOALKEEPER_X_M = -2.85  # own-goal frame
GOALKEEPER_MAX_Y_M = 0.55
GOALKEEPER_FOLLOW = 0.4  # the keeper moves this share of the ball's y
SUPPORT_BEHIND_M = 1.1
SUPPORT_SIDE_M = 0.7
DEFEND_SHARE = 0.4  # the defender stands this share of the way from its goal to the ball
DEFENDER_MAX_X_M = -0.6  # own-goal frame: the defender stays in its own half
FIELD_MARGIN_M = 0.3


@dataclass(frozen=True)
class Candidate:
    """A robot that may take a role: its number, its estimated time to the ball (s), and whether it
    said it is the striker (a teammate's last message; ignored for the robot deciding)."""

    player: int
    time_to_ball_s: float
    striker: bool = False


def time_to_ball(pose: Pose2D, ball_xy: tuple[float, float], fallen: bool = False) -> float:
    """Seconds to reach the ball: walk the distance and turn to face it first."""
    dx, dy = ball_xy[0] - pose.x, ball_xy[1] - pose.y
    turn = abs(math.remainder(math.atan2(dy, dx) - pose.theta, math.tau))
    return math.hypot(dx, dy) / WALK_SPEED_MPS + turn / TURN_SPEED_RADPS + (FALLEN_PENALTY_S if fallen else 0.0)


FIELD_ROLES = (Role.DEFENDER, Role.SUPPORTER)  # the field players beside the striker, by player number


def assign_role(own: Candidate, others: Sequence[Candidate], current: str, lone: bool = False,
                field_roles: Sequence[str] = FIELD_ROLES) -> str:
    """This robot's role (a name), given the field players heard from (``others``, keeper excluded);
    ``lone``: this robot has heard no teammate for a while (a player 0 then plays the field). Beside the
    striker, the field players take ``field_roles`` by player number, the last one as often as needed."""
    if own.player == 0 and not lone:
        return Role.GOALKEEPER
    field_players = [own, *[c for c in others if c.player != 0 and c.player != own.player]]

    def effective(c: Candidate) -> tuple[float, int]:
        striker = current == Role.STRIKER if c.player == own.player else c.striker
        return (c.time_to_ball_s - (STRIKER_HYSTERESIS_S if striker else 0.0), c.player)

    striker = min(field_players, key=effective)
    if striker.player == own.player:
        return Role.STRIKER
    rest = sorted(c.player for c in field_players if c.player != striker.player)
    return field_roles[min(rest.index(own.player), len(field_roles) - 1)]


def goalkeeper_spot(bx: float, by: float) -> tuple[float, float]:
    """The goalkeeper's spot on its line, following the ball's y (own-goal frame, ball at ``bx, by``)."""
    return GOALKEEPER_X_M, _clip(by * GOALKEEPER_FOLLOW, GOALKEEPER_MAX_Y_M)


def defender_spot(bx: float, by: float) -> tuple[float, float]:
    """Between the ball and the own goal, in the own half (own-goal frame)."""
    x = min(-FIELD.half_length + DEFEND_SHARE * (bx + FIELD.half_length), DEFENDER_MAX_X_M)
    return _in_field(x, by * DEFEND_SHARE)


def supporter_spot(bx: float, by: float) -> tuple[float, float]:
    """Behind the ball, off to the side (own-goal frame); a striker without a ball stands there too."""
    x = bx - SUPPORT_BEHIND_M
    y = by - math.copysign(SUPPORT_SIDE_M, by) if abs(by) > SUPPORT_SIDE_M else by + SUPPORT_SIDE_M
    return _in_field(x, y)


SPOTS = {Role.GOALKEEPER: goalkeeper_spot, Role.DEFENDER: defender_spot}  # any other role: supporter_spot


def role_position(role: str, ball_xy: tuple[float, float] | None, attack: float) -> Pose2D:
    """Where a robot of ``role`` should stand (field frame), facing the ball or the field."""
    return position_from_spot(SPOTS.get(role, supporter_spot), ball_xy, attack)


def position_from_spot(spot: Callable[[float, float], tuple[float, float]], ball_xy: tuple[float, float] | None,
                       attack: float) -> Pose2D:
    """The pose (field frame) at ``spot(bx, by)`` (own-goal frame: a function of the ball there, or of the
    centre spot without a ball), facing the ball or the field."""
    if ball_xy is None:
        bx, by = 0.0, 0.0
    else:
        bx, by = ball_xy[0] * attack, ball_xy[1] * attack  # own-goal frame
    x, y = spot(bx, by)
    face = math.atan2(by - y, bx - x)
    if attack > 0:
        return Pose2D(x, y, face)
    return Pose2D(-x, -y, math.remainder(face + math.pi, math.tau))


def _in_field(x: float, y: float) -> tuple[float, float]:
    return _clip(x, FIELD.half_length - FIELD_MARGIN_M), _clip(y, FIELD.half_width - FIELD_MARGIN_M)


def _clip(value: float, limit: float) -> float:
    return min(max(value, -limit), limit)
