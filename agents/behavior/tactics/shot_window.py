"""Where a shot goes in: the widest part of the opponent goal's mouth that no robot covers, seen from the ball.

Seen from the ball, the mouth spans the directions between its two posts, each brought in
by :data:`POST_MARGIN_M` (a ball grazing the post's inner face still goes in). Every robot
standing between the ball and the goal line (the goalkeeper first of all) covers the
directions within :data:`BLOCKER_RADIUS_M` of its centre. What is left is a set of open
intervals of direction; a shot aims at the middle of the widest one, and the robot kicks
when its heading lies within :data:`TOLERANCE_SHARE` of that interval's half-width of the
aim (at least :data:`MIN_TOLERANCE_RAD`): a kick's own spread (about 5 degrees either way)
and the pose estimate's heading error (3-4 degrees) then keep most shots inside the
interval. The interval aimed at last is kept while it stays open and at least
:data:`KEEP_SHARE` as wide as the widest, so that the aim does not flip from one side of
the goalkeeper to the other while the robot walks round the ball.

A mouth covered all over (a robot just in front of the ball) leaves the whole mouth to aim
at: the shot is still the best play the striker has.

Field frame throughout (m, rad); directions are absolute, normalized to (-pi, pi].
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

from world.field import FIELD

POST_MARGIN_M = FIELD.ball_radius + 0.05  # ours: the mouth's usable width ends this far inside each post
BLOCKER_RADIUS_M = 0.12 + FIELD.ball_radius + 0.03  # a robot's half width with its arms, the ball's radius, a margin
BEHIND_LINE_M = 0.3  # robots up to this far behind the goal line (inside the goal) still cover the mouth
MIN_TOLERANCE_RAD = math.radians(2.5)  # ours: the least heading tolerance (the robot cannot turn finer)
TOLERANCE_SHARE = 0.5  # ours: a kick may go when the heading lies within this share of the interval's half-width
KEEP_SHARE = 0.7  # ours: the interval aimed at last is kept while at least this share of the widest one


class ShotWindowError(ValueError):
    """An input the shot window does not accept (names the value)."""


@dataclass(frozen=True)
class ShotWindow:
    """Where to shoot from the ball: ``direction_rad`` (field frame) toward ``aim_xy`` on the goal
    line (m; for a kick past a robot, :mod:`agents.behavior.tactics.kick_past`, a point along the
    direction), the open interval's ``half_width_rad`` around it, the heading ``tolerance_rad``
    within which to kick, and whether the mouth was ``covered`` all over (then it is all of it)."""

    aim_xy: tuple[float, float]
    direction_rad: float
    half_width_rad: float
    tolerance_rad: float
    covered: bool

    def allows(self, heading_rad: float) -> bool:
        """Whether a kick along ``heading_rad`` (field frame) lies within the tolerance of the aim."""
        return abs(math.remainder(heading_rad - self.direction_rad, math.tau)) <= self.tolerance_rad


def shot_window(
    ball_xy: tuple[float, float],
    goal_x: float,
    blockers_xy: Iterable[tuple[float, float]] = (),
    previous_direction_rad: float | None = None,
) -> ShotWindow:
    """The shot at the goal whose line is at ``goal_x`` (+-3 m) for a ball at ``ball_xy`` with robots at
    ``blockers_xy`` (field frame, m); ``previous_direction_rad``: the direction aimed at last, kept while
    its interval stays open and wide enough (see the module)."""
    bx, by = finite_pair(ball_xy, "ball_xy")
    if not (math.isfinite(goal_x) and abs(goal_x) > 0.0):
        raise ShotWindowError(f"goal_x must be a finite, non-zero x of a goal line (m); got {goal_x!r}")
    ahead = math.copysign(1.0, goal_x) * (goal_x - bx)  # from the ball to the goal line, along the attack
    if ahead <= FIELD.ball_radius:
        raise ShotWindowError(f"ball_xy {ball_xy!r} lies on or beyond the goal line at x = {goal_x}")
    base = math.atan2(-by, goal_x - bx)  # toward the goal's centre: all directions are taken relative to it
    mouth_y = FIELD.goal_inner_width / 2.0 - POST_MARGIN_M
    lo, hi = sorted(relative(math.atan2(y - by, goal_x - bx), base) for y in (-mouth_y, mouth_y))
    covers = []
    for point in blockers_xy:
        ox, oy = finite_pair(point, "a blocker")
        along = math.copysign(1.0, goal_x) * (ox - bx)
        if not 0.0 < along <= ahead + BEHIND_LINE_M:
            continue
        distance = math.hypot(ox - bx, oy - by)
        half = math.asin(min(1.0, BLOCKER_RADIUS_M / distance))
        centre = relative(math.atan2(oy - by, ox - bx), base)
        covers.append((centre - half, centre + half))
    intervals = open_intervals(lo, hi, covers)
    covered = not intervals
    if covered:
        intervals = [(lo, hi)]
    chosen = max(intervals, key=lambda iv: iv[1] - iv[0])
    if previous_direction_rad is not None and math.isfinite(previous_direction_rad):
        previous = relative(previous_direction_rad, base)
        for start, end in intervals:
            if start <= previous <= end and end - start >= KEEP_SHARE * (chosen[1] - chosen[0]):
                chosen = (start, end)
                break
    middle = (chosen[0] + chosen[1]) / 2.0
    half_width = (chosen[1] - chosen[0]) / 2.0
    direction = math.remainder(base + middle, math.tau)
    aim_y = by + math.tan(direction) * (goal_x - bx)
    return ShotWindow((goal_x, aim_y), direction, half_width, max(MIN_TOLERANCE_RAD, TOLERANCE_SHARE * half_width),
                      covered)


def open_intervals(lo: float, hi: float, covers: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """The parts of [lo, hi] outside every interval of ``covers`` (sorted, non-empty)."""
    intervals = []
    start = lo
    for cover_lo, cover_hi in sorted(covers):
        if cover_lo > start:
            intervals.append((start, min(cover_lo, hi)))
        start = max(start, cover_hi)
        if start >= hi:
            break
    if start < hi:
        intervals.append((start, hi))
    return [(a, b) for a, b in intervals if b > a]


def relative(direction_rad: float, base_rad: float) -> float:
    """``direction_rad`` minus ``base_rad``, normalized to (-pi, pi] (rad)."""
    return math.remainder(direction_rad - base_rad, math.tau)


def finite_pair(value: object, name: str) -> tuple[float, float]:
    try:
        x, y = (float(v) for v in value)  # type: ignore[union-attr]
    except (TypeError, ValueError):
        raise ShotWindowError(f"{name} must be two numbers (m, field frame); got {value!r}") from None
    if not (math.isfinite(x) and math.isfinite(y)):
        raise ShotWindowError(f"{name} must be finite (m, field frame); got {value!r}")
    return x, y
