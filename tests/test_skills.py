"""The walk-to skill: a far target off to the side or behind is stepped toward while turning."""

from __future__ import annotations

import math

import pytest

from agents.behavior import skills
from match.protocol import WALK_HIGH, WALK_LOW, Motion, Pose2D


@pytest.mark.parametrize("bearing_deg", [-170.0, -90.0, -45.0, 40.0, 90.0, 135.0, 180.0])
def test_a_far_target_off_the_heading_is_stepped_toward_while_turning_to_it(bearing_deg: float) -> None:
    bearing = math.radians(bearing_deg)
    pose = Pose2D(0.5, -0.3, 0.4)
    target = Pose2D(pose.x + 2.0 * math.cos(pose.theta + bearing), pose.y + 2.0 * math.sin(pose.theta + bearing), 0.0)
    motion, (vx, vy, omega) = skills.walk_to(pose, target)
    assert motion is Motion.WALK
    assert all(lo <= v <= hi for v, lo, hi in zip((vx, vy, omega), WALK_LOW, WALK_HIGH))
    assert math.copysign(1.0, omega) == math.copysign(1.0, math.remainder(bearing, math.tau))  # turns toward it
    speed = math.hypot(vx, vy)
    assert speed >= min(-WALK_LOW[0], WALK_HIGH[1]) - 1e-9  # as fast as the limits allow that way
    assert math.atan2(vy, vx) == pytest.approx(math.remainder(bearing, math.tau), abs=1e-9)  # straight at it


def test_the_step_toward_a_bearing_lies_on_the_walk_limits() -> None:
    assert skills.toward(0.0) == pytest.approx((WALK_HIGH[0], 0.0))
    assert skills.toward(math.pi / 2) == pytest.approx((0.0, WALK_HIGH[1]))
    assert skills.toward(math.pi) == pytest.approx((WALK_LOW[0], 0.0))
    vx, vy = skills.toward(math.radians(-45.0))
    assert (vx / WALK_HIGH[0]) ** 2 + (vy / WALK_HIGH[1]) ** 2 == pytest.approx(1.0)


def test_a_far_target_ahead_is_walked_to_at_full_speed_and_a_near_one_stepped_to() -> None:
    pose = Pose2D(0.0, 0.0, 0.0)
    motion, walk = skills.walk_to(pose, Pose2D(2.0, 0.1, 0.0))
    steer = skills.TURN_GAIN_PER_S * math.atan2(0.1, 2.0)
    assert motion is Motion.WALK and walk == pytest.approx((WALK_HIGH[0], 0.0, steer))
    motion, (vx, vy, _) = skills.walk_to(pose, Pose2D(0.0, -0.4, 0.0))
    assert motion is Motion.WALK and vx == pytest.approx(0.0) and vy < 0.0
