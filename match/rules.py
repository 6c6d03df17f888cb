"""The referee's geometric judgements and placements (SPL 2011 as run by RobotStadium).

Pure functions of positions on the field, so every rule can be tested with a placed ball
and a given last toucher. Field frame, metres (docs/design/index.md section 3).
"""

from __future__ import annotations

import enum
import math
from collections.abc import Iterable
from dataclasses import dataclass

from world.field import FIELD, FieldGeometry, GoalColor, Pose2D

BALL_SHIFT_M = 0.1  # placed ball moved this far toward the centre while on a robot
BALL_ROBOT_CLEARANCE_M = 0.2  # a placed ball nearer a robot's torso centre than this is "on" it
ROBOT_SPACING_M = 0.4  # robots placed back at the side line keep this far apart
SIDELINE_REPLACEMENT_X_M = 1.2  # |x| of the side-line spot: the own penalty mark's x


class OutKind(enum.Enum):
    SIDE_LINE = "side_line"
    END_LINE = "end_line"


@dataclass(frozen=True)
class BallOut:
    """Where and how the ball left the field."""

    kind: OutKind
    x: float
    y: float


def goal_crossed(x: float, y: float, z: float, field: FieldGeometry = FIELD) -> GoalColor | None:
    """The goal the whole ball is inside of (beyond the goal line, between posts, under the bar)."""
    beyond = field.half_length + field.line_width / 2.0 + field.ball_radius
    inside_posts = abs(y) < field.goal_post_y - field.goal_post_radius
    if abs(x) > beyond and inside_posts and z < field.goal_height:
        return GoalColor.YELLOW if x > 0 else GoalColor.BLUE
    return None


def ball_out(x: float, y: float, z: float, field: FieldGeometry = FIELD) -> BallOut | None:
    """How the whole ball left the field, unless it is a goal or still in (lines are in)."""
    if goal_crossed(x, y, z, field) is not None:
        return None
    margin = field.line_width / 2.0 + field.ball_radius
    if abs(y) > field.half_width + margin:
        return BallOut(OutKind.SIDE_LINE, x, y)
    if abs(x) > field.half_length + margin:
        return BallOut(OutKind.END_LINE, x, y)
    return None


def shift_off_robots(
    spot: tuple[float, float], robots: Iterable[tuple[float, float]], max_shifts: int = 60
) -> tuple[float, float]:
    """Move ``spot`` toward the centre spot in 0.1 m steps while it lies on a robot."""
    positions = list(robots)
    x, y = spot
    for _ in range(max_shifts):
        if all(math.hypot(x - rx, y - ry) >= BALL_ROBOT_CLEARANCE_M for rx, ry in positions):
            break
        distance = math.hypot(x, y)
        if distance < 1e-9:  # at the centre: step along +x instead
            x += BALL_SHIFT_M
            continue
        step = min(BALL_SHIFT_M, distance)
        x, y = x - step * x / distance, y - step * y / distance
    return x, y


def sideline_pose(
    defended: GoalColor, ball_y: float, occupied: Iterable[tuple[float, float]], field: FieldGeometry = FIELD
) -> Pose2D:
    """Where a robot taken off the field is put back: on the side line away from the ball.

    At the x of its own penalty mark, facing into the field; moved toward the halfway line
    in 0.4 m steps while another robot stands there.
    """
    side = -1.0 if ball_y >= 0.0 else 1.0
    y = side * field.half_width
    x = defended.sign * SIDELINE_REPLACEMENT_X_M
    positions = list(occupied)
    for _ in range(int(field.half_length / ROBOT_SPACING_M) * 2):
        if all(math.hypot(x - ox, y - oy) >= ROBOT_SPACING_M for ox, oy in positions):
            break
        x -= defended.sign * ROBOT_SPACING_M
    return Pose2D(x, y, -side * math.pi / 2.0)


