"""A duel drill: two strikers race from their kick-off positions to a ball near the centre spot.

Each trial is a free-play match (:mod:`match.free_play`: always PLAYING, no referee) with two
robots at the defending team's kick-off positions of their halves: ``home_1``, played by
``--home``, at (-1, 0) attacking the yellow goal (+x), and ``away_1``, played by ``--away``, at
(+1, 0) attacking the blue one. The ball lies at a seeded spot within ``--spread`` of the
middle along the field (0: both robots are as far from it) and 0.8 m across. A trial ends when
the ball has gone :data:`WIN_X_M` toward one goal (``home`` or ``away`` won the duel), over a
side line (``out``), or after ``--seconds`` (``none``). The world's ground truth decides the
outcome and is recorded at every kick (where the other robot stood: evaluation only); the
policies see only their observations.

It prints one line per trial and writes ``results.json`` into ``--out`` (every trial's ball
spot, outcome, time and kicks; each side's wins with their 95% Wilson interval; the kicks
made with the other robot within :data:`CONTESTED_M` of the ball). Swap ``--home`` and
``--away`` to cancel what the sides' starts favour:

    python examples/duel_drill.py --home team --away mypackage.player:Player --trials 40 --out out/duel

Policies are built-in names or ``package.module:ClassName``, as for ``robotstadium match``.
"""

from __future__ import annotations

import argparse
import logging
import math
import sys
import time
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from agents.policies import make_policy, policy_factory
from match.free_play import FreePlay
from match.game import Match, MatchConfig
from match.protocol import kickoff_pose
from match.runner import run_match
from scenarios.cli.arguments import int_in, number_in
from scenarios.common.io import write_json
from scenarios.tournament.statistics import wilson_interval
from world.field import FIELD, GoalColor

HOME, AWAY = "home_1", "away_1"
WIN_X_M = 1.5  # the ball this far from the middle toward a goal: the duel is won
BALL_Y_M = 0.8  # the ball lies at most this far from the middle across the field
CONTESTED_M = 0.5  # a kick with the other robot this near the ball is contested
OUTCOMES = ("home", "away", "out", "none")


@dataclass(frozen=True)
class Kick:
    """A kick's start: who, when (s), and the other robot's distance from the ball then (m)."""

    robot: str
    time_s: float
    other_distance_m: float


@dataclass(frozen=True)
class Trial:
    """One trial: its seed, the ball's spot (m, field frame), the outcome, when it came (s), the kicks."""

    seed: int
    ball_x: float
    ball_y: float
    outcome: str
    time_s: float
    kicks: tuple[Kick, ...]


class Referee:
    """Ends a trial on its outcome (see the module) and records every kick, from the world's ground truth."""

    def __init__(self, limit_s: float):
        self.limit_s = limit_s
        self.outcome: tuple[str, float] | None = None
        self.kicks: list[Kick] = []
        self._kicking: dict[str, bool] = {}

    def decided(self, match: Match, actions) -> None:
        ball = match.world.ball()
        for robot, action in actions.items():
            motion = getattr(action, "motion", None)
            kicking = motion is not None and motion.is_kick
            if kicking and not self._kicking.get(robot, False):
                other = match.world.robot_pose(AWAY if robot == HOME else HOME)
                self.kicks.append(Kick(robot, round(self._time_s(match), 2),
                                       round(math.hypot(other.x - ball.x, other.y - ball.y), 3)))
            self._kicking[robot] = kicking

    def done(self, match: Match) -> bool:
        ball = match.world.ball()
        time_s = self._time_s(match)
        if ball.x > WIN_X_M:
            self.outcome = ("home", time_s)
        elif ball.x < -WIN_X_M:
            self.outcome = ("away", time_s)
        elif abs(ball.y) > FIELD.half_width + FIELD.ball_radius:
            self.outcome = ("out", time_s)
        elif time_s >= self.limit_s:
            self.outcome = ("none", time_s)
        return self.outcome is not None

    @staticmethod
    def _time_s(match: Match) -> float:
        return match.step_index * match.config.world.physics.control_step_s


