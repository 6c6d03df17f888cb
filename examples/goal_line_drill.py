"""A goal-line drill: the ball at the own goal line beside the goal, an attacker and a defender near it.

Each trial is a free-play match (:mod:`match.free_play`: always PLAYING, no referee) of three robots.
The home team defends the blue goal (x = -3 m): ``home_0``, its goalkeeper, stands on its line and
``home_1``, both played by ``--defenders``, :data:`DEFENDER_M` from the ball; ``away_1``, played by
``--attacker``, :data:`ATTACKER_M` from it; each on the field side of the ball, in a seeded direction
within :data:`START_SPREAD_DEG` of the one straight into the field, at least :data:`APART_M` apart. The
robots face the ball and are told where they stand (the team agent's pose is set where the drill put
it, as the kick-off does). The ball lies at a seeded spot :data:`BALL_DEPTH_M` from the goal line and
:data:`BALL_Y_M` from the field's long axis, beside the goal: the place of the team agent's clear-line
set play (``[clear_line]`` in ``agents/team/params.toml``).

A trial ends when the ball is in the home goal (``goal``: against the defenders), over the home end
line beside it (``out_end``: the attackers' restart near the goal), over a side line or the far end
line (``out_side``), out of the danger zone in front of the goal (``cleared``: :data:`DANGER_DEPTH_M`
from the goal line or :data:`DANGER_HALF_WIDTH_M` from the long axis), or after ``--seconds`` (``none``). The world's ground truth decides the outcome; the policies see only
their observations. It prints one line per trial and writes ``results.json`` into ``--out`` (every
trial's ball spot, outcome and time; the goals' share with its 95% Wilson interval). The set play off
(as shipped) and on, the same seeds:

    python examples/goal_line_drill.py --trials 40 --seed 0 --out out/goal_line_off
    python examples/goal_line_drill.py --defenders team:on.toml --trials 40 --seed 0 --out out/goal_line_on

with ``on.toml`` holding ``[clear_line]`` and ``enabled = true``. Policies are built-in names or
``package.module:ClassName``, as for ``robotstadium match``.
"""

from __future__ import annotations

import argparse
import logging
import math
import sys
import time
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

from agents.policies import make_policy, policy_factory
from match.free_play import FreePlay
from match.game import Match, MatchConfig
from match.protocol import Pose2D, kickoff_pose
from match.runner import run_match
from scenarios.cli.arguments import int_in
from scenarios.common.io import write_json
from scenarios.tournament.statistics import wilson_interval
from world.field import FIELD, GoalColor

KEEPER, DEFENDER, ATTACKER = "home_0", "home_1", "away_1"
BALL_DEPTH_M = (0.05, 0.3)  # the ball this far in front of the home goal line ...
BALL_Y_M = (0.9, 1.5)  # ... and this far from the long axis, on a seeded side
DEFENDER_M = 0.9  # home_1 this far from the ball (it comes first) ...
ATTACKER_M = 1.2  # ... away_1 this far ...
START_SPREAD_DEG = 80.0  # ... each within this of straight into the field from the ball ...
APART_M = 0.5  # ... and the two at least this far apart
DANGER_DEPTH_M = 1.0  # a ball this far from the home goal line ...
DANGER_HALF_WIDTH_M = 1.6  # ... or this far from the long axis is out of danger
OUTCOMES = ("goal", "out_end", "out_side", "cleared", "none")


@dataclass(frozen=True)
class Trial:
    """One trial: its seed, the ball's spot (m, field frame), the outcome and when it came (s)."""

    seed: int
    ball_x: float
    ball_y: float
    outcome: str
    time_s: float


class Placed:
    """A policy told where the drill put its robot: a team agent's pose is set there at the reset (as at a
    kick-off); other policies play as they are."""

    def __init__(self, policy: Any, pose: Pose2D):
        self.policy, self.pose = policy, pose

    def reset(self, agent_id: str, seed: int) -> None:
        self.policy.reset(agent_id, seed)
        world = getattr(self.policy, "world", None)
        if world is not None:
            world.locator.reset(self.pose)

    def act(self, observation: Any) -> dict:
        return self.policy.act(observation)

    def think(self) -> None:
        think = getattr(self.policy, "think", None)
        if think is not None:
            think()


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
        beyond = FIELD.half_length + FIELD.ball_radius
        if ball.x < -beyond:
            self.outcome = ("goal" if abs(ball.y) < FIELD.goal_inner_width / 2 else "out_end", time_s)
        elif abs(ball.y) > FIELD.half_width + FIELD.ball_radius or ball.x > beyond:
            self.outcome = ("out_side", time_s)
        elif ball.x + FIELD.half_length > DANGER_DEPTH_M or abs(ball.y) > DANGER_HALF_WIDTH_M:
            self.outcome = ("cleared", time_s)
        elif time_s >= self.limit_s:
            self.outcome = ("none", time_s)
        return self.outcome is not None


