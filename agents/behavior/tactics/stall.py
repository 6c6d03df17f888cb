"""Getting a stalled ball moving: a striker at the ball whose skills cannot agree on a touch
can stand by it for good (a ball wedged at a post, the striker turning one way to orbit to an
aim it cannot kick along and back the other way to face the ball, while the robots around wait).

The striker watches where it believes the ball and whether it is near it; when the ball has
stayed within :data:`STALL_BALL_M` of one place for :data:`STALL_S` with the robot within
:data:`STALL_NEAR_M` all along, the ball is stalled, and for :data:`PUSH_S` the robot walks on
through it the way it faces (:func:`agents.behavior.skills.push`), if that way leads away from
its own goal (:func:`push_allowed`). Field frame, m, s and rad.
"""

from __future__ import annotations

import math

STALL_NEAR_M = 0.35  # ours: a striker this near its ball ...
STALL_BALL_M = 0.25  # ... believed within this of one place (a ball among feet is seen 0.1-0.2 m apart) ...
STALL_S = 8.0  # ... this long has stalled the ball (orbiting half round it at 0.5 rad/s takes 6.3 s) ...
PUSH_S = 2.0  # ... and walks through it this long (0.4 m at the push's 0.2 m/s)
GAP_S = 0.2  # a watch not called for this long (another role, no ball in sight) begins again
AWAY_FROM_OWN_GOAL_RAD = math.radians(80.0)  # ours: the push's way within this of the attack direction


class StallWatch:
    """Watches one striker's ball (one call a control step) and says when to push it loose."""

    def __init__(self) -> None:
        self._anchor: tuple[float, float] | None = None  # where the ball lay when the watch began
        self._since_s = 0.0
        self._last_s = -math.inf  # when it was last called
        self._push_until_s = -math.inf
        self.pushes = 0  # times it pushed a stalled ball (statistics)

    def pushing(self, now_s: float, ball_xy: tuple[float, float], near: bool) -> bool:
        """Whether to push the ball believed at ``ball_xy`` now (``near``: the robot is within
        :data:`STALL_NEAR_M` of it). A push, once begun, lasts :data:`PUSH_S`; a call after a gap
        of :data:`GAP_S` or more begins the watch again."""
        gap = now_s - self._last_s >= GAP_S
        self._last_s = now_s
        if now_s < self._push_until_s and not gap:
            return True
        if not near or gap:
            self._anchor = None
            return False
        if self._anchor is None or math.dist(self._anchor, ball_xy) > STALL_BALL_M:
            self._anchor, self._since_s = ball_xy, now_s
            return False
        if now_s - self._since_s < STALL_S:
            return False
        self._push_until_s = now_s + PUSH_S
        self._anchor = None
        self.pushes += 1
        return True


def push_allowed(heading_rad: float, attack: float) -> bool:
    """Whether a push along ``heading_rad`` (field frame) goes away from the own goal: within
    :data:`AWAY_FROM_OWN_GOAL_RAD` of the attack direction (``attack`` +1: toward +x)."""
    attack_rad = 0.0 if attack > 0 else math.pi
    return abs(math.remainder(heading_rad - attack_rad, math.tau)) <= AWAY_FROM_OWN_GOAL_RAD