def play_trial(home: str, away: str, seed: int, limit_s: float, spread_m: float) -> Trial:
    rng = np.random.default_rng(seed)
    ball_x, ball_y = float(rng.uniform(-spread_m, spread_m)), float(rng.uniform(-BALL_Y_M, BALL_Y_M))
    starts = ((HOME, kickoff_pose(1, False, GoalColor.BLUE)), (AWAY, kickoff_pose(1, False, GoalColor.YELLOW)))
    config = MatchConfig(free_play=FreePlay(starts, ball_xy=(ball_x, ball_y)))
    referee = Referee(limit_s)
    run_match(config, {HOME: make_policy(home), AWAY: make_policy(away)}, seed=seed, progress=False,
              observer=referee)
    outcome, time_s = referee.outcome or ("none", limit_s)
    return Trial(seed, round(ball_x, 3), round(ball_y, 3), outcome, round(time_s, 2), tuple(referee.kicks))


def summarize(trials: list[Trial]) -> dict:
    outcomes = [t.outcome for t in trials]
    kicks = [k for t in trials for k in t.kicks]
    return {
        "trials": len(trials),
        "outcomes": {name: outcomes.count(name) for name in OUTCOMES},
        "home_wins_ci95": wilson_interval(outcomes.count("home"), len(trials)),
        "away_wins_ci95": wilson_interval(outcomes.count("away"), len(trials)),
        "kicks": {side: sum(1 for k in kicks if k.robot == robot) for side, robot in (("home", HOME), ("away", AWAY))},
        "kicks_contested": {side: sum(1 for k in kicks if k.robot == robot and k.other_distance_m < CONTESTED_M)
                            for side, robot in (("home", HOME), ("away", AWAY))},
    }


def parse_args(argv: list[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--home", default="team", help="home_1's policy, attacking +x (default team)")
    parser.add_argument("--away", default="team", help="away_1's policy, attacking -x (default team)")
    parser.add_argument("--trials", type=int_in(1, 10_000), default=40, metavar="N", help="trials, 1-10000 (default 40)")
    parser.add_argument("--seed", type=int_in(0, 2**32 - 1 - 10_000), default=0, metavar="N",
                        help="the first trial's seed; trial k has seed + k (default 0)")
    parser.add_argument("--seconds", type=int_in(1, 600), default=30, metavar="S",
                        help="a trial's longest simulated time, 1-600 s (default 30)")
    parser.add_argument("--spread", type=number_in(0.0, 0.9), default=0.3, metavar="M",
                        help="the ball lies within this of the middle along the field, 0-0.9 m (default 0.3)")
    parser.add_argument("--out", type=Path, default=None, help="write results.json here")
    args = parser.parse_args(argv)
    for flag, name in (("--home", args.home), ("--away", args.away)):
        try:
            policy_factory(name)
        except ValueError as error:
            parser.error(f"{flag}: {error}")
    return args


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    logging.basicConfig(level=logging.WARNING, format="%(levelname)s %(name)s: %(message)s")
    started = time.perf_counter()
    trials = []
    for k in range(args.trials):
        trial = play_trial(args.home, args.away, args.seed + k, float(args.seconds), args.spread)
        trials.append(trial)
        contested = sum(1 for kick in trial.kicks if kick.other_distance_m < CONTESTED_M)
        print(f"trial {k + 1}/{args.trials} seed {trial.seed}: ball ({trial.ball_x:+.2f}, {trial.ball_y:+.2f}) m: "
              f"{trial.outcome} at {trial.time_s:.1f} s; {len(trial.kicks)} kicks, {contested} contested", flush=True)
    summary = summarize(trials)
    print(f"outcomes {summary['outcomes']}; home wins 95% interval {_percent(summary['home_wins_ci95'])}, away "
          f"{_percent(summary['away_wins_ci95'])}; kicks {summary['kicks']}, contested {summary['kicks_contested']}; "
          f"wall {time.perf_counter() - started:.0f} s")
    if args.out is not None:
        settings = {"home": args.home, "away": args.away, "trials": args.trials, "seed": args.seed,
                    "seconds": args.seconds, "spread": args.spread}
        write_json(args.out / "results.json",
                   {"settings": settings, "summary": summary, "trials": [asdict(t) for t in trials]})
    return 0


def _percent(interval: tuple[float, float]) -> str:
    return f"{interval[0]:.0%}-{interval[1]:.0%}"


if __name__ == "__main__":
    sys.exit(main())