def start_near(ball: tuple[float, float], reach_m: float, angle_rad: float) -> Pose2D:
    """A pose ``reach_m`` from the ball, ``angle_rad`` off the direction straight into the home team's
    attacking half (field frame), facing the ball."""
    x, y = ball[0] + reach_m * math.cos(angle_rad), ball[1] + reach_m * math.sin(angle_rad)
    return Pose2D(x, y, math.atan2(ball[1] - y, ball[0] - x))


def play_trial(defenders: str, attacker: str, seed: int, limit_s: float) -> Trial:
    rng = np.random.default_rng(seed)
    side = 1.0 if rng.uniform() < 0.5 else -1.0
    ball = (-FIELD.half_length + float(rng.uniform(*BALL_DEPTH_M)), side * float(rng.uniform(*BALL_Y_M)))
    spread = math.radians(START_SPREAD_DEG)
    while True:
        near, far = (start_near(ball, reach, float(rng.uniform(-spread, spread))) for reach in (DEFENDER_M, ATTACKER_M))
        if math.dist((near.x, near.y), (far.x, far.y)) >= APART_M:
            break
    starts = {KEEPER: kickoff_pose(0, False, GoalColor.BLUE), DEFENDER: near, ATTACKER: far}
    config = MatchConfig(free_play=FreePlay(tuple(starts.items()), ball_xy=ball))
    names = {KEEPER: defenders, DEFENDER: defenders, ATTACKER: attacker}
    policies = {robot: Placed(make_policy(names[robot]), pose) for robot, pose in starts.items()}
    referee = Referee(limit_s)
    run_match(config, policies, seed=seed, progress=False, observer=referee)
    outcome, time_s = referee.outcome or ("none", limit_s)
    return Trial(seed, round(ball[0], 3), round(ball[1], 3), outcome, round(time_s, 2))


def summarize(trials: list[Trial]) -> dict:
    outcomes = [t.outcome for t in trials]
    goals = outcomes.count("goal")
    return {
        "trials": len(trials),
        "outcomes": {name: outcomes.count(name) for name in OUTCOMES},
        "goal_share": goals / len(trials) if trials else None,
        "goal_share_ci95": wilson_interval(goals, len(trials)),
    }


def parse_args(argv: list[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--defenders", default="team", help="the home goalkeeper's and defender's policy (default team)")
    parser.add_argument("--attacker", default="team", help="the attacker's policy (default team)")
    parser.add_argument("--trials", type=int_in(1, 10_000), default=40, metavar="N", help="trials, 1-10000 (default 40)")
    parser.add_argument("--seed", type=int_in(0, 2**32 - 1 - 10_000), default=0, metavar="N",
                        help="the first trial's seed; trial k has seed + k (default 0)")
    parser.add_argument("--seconds", type=int_in(1, 600), default=20, metavar="S",
                        help="a trial's longest simulated time, 1-600 s (default 20)")
    parser.add_argument("--out", type=Path, default=None, help="write results.json here")
    args = parser.parse_args(argv)
    for flag, name in (("--defenders", args.defenders), ("--attacker", args.attacker)):
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
        trial = play_trial(args.defenders, args.attacker, args.seed + k, float(args.seconds))
        trials.append(trial)
        print(f"trial {k + 1}/{args.trials} seed {trial.seed}: ball ({trial.ball_x:+.2f}, {trial.ball_y:+.2f}) m: "
              f"{trial.outcome} at {trial.time_s:.1f} s", flush=True)
    summary = summarize(trials)
    low, high = summary["goal_share_ci95"]
    print(f"goals against {summary['outcomes']['goal']} of {len(trials)} ({summary['goal_share']:.0%}, 95% interval "
          f"{low:.0%}-{high:.0%}); outcomes {summary['outcomes']}; wall {time.perf_counter() - started:.0f} s")
    if args.out is not None:
        settings = {"defenders": args.defenders, "attacker": args.attacker, "trials": args.trials, "seed": args.seed,
                    "seconds": args.seconds}
        write_json(args.out / "results.json",
                   {"settings": settings, "summary": summary, "trials": [asdict(t) for t in trials]})
    return 0


if __name__ == "__main__":
    sys.exit(main())
