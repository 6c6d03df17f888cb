"""A ball lying at the own goal line in front of the goal is held off, not played.

Such a ball cannot be reached from behind: the spot behind it lies in the goal, and a robot
that walks or side-steps round it to get there sweeps it over the line with its legs. A ball within :data:`HOLD_BAND_M` of the own goal
line (or beyond it) and in front of the goal (between the posts, or beside one by less than
:data:`HOLD_BESIDE_POST_M`) is held off: a robot within :data:`HOLD_NEAR_M` of it stands
still; one farther away walks to the spot :data:`HOLD_NEAR_M` in front of it, facing it,
and waits there. It plays the ball again once the ball leaves the band (pushed back out by
an opponent, or rolled). An opponent that pushes the ball in scores; the robot does not.

Computed in the frame where the own goal is at x = -3 (``attack`` = +1 when the robot defends
the blue goal, -1 otherwise) and mirrored; field frame, m and rad.
"""

from __future__ import annotations

import math

from agents.behavior import skills
from match.protocol import Motion, Pose2D
from world.field import FIELD

HOLD_BAND_M = 0.15  # ours: a ball nearer the own goal line than this (its centre, m) ...
HOLD_BESIDE_POST_M = 0.15  # ... and in front of the goal, or beside a post by less than this, is held off
HOLD_NEAR_M = 0.4  # ours: within this of the ball the robot stands; farther, it waits this far in front of it


def at_own_goal_line(ball_xy: tuple[float, float], attack: float) -> bool:
    """Whether a ball believed at ``ball_xy`` (field frame) lies at the own goal line in front of the goal."""
    bx, by = ball_xy
    return (attack * bx < -FIELD.half_length + HOLD_BAND_M
            and abs(by) < FIELD.goal_post_y + HOLD_BESIDE_POST_M)


def hold_pose(ball_xy: tuple[float, float], attack: float) -> Pose2D:
    """The spot :data:`HOLD_NEAR_M` in front of a ball at the own goal line, toward the field, facing it."""
    bx, by = ball_xy
    x = max(attack * bx, -FIELD.half_length) + HOLD_NEAR_M  # own-goal frame
    return Pose2D(attack * x, by, math.pi if attack > 0 else 0.0)


def hold_off(pose: Pose2D, ball_xy: tuple[float, float], attack: float
             ) -> tuple[Motion, tuple[float, float, float]]:
    """Stand within :data:`HOLD_NEAR_M` of a ball at the own goal line; else walk to :func:`hold_pose`."""
    if math.dist((pose.x, pose.y), ball_xy) < HOLD_NEAR_M:
        return Motion.STAND, skills.STILL
    return skills.walk_to(pose, hold_pose(ball_xy, attack))
