"""Getting free when a commanded turn does not turn (agents.behavior.tactics.unjam)."""

from __future__ import annotations

import pytest

from agents.behavior.tactics.unjam import ESCAPE_S, WINDOW_S, Unjammer

STEP_S = 0.04
CLEAR = (2.5, 2.5, 2.5, 2.5)


def turned(measured_share: float, seconds: float = WINDOW_S, commanded: float = -1.0) -> Unjammer:
    unjam = Unjammer(STEP_S)
    for _ in range(round(seconds / STEP_S)):
        unjam.observe(commanded, measured_share * commanded)
    return unjam


def test_a_turn_the_gyro_does_not_feel_is_a_jam_and_the_robot_steps_back_for_a_while() -> None:
    unjam = turned(0.05)
    steps = [unjam.escape(CLEAR) for _ in range(round(ESCAPE_S / STEP_S) + 1)]
    assert all(walk is not None and walk[0] < 0.0 and walk[2] == 0.0 for walk in steps[:-1])
    assert steps[-1] is None and unjam.escapes == 1  # then it plays on, its window started afresh


@pytest.mark.parametrize("unjam", [turned(0.6), turned(0.05, seconds=WINDOW_S / 2), turned(0.0, commanded=-0.2)],
                         ids=["it turns", "not for long yet", "hardly a turn asked"])
def test_no_escape_while_it_turns_or_has_not_tried_long_or_hard(unjam: Unjammer) -> None:
    assert unjam.escape(CLEAR) is None


def test_it_steps_toward_the_side_with_more_room() -> None:
    left_blocked = (0.2, 1.0, 0.2, 1.0)  # upper-left, upper-right, lower-left, lower-right (m)
    assert turned(0.0).escape(left_blocked)[1] < 0.0
    assert turned(0.0).escape(tuple(reversed(left_blocked)))[1] > 0.0
