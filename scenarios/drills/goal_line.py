"""The goal-line drill: the ball at the own goal line beside the goal, an attacker and a defender near it.

Each trial is a free-play match of three robots.
The home team defends the blue goal (x = -3 m): ``home_0``, its goalkeeper, stands on its line and
``home_1``, both played by the defenders' policy, :data:`DEFENDER_M` from the ball; ``away_1``, the
attacker, :data:`ATTACKER_M` from it; each on the field side of the ball, in a seeded direction within
:data:`START_SPREAD_DEG` of the one straight into the field, at least :data:`APART_M` apart. The robots
face the ball and are told where they stand (a team agent's pose is set where the drill put it, as
the kick-off does). The ball lies at a seeded spot :data:`BALL_DEPTH_M` from the goal line and
:data:`BALL_Y_M` from the field's long axis, beside the goal: the place of the team agent's clear-line
set play (``[clear_line]`` in ``agents/team/params.toml``; ``--defenders team:FILE.toml`` plays it on).

A trial ends when the ball is in the home goal (``goal``: against the defenders), over the home end
line beside it (``out_end``: the attackers' restart near the goal), over a side line or the far end
line (``out_side``), out of the danger zone in front of the goal (``cleared``: :data:`DANGER_DEPTH_M`
from the goal line or :data:`DANGER_HALF_WIDTH_M` from the long axis), or after ``--seconds``
(``none``). The summary: the goals' share with its 95% Wilson interval.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from match.protocol import Pose2D, kickoff_pose
from scenarios.common.statistics import wilson_interval
from scenarios.drills.ball_drill import BallDrill
from scenarios.drills.base import Role, Setup
from scenarios.drills.records import TrialRecord
from scenarios.drills.summaries import counts, interval, percent
from world.field import FIELD, GoalColor

KEEPER, DEFENDER, ATTACKER = "home_0", "home_1", "away_1"
BALL_DEPTH_M = (0.05, 0.3)  # the ball this far in front of the home goal line (m) ...
BALL_Y_M = (0.9, 1.5)  # ... and this far from the long axis, on a seeded side (m)
DEFENDER_M = 0.9  # home_1 this far from the ball (m) ...
ATTACKER_M = 1.2  # ... away_1 this far (m) ...
START_SPREAD_DEG = 80.0  # ... each within this of straight into the field from the ball ...
APART_M = 0.5  # ... and the two at least this far apart (m)
DANGER_DEPTH_M = 1.0  # a ball this far from the home goal line (m) ...
DANGER_HALF_WIDTH_M = 1.6  # ... or this far from the long axis is out of danger (m)


def start_near(ball: tuple[float, float], reach_m: float, angle_rad: float) -> Pose2D:
    """A pose ``reach_m`` from the ball, ``angle_rad`` off the direction straight into the home team's
    attacking half (field frame), facing the ball."""
    x, y = ball[0] + reach_m * math.cos(angle_rad), ball[1] + reach_m * math.sin(angle_rad)
    return Pose2D(x, y, math.atan2(ball[1] - y, ball[0] - x))


class GoalLine(BallDrill, seconds=20):
    """The ball at the own goal line beside the goal, an attacker and a defender near it: goals against."""

    ROLES = (Role("defenders", "home_0's and home_1's policy: keeper, defender"), Role("attacker", "away_1's policy"))
    OUTCOMES = ("goal", "out_end", "out_side", "cleared", "none")

    def setup(self, rng: np.random.Generator) -> Setup:
        side = 1.0 if rng.uniform() < 0.5 else -1.0
        ball = (-FIELD.half_length + float(rng.uniform(*BALL_DEPTH_M)), side * float(rng.uniform(*BALL_Y_M)))
        spread = math.radians(START_SPREAD_DEG)
        while True:
            near, far = (start_near(ball, reach, float(rng.uniform(-spread, spread)))
                         for reach in (DEFENDER_M, ATTACKER_M))
            if math.dist((near.x, near.y), (far.x, far.y)) >= APART_M:
                break
        starts = {KEEPER: kickoff_pose(0, False, GoalColor.BLUE), DEFENDER: near, ATTACKER: far}
        return self.free_play(starts, ball, {KEEPER: "defenders", DEFENDER: "defenders", ATTACKER: "attacker"},
                              placed=True)

    def judge(self, x: float, y: float) -> str | None:
        beyond = FIELD.half_length + FIELD.ball_radius
        if x < -beyond:
            return "goal" if abs(y) < FIELD.goal_inner_width / 2 else "out_end"
        if abs(y) > FIELD.half_width + FIELD.ball_radius or x > beyond:
            return "out_side"
        if x + FIELD.half_length > DANGER_DEPTH_M or abs(y) > DANGER_HALF_WIDTH_M:
            return "cleared"
        return None

    def summarize(self, records: Sequence[TrialRecord]) -> dict:
        outcomes = counts(records, self.OUTCOMES)
        return {
            "trials": len(records),
            "outcomes": outcomes,
            "goal_share": outcomes["goal"] / len(records) if records else None,
            "goal_share_ci95": wilson_interval(outcomes["goal"], len(records)),
        }

    def headline(self, summary: dict) -> str:
        return (f"goals against {summary['outcomes']['goal']} of {summary['trials']} "
                f"({percent(summary['goal_share'])}, 95% interval {interval(summary['goal_share_ci95'])}); "
                f"outcomes {summary['outcomes']}")
