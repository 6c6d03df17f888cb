"""Kick-off positions (thesis figure 2.11, SPL 2011 placement): public facts of the rules.

Positions are given for a team that defends the blue goal (own half x < 0, attacking +x)
and mirrored through the centre spot for the other team. Player 0 is the goalkeeper, on
its goal line; the kicking team's player 1 stands just behind the ball at the centre spot;
everyone else stays in its own half, the defenders outside the centre circle.
"""

from __future__ import annotations

import math

from world.field import FIELD, FieldGeometry, GoalColor, Pose2D

LEGAL_POSITION_TOLERANCE_M = 0.05  # slack on half and circle limits at SET
GOALKEEPER_LINE_X_M = 2.85  # |x| (m) of a goalkeeper placed on its goal line, 0.15 m inside the 3 m line

# (x m, y m, theta rad) for the team defending the blue goal, by player number.
KICKING_POSITIONS: tuple[tuple[float, float, float], ...] = (
    (-GOALKEEPER_LINE_X_M, 0.0, 0.0),
    (-0.22, 0.0, 0.0),
    (-1.2, 1.0, 0.0),
    (-1.2, -1.0, 0.0),
)
DEFENDING_POSITIONS: tuple[tuple[float, float, float], ...] = (
    (-GOALKEEPER_LINE_X_M, 0.0, 0.0),
    (-1.0, 0.0, 0.0),
    (-1.6, 1.1, 0.0),
    (-1.6, -1.1, 0.0),
)

PENALTY_KICKER_BEHIND_BALL_M = 0.22  # a penalty kicker stands this far behind the ball on the penalty mark


def kickoff_pose(player: int, kicking: bool, defended_goal: GoalColor) -> Pose2D:
    """Where ``player`` stands at a kick-off (field frame: m, rad); player 0 is the goalkeeper."""
    table = KICKING_POSITIONS if kicking else DEFENDING_POSITIONS
    if not 0 <= player < len(table):
        raise ValueError(f"player number {player!r} outside [0, {len(table) - 1}]")
    x, y, theta = table[player]
    if defended_goal is GoalColor.BLUE:
        return Pose2D(x, y, theta)
    return Pose2D(-x, -y, math.pi)


def penalty_pose(kicker: bool, defended_goal: GoalColor) -> Pose2D:
    """Where a shoot-out kick places the kicker (behind the ball on the penalty mark before the
    goal it attacks, facing it) or the goalkeeper (on its goal line, facing the field); field
    frame, m and rad. ``defended_goal``: the goal the robot's team defends for this kick."""
    if kicker:
        x, y, theta = FIELD.penalty_mark_x - PENALTY_KICKER_BEHIND_BALL_M, 0.0, 0.0
    else:
        x, y, theta = -GOALKEEPER_LINE_X_M, 0.0, 0.0
    if defended_goal is GoalColor.BLUE:
        return Pose2D(x, y, theta)
    return Pose2D(-x, -y, math.pi)


def legal_kickoff_position(
    x: float, y: float, defended: GoalColor, kicking: bool, field: FieldGeometry = FIELD
) -> bool:
    """Whether a robot at (x, y) (field frame, m) may stay there when SET begins; the referee puts
    every other robot (and every fallen one) at its kick-off position.

    Everyone must be on the field in its own half; robots of the defending team must also be
    outside the centre circle.
    """
    tol = LEGAL_POSITION_TOLERANCE_M
    on_field = abs(x) <= field.half_length + tol and abs(y) <= field.half_width + tol
    own_half = defended.sign * x >= -tol
    outside_circle = math.hypot(x, y) >= field.center_circle_radius - tol
    return on_field and own_half and (kicking or outside_circle)
