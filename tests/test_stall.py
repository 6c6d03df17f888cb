"""Getting a stalled ball moving (agents.behavior.tactics.stall)."""

from __future__ import annotations

import math

import pytest

from agents.behavior.tactics.stall import GAP_S, PUSH_S, STALL_BALL_M, STALL_S, StallWatch, push_allowed

STEP_S = 0.04


def _watch(watch: StallWatch, seconds: float, ball_xy: tuple[float, float] = (2.99, -0.67), near: bool = True,
           wobble_m: float = 0.0) -> list[bool]:
    """Calls the watch every control step for ``seconds``; the believed ball wobbles by ``wobble_m``."""
    steps = round(seconds / STEP_S)
    return [watch.pushing(k * STEP_S, (ball_xy[0] + wobble_m * math.sin(k), ball_xy[1]), near)
            for k in range(steps)]


def test_a_ball_that_stays_at_the_striker_for_the_stall_time_is_pushed_for_the_push_time() -> None:
    watch = StallWatch()
    pushes = _watch(watch, STALL_S + PUSH_S + 1.0, wobble_m=0.4 * STALL_BALL_M)
    first = pushes.index(True)
    assert first * STEP_S == pytest.approx(STALL_S, abs=2 * STEP_S)
    assert sum(pushes) * STEP_S == pytest.approx(PUSH_S, abs=2 * STEP_S)
    assert all(pushes[first:first + round(PUSH_S / STEP_S) - 1])
    assert watch.pushes == 1


def test_a_moving_ball_a_far_ball_or_a_gap_in_the_watch_is_no_stall() -> None:
    moving = StallWatch()
    steps = round(3 * STALL_S / STEP_S)
    assert not any(moving.pushing(k * STEP_S, (k * STEP_S * 0.1, 0.0), True) for k in range(steps))  # 0.1 m/s
    assert not any(_watch(StallWatch(), 3 * STALL_S, near=False))
    gaps = StallWatch()
    calls = [gaps.pushing(k * (GAP_S + STEP_S), (1.0, 1.0), True) for k in range(round(3 * STALL_S / GAP_S))]
    assert not any(calls)  # called only now and then (another role in between): it begins again each time


def test_the_watch_begins_again_after_a_push() -> None:
    watch = StallWatch()
    pushes = _watch(watch, 2 * STALL_S + 2 * PUSH_S + 1.0)
    assert watch.pushes == 2
    starts = [k for k in range(1, len(pushes)) if pushes[k] and not pushes[k - 1]]
    assert (starts[1] - starts[0]) * STEP_S == pytest.approx(STALL_S + PUSH_S, abs=2 * STEP_S)


@pytest.mark.parametrize("attack", [1.0, -1.0])
def test_a_push_goes_only_away_from_the_own_goal(attack: float) -> None:
    toward_opponents = 0.0 if attack > 0 else math.pi
    assert push_allowed(toward_opponents, attack)
    assert push_allowed(toward_opponents + math.radians(70.0), attack)
    assert push_allowed(toward_opponents - math.radians(70.0), attack)
    assert not push_allowed(toward_opponents + math.radians(100.0), attack)
    assert not push_allowed(toward_opponents + math.pi, attack)
