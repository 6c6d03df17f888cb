"""The shooting drill: one striker against one goalkeeper, the ball placed in the attacking half.

Each trial is a free-play match of two robots at their kick-off positions: ``home_1``, the striker,
at the defending team's position (-1, 0), facing the yellow goal it attacks, and ``away_0``, the
goalkeeper, on the yellow goal's line. The ball lies at a seeded spot :data:`BALL_X_M` into the
attacking half, at most :data:`BALL_Y_M` from the middle. A trial ends when the ball is in the goal
(``goal``), over the end line beside it (``wide``), over a side line (``out``), back past x =
:data:`CLEARED_X_M` (``cleared``), or after ``--seconds`` (``none``). The summary: the goals' share
with its 95% Wilson interval, the median time to a goal.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from match.protocol import kickoff_pose
from scenarios.common.statistics import wilson_interval
from scenarios.drills.ball_drill import BallDrill
from scenarios.drills.base import Role, Setup
from scenarios.drills.records import TrialRecord
from scenarios.drills.summaries import counts, interval, median, percent, values
from world.field import FIELD, GoalColor

STRIKER, KEEPER = "home_1", "away_0"
BALL_X_M = (0.8, 2.2)  # the ball's spot: this far into the attacking half (m) ...
BALL_Y_M = 1.2  # ... and at most this far from the middle (m)
CLEARED_X_M = -0.5  # a ball back past this line is cleared (m, field frame)


class Shooting(BallDrill, seconds=40):
    """A striker from its kick-off position shoots at a goalkeeper: goals with 95% intervals."""

    ROLES = (Role("striker", "home_1's policy, attacking the yellow goal"), Role("keeper", "away_0's policy, in goal"))
    OUTCOMES = ("goal", "wide", "out", "cleared", "none")

    def setup(self, rng: np.random.Generator) -> Setup:
        ball = (float(rng.uniform(*BALL_X_M)), float(rng.uniform(-BALL_Y_M, BALL_Y_M)))
        starts = {STRIKER: kickoff_pose(1, False, GoalColor.BLUE), KEEPER: kickoff_pose(0, False, GoalColor.YELLOW)}
        return self.free_play(starts, ball, {STRIKER: "striker", KEEPER: "keeper"})

    def judge(self, x: float, y: float) -> str | None:
        if x > FIELD.half_length + FIELD.ball_radius:
            return "goal" if abs(y) < FIELD.goal_inner_width / 2 else "wide"
        if abs(y) > FIELD.half_width + FIELD.ball_radius:
            return "out"
        return "cleared" if x < CLEARED_X_M else None

    def summarize(self, records: Sequence[TrialRecord]) -> dict:
        goals = sum(1 for r in records if r.outcome == "goal")
        return {
            "trials": len(records),
            "outcomes": counts(records, self.OUTCOMES),
            "goal_share": goals / len(records) if records else None,
            "goal_share_ci95": wilson_interval(goals, len(records)),
            "goal_time_median_s": median(values(records, "time_s", outcome="goal")),
        }

    def headline(self, summary: dict) -> str:
        return (f"goals {summary['outcomes']['goal']} of {summary['trials']} "
                f"({percent(summary['goal_share'])}, 95% interval {interval(summary['goal_share_ci95'])}); "
                f"outcomes {summary['outcomes']}")
