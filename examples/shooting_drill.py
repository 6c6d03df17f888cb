"""A shooting drill: one striker against one goalkeeper, the ball placed in the attacking half.

Each trial is a free-play match (:mod:`match.free_play`: always PLAYING, no referee) with two
robots at their kick-off positions: ``home_1``, played by ``--striker``, at the defending
team's position (-1, 0), facing the yellow goal it attacks, and ``away_0``, played by
``--keeper``, on the yellow goal's line. The ball lies at a seeded spot 0.8-2.2 m into the
attacking half, at most 1.2 m from the middle. A trial ends when the ball is in the goal
(``goal``), over the end line beside it (``wide``), over a side line (``out``), back past
x = -0.5 m (``cleared``), or after ``--seconds`` (``none``). The referee's ground truth decides
the outcome; the policies see only their observations.

It prints one line per trial and writes ``results.json`` into ``--out`` (every trial's ball
spot, outcome and time; the goals' share with its 95% Wilson interval; the median time to a
goal). Used for the shot window of the team agents (``docs/design.md``, section 5.3):

    python examples/shooting_drill.py --trials 40 --seed 100 --out out/drill

Policies are built-in names or ``package.module:ClassName``, as for ``robotstadium match``.
"""

from __future__ import annotations

import argparse
import logging
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
from scenarios.cli.arguments import int_in
from scenarios.common.io import write_json
from scenarios.tournament.statistics import wilson_interval
from world.field import FIELD, GoalColor

STRIKER = "home_1"
KEEPER = "away_0"
BALL_X_M = (0.8, 2.2)  # the ball's spot: this far into the attacking half ...
BALL_Y_M = 1.2  # ... and at most this far from the middle
CLEARED_X_M = -0.5  # a ball back past this line is cleared


@dataclass(frozen=True)
class Trial:
    """One trial: its seed, the ball's spot (m, field frame), the outcome and when it came (s)."""

    seed: int
    ball_x: float
    ball_y: float
    outcome: str
    time_s: float


class Referee:
    """Ends a trial on its outcome (see the module), from the world's ground truth."""

    def __init__(self, limit_s: float):
        self.limit_s = limit_s
        self.outcome: tuple[str, float] | None = None

    def decided(self, match: Match, actions) -> None:
        pass

    def done(self, match: Match) -> bool:
        ball = match.world.ball()
        time_s = match.step_index * match.config.world.physics.control_step_s
        if ball.x > FIELD.half_length + FIELD.ball_radius:
            self.outcome = ("goal" if abs(ball.y) < FIELD.goal_inner_width / 2 else "wide", time_s)
        elif abs(ball.y) > FIELD.half_width + FIELD.ball_radius:
            self.outcome = ("out", time_s)
        elif ball.x < CLEARED_X_M:
            self.outcome = ("cleared", time_s)
        elif time_s >= self.limit_s:
            self.outcome = ("none", time_s)
        return self.outcome is not None


def play_trial(striker: str, keeper: str, seed: int, limit_s: float) -> Trial:
    rng = np.random.default_rng(seed)
    ball_x, ball_y = float(rng.uniform(*BALL_X_M)), float(rng.uniform(-BALL_Y_M, BALL_Y_M))
    starts = ((STRIKER, kickoff_pose(1, False, GoalColor.BLUE)), (KEEPER, kickoff_pose(0, False, GoalColor.YELLOW)))
    config = MatchConfig(free_play=FreePlay(starts, ball_xy=(ball_x, ball_y)))
    referee = Referee(limit_s)
    run_match(config, {STRIKER: make_policy(striker), KEEPER: make_policy(keeper)}, seed=seed, progress=False,
              observer=referee)
    outcome, time_s = referee.outcome or ("none", limit_s)
    return Trial(seed, round(ball_x, 3), round(ball_y, 3), outcome, round(time_s, 2))


def summarize(trials: list[Trial]) -> dict:
    outcomes = [t.outcome for t in trials]
    goals = outcomes.count("goal")
    goal_times = [t.time_s for t in trials if t.outcome == "goal"]
    return {
        "trials": len(trials),
        "outcomes": {name: outcomes.count(name) for name in ("goal", "wide", "out", "cleared", "none")},
        "goal_share": goals / len(trials) if trials else None,
        "goal_share_ci95": wilson_interval(goals, len(trials)),
        "goal_time_median_s": float(np.median(goal_times)) if goal_times else None,
    }


def parse_args(argv: list[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--striker", default="team", help="the striker's policy (default team)")
    parser.add_argument("--keeper", default="team", help="the goalkeeper's policy (default team)")
    parser.add_argument("--trials", type=int_in(1, 10_000), default=40, metavar="N", help="trials, 1-10000 (default 40)")
    parser.add_argument("--seed", type=int_in(0, 2**32 - 1 - 10_000), default=0, metavar="N",
                        help="the first trial's seed; trial k has seed + k (default 0)")
    parser.add_argument("--seconds", type=int_in(1, 600), default=40, metavar="S",
                        help="a trial's longest simulated time, 1-600 s (default 40)")
    parser.add_argument("--out", type=Path, default=None, help="write results.json here")
    args = parser.parse_args(argv)
    for flag, name in (("--striker", args.striker), ("--keeper", args.keeper)):
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
        trial = play_trial(args.striker, args.keeper, args.seed + k, float(args.seconds))
        trials.append(trial)
        print(f"trial {k + 1}/{args.trials} seed {trial.seed}: ball ({trial.ball_x:+.2f}, {trial.ball_y:+.2f}) m: "
              f"{trial.outcome} at {trial.time_s:.1f} s", flush=True)
    summary = summarize(trials)
    low, high = summary["goal_share_ci95"]
    print(f"goals {summary['outcomes']['goal']} of {len(trials)} ({summary['goal_share']:.0%}, 95% interval "
          f"{low:.0%}-{high:.0%}); outcomes {summary['outcomes']}; wall {time.perf_counter() - started:.0f} s")
    if args.out is not None:
        settings = {"striker": args.striker, "keeper": args.keeper, "trials": args.trials, "seed": args.seed,
                    "seconds": args.seconds}
        write_json(args.out / "results.json",
                   {"settings": settings, "summary": summary, "trials": [asdict(t) for t in trials]})
    return 0


if __name__ == "__main__":
    sys.exit(main())
