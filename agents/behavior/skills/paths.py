"""Walking around obstacles: a walk command turned aside from what lies in its way.

A pure function, like the skills of :mod:`agents.behavior.skills`, whose step-aside speed,
slow-down and walk limits it shares. The walk command is (vx m/s, vy m/s, omega rad/s) in
the torso frame (x forward, y left, CCW positive); obstacles are those of
:mod:`agents.modelling.obstacle_model`, robot-relative in the same frame.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

from agents.behavior.skills import AVOID_BELOW_M, AVOID_SIDE_MPS, AVOID_SLOWDOWN, walk_command
from agents.modelling.obstacle_model import CORRIDOR_HALF_WIDTH_M, Obstacle, first_in_path

LOOK_AHEAD_M = 0.8  # ours: an obstacle this far along the path (centre to centre) is stepped around
SLOW_FROM_M = 0.6  # ours: nearer than this the walk slows, down to AVOID_SLOWDOWN at AVOID_BELOW_M
MIN_SPEED_MPS = 0.02  # ours: a slower walk (turning in place) has no path to block
SIDE_RANGE_M = 1.2  # ours: obstacles this near, ahead, weigh on which side is freer
MIN_WEIGHT_DISTANCE_M = 0.1


def steer_around(
    walk: tuple[float, float, float], obstacles: Iterable[Obstacle], look_ahead_m: float = LOOK_AHEAD_M
) -> tuple[float, float, float]:
    """The walk, turned aside from the nearest obstacle in its way.

    The way is the corridor :data:`~agents.modelling.obstacle_model.CORRIDOR_HALF_WIDTH_M`
    to each side of the walking direction (that of (vx, vy)), ``look_ahead_m`` long. With an
    obstacle in it, the robot steps sideways toward the freer side at
    :data:`~agents.behavior.skills.AVOID_SIDE_MPS` and slows down along the path when it is
    near (below :data:`SLOW_FROM_M`); the turn rate is kept, the result is within the walk
    limits. A clear way, or a walk slower than :data:`MIN_SPEED_MPS`, returns ``walk`` as it is.
    """
    vx, vy, omega = walk
    speed = math.hypot(vx, vy)
    if speed < MIN_SPEED_MPS:
        return walk
    obstacles = tuple(obstacles)
    direction = math.atan2(vy, vx)
    blocker = first_in_path(obstacles, direction, look_ahead_m, CORRIDOR_HALF_WIDTH_M)
    if blocker is None:
        return walk
    c, s = math.cos(direction), math.sin(direction)
    along = c * blocker.x_m + s * blocker.y_m
    forward = speed * slowdown(along)
    lateral = freer_side(obstacles, direction) * AVOID_SIDE_MPS
    return walk_command(c * forward - s * lateral, s * forward + c * lateral, omega)


def slowdown(along_m: float) -> float:
    """Speed factor for an obstacle ``along_m`` ahead on the path: 1 from :data:`SLOW_FROM_M`
    on, :data:`~agents.behavior.skills.AVOID_SLOWDOWN` at
    :data:`~agents.behavior.skills.AVOID_BELOW_M` and nearer, linear between."""
    if along_m >= SLOW_FROM_M:
        return 1.0
    if along_m <= AVOID_BELOW_M:
        return AVOID_SLOWDOWN
    return AVOID_SLOWDOWN + (1.0 - AVOID_SLOWDOWN) * (along_m - AVOID_BELOW_M) / (SLOW_FROM_M - AVOID_BELOW_M)


def freer_side(obstacles: Iterable[Obstacle], direction_rad: float) -> float:
    """+1 (left of the walking direction) or -1 (right): the side with less in the way.

    Each obstacle ahead within :data:`SIDE_RANGE_M` weighs on its side of the path by the
    inverse of its distance (one on the path's line weighs half on each side); ties go left.
    """
    c, s = math.cos(direction_rad), math.sin(direction_rad)
    left = right = 0.0
    for obstacle in obstacles:
        along = c * obstacle.x_m + s * obstacle.y_m
        across = -s * obstacle.x_m + c * obstacle.y_m
        distance = obstacle.distance_m
        if along <= 0.0 or distance > SIDE_RANGE_M:
            continue
        weight = 1.0 / max(distance, MIN_WEIGHT_DISTANCE_M)
        if across > 0.0:
            left += weight
        elif across < 0.0:
            right += weight
        else:
            left += weight / 2.0
            right += weight / 2.0
    return -1.0 if left > right else 1.0
