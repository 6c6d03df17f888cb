"""The duel drill: two strikers race from their kick-off positions to a ball near the centre spot.

Each trial is a free-play match of two robots at the defending team's kick-off positions of their
halves: ``home_1`` at (-1, 0) attacking the yellow goal (+x), and ``away_1`` at (+1, 0) attacking
the blue one. The ball lies at a seeded spot within ``--spread`` of the middle along the field (0:
both robots are as far from it) and :data:`BALL_Y_M` across. A trial ends when the ball has gone
:data:`WIN_X_M` toward one goal (``home`` or ``away`` won the duel), over a side line (``out``), or
after ``--seconds`` (``none``). At every kick's start the other robot's distance from the ball is
measured: a kick with it within :data:`CONTESTED_M` is contested. The summary: each side's wins with
their 95% Wilson intervals, the kicks and the contested kicks of each side. Swap ``--home`` and
``--away`` to cancel what the sides' starts favour.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np

from match.game import Match
from match.protocol import kickoff_pose
from match.protocol.actions import Action
from scenarios.common.statistics import wilson_interval
from scenarios.drills.ball_drill import BallDrill, BallWatch, Judge
from scenarios.drills.base import Role, Score, Setup, parameter
from scenarios.drills.records import TrialRecord
from scenarios.drills.summaries import counts, interval
from world.field import FIELD, GoalColor

HOME, AWAY = "home_1", "away_1"
SIDES = (("home", HOME), ("away", AWAY))
WIN_X_M = 1.5  # the ball this far from the middle toward a goal: the duel is won (m)
BALL_Y_M = 0.8  # the ball lies at most this far from the middle across the field (m)
CONTESTED_M = 0.5  # a kick with the other robot this near the ball is contested (m)


class DuelWatch(BallWatch):
    """Ends a trial on its outcome (see the module) and counts each robot's kicks, and those contested."""

    def __init__(self, judge: Judge, limit_s: float):
        super().__init__(judge, limit_s)
        self.kicks = dict.fromkeys((HOME, AWAY), 0)
        self.contested = dict.fromkeys((HOME, AWAY), 0)
        self._kicking: dict[str, bool] = {}

    def decided(self, match: Match, actions: Mapping[str, Action | None]) -> None:
        ball = match.world.ball()
        for robot, action in actions.items():
            motion = getattr(action, "motion", None)
            kicking = motion is not None and motion.is_kick
            if kicking and not self._kicking.get(robot, False):
                other = match.world.robot_pose(AWAY if robot == HOME else HOME)
                self.kicks[robot] += 1
                self.contested[robot] += round(math.hypot(other.x - ball.x, other.y - ball.y), 3) < CONTESTED_M
            self._kicking[robot] = kicking


class Duel(BallDrill, seconds=30):
    """Two strikers race from their kick-off positions to a ball near the centre spot: who wins it."""

    ROLES = (Role("home", "home_1's policy, attacking +x"), Role("away", "away_1's policy, attacking -x"))
    OUTCOMES = ("home", "away", "out", "none")
    COLUMNS = {**BallDrill.COLUMNS, "home_kicks": int, "away_kicks": int, "home_contested": int, "away_contested": int}
    spread: float = parameter(0.3, 0.0, 0.9, "m", "the ball lies within this of the middle along the field")

    def setup(self, rng: np.random.Generator) -> Setup:
        ball = (float(rng.uniform(-self.spread, self.spread)), float(rng.uniform(-BALL_Y_M, BALL_Y_M)))
        starts = {HOME: kickoff_pose(1, False, GoalColor.BLUE), AWAY: kickoff_pose(1, False, GoalColor.YELLOW)}
        return self.free_play(starts, ball, {HOME: "home", AWAY: "away"})

    def judge(self, x: float, y: float) -> str | None:
        if x > WIN_X_M:
            return "home"
        if x < -WIN_X_M:
            return "away"
        return "out" if abs(y) > FIELD.half_width + FIELD.ball_radius else None

    def observe(self, setup: Setup) -> DuelWatch:
        return DuelWatch(self.judge, float(self.seconds))

    def score(self, setup: Setup, observer: DuelWatch) -> Score:
        score = observer.score()
        kicks = {f"{side}_kicks": observer.kicks[robot] for side, robot in SIDES}
        contested = {f"{side}_contested": observer.contested[robot] for side, robot in SIDES}
        return Score(score.outcome, {**score.figures, **kicks, **contested})

    def summarize(self, records: Sequence[TrialRecord]) -> dict:
        outcomes = counts(records, self.OUTCOMES)
        return {
            "trials": len(records),
            "outcomes": outcomes,
            "home_wins_ci95": wilson_interval(outcomes["home"], len(records)),
            "away_wins_ci95": wilson_interval(outcomes["away"], len(records)),
            "kicks": {side: sum(r.values[f"{side}_kicks"] for r in records) for side, _ in SIDES},
            "kicks_contested": {side: sum(r.values[f"{side}_contested"] for r in records) for side, _ in SIDES},
        }

    def headline(self, summary: dict) -> str:
        return (f"outcomes {summary['outcomes']}; home wins 95% interval {interval(summary['home_wins_ci95'])}, "
                f"away {interval(summary['away_wins_ci95'])}; kicks {summary['kicks']}, "
                f"contested {summary['kicks_contested']}")
