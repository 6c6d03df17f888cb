"""Kicking past a robot in the way: in open play, a kick at the opponent goal that a robot near
the ball would stop is turned just far enough to pass it.

A robot standing just in front of the ball blocks many kicks at the goal (a kick takes 1.6 s;
the opponent is there meanwhile, or already). Every robot within :data:`PAST_WITHIN_M` of the ball covers the
directions within :data:`agents.behavior.tactics.shot_window.BLOCKER_RADIUS_M` of its centre, seen
from the ball (all of them when it stands nearer than that: then nothing passes it, and the
kick goes at the goal as before). When the direction at the goal's centre is covered, the
kick goes along the open direction nearest to it, :data:`PAST_MARGIN_RAD` inside the gap's
edge, turned at most :data:`PAST_SPAN_RAD` from the goal, never more than
:data:`AWAY_FROM_OWN_GOAL_RAD` from the attack direction, and never so that a kick's roll
(:data:`agents.behavior.skills.KICK_ROLL_M`) ends within
:data:`agents.behavior.skills.SIDELINE_MARGIN_M` of a side line or beyond it. The gap aimed
at last is kept while it stays open, so that the aim does not flip from one side of the robot
to the other while the striker turns round the ball.

Field frame throughout (m, rad); directions are absolute, normalized to (-pi, pi].
"""

from __future__ import annotations

import math
from collections.abc import Iterable

from agents.behavior.skills import KICK_ROLL_M, SIDELINE_MARGIN_M
from agents.behavior.tactics.shot_window import (
    BLOCKER_RADIUS_M,
    ShotWindow,
    ShotWindowError,
    finite_pair,
    open_intervals,
    relative,
)
from world.field import FIELD

PAST_WITHIN_M = 1.0  # ours: robots this near the ball are in a kick's way
PAST_SPAN_RAD = math.radians(60.0)  # ours: the kick turns at most this far from the goal's centre ...
AWAY_FROM_OWN_GOAL_RAD = math.radians(80.0)  # ... and from the attack direction
PAST_MARGIN_RAD = math.radians(10.0)  # ours: the aim lies this far inside the gap's edge ...
PAST_TOLERANCE_RAD = math.radians(5.0)  # ... and the kick goes when the heading is this near it (a kick spreads
# about 5 degrees either way)
MIN_GAP_RAD = math.radians(8.0)  # ours: a narrower gap is no way past
AIM_DISTANCE_M = 2.0  # the aim point lies this far from the ball


def kick_past(
    ball_xy: tuple[float, float],
    goal_x: float,
    blockers_xy: Iterable[tuple[float, float]] = (),
    previous_direction_rad: float | None = None,
) -> ShotWindow | None:
    """The kick past the robots at ``blockers_xy`` for a ball at ``ball_xy`` played at the goal whose
    line is at ``goal_x`` (+-3 m): its direction, the aim point :data:`AIM_DISTANCE_M` along it, the
    gap's half-width and the heading tolerance; None when the way at the goal's centre is open (or
    no gap within the span is): then the kick goes at the goal. ``previous_direction_rad``: the
    direction aimed at last, whose gap is kept while it is open (see the module)."""
    bx, by = finite_pair(ball_xy, "ball_xy")
    if not (math.isfinite(goal_x) and abs(goal_x) > 0.0):
        raise ShotWindowError(f"goal_x must be a finite, non-zero x of a goal line (m); got {goal_x!r}")
    base = math.atan2(-by, goal_x - bx)  # toward the goal's centre: all directions are taken relative to it
    covers = []
    for point in blockers_xy:
        ox, oy = finite_pair(point, "a blocker")
        distance = math.hypot(ox - bx, oy - by)
        if distance > PAST_WITHIN_M:
            continue
        if distance <= BLOCKER_RADIUS_M:
            return None  # at the ball: nothing passes it
        half = math.asin(BLOCKER_RADIUS_M / distance)
        centre = relative(math.atan2(oy - by, ox - bx), base)
        covers.append((centre - half, centre + half))
    if not any(lo <= 0.0 <= hi for lo, hi in covers):
        return None
    lo, hi = _span(bx, by, goal_x, base)
    gaps = [(a, b) for a, b in open_intervals(lo, hi, covers) if b - a >= MIN_GAP_RAD]
    if not gaps:
        return None
    chosen = min(gaps, key=lambda gap: min(abs(gap[0]), abs(gap[1])))
    if previous_direction_rad is not None and math.isfinite(previous_direction_rad):
        previous = relative(previous_direction_rad, base)
        chosen = next((gap for gap in gaps if gap[0] <= previous <= gap[1]), chosen)
    a, b = chosen
    inner_lo, inner_hi = a + PAST_MARGIN_RAD, b - PAST_MARGIN_RAD
    turn = (a + b) / 2.0 if inner_lo > inner_hi else min(max(0.0, inner_lo), inner_hi)
    direction = math.remainder(base + turn, math.tau)
    aim = (bx + AIM_DISTANCE_M * math.cos(direction), by + AIM_DISTANCE_M * math.sin(direction))
    half_width = (b - a) / 2.0
    return ShotWindow(aim, direction, half_width, min(PAST_TOLERANCE_RAD, half_width), False)


def _span(bx: float, by: float, goal_x: float, base: float) -> tuple[float, float]:
    """The directions a kick may take (relative to ``base``): within :data:`PAST_SPAN_RAD` of it,
    :data:`AWAY_FROM_OWN_GOAL_RAD` of the attack direction, and with a roll that stays
    :data:`SIDELINE_MARGIN_M` inside the side lines."""
    attack = math.copysign(1.0, goal_x)
    attack_rad = 0.0 if attack > 0 else math.pi
    room = FIELD.half_width - SIDELINE_MARGIN_M
    # along the attack direction turned by psi the ball's y changes by attack * sin(psi) per metre
    sines = sorted(attack * (edge - by) / KICK_ROLL_M for edge in (-room, room))
    psi_lo, psi_hi = (math.asin(min(max(s, -1.0), 1.0)) for s in sines)
    psi_lo, psi_hi = max(psi_lo, -AWAY_FROM_OWN_GOAL_RAD), min(psi_hi, AWAY_FROM_OWN_GOAL_RAD)
    offset = relative(base, attack_rad)  # the goal's centre, from the attack direction
    return max(psi_lo - offset, -PAST_SPAN_RAD), min(psi_hi - offset, PAST_SPAN_RAD)
