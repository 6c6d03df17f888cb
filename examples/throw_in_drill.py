"""A throw-in drill: after the kick-off, the ball rolls out over a side line; how long until the throw-in's first touch?

Each trial is a refereed match (short pauses before the kick-off) between ``--home`` and
``--away`` with ``--players`` per side, cut short. :data:`ROLL_AFTER_S` into the first
PLAYING, the drill puts the ball at a seeded spot :data:`ROLL_FROM_Y_M` from the middle
line, anywhere along the field within :data:`ROLL_MAX_X_M` of the middle, rolling at
:data:`ROLL_MPS` toward the nearer side line, where the players can see it go out, as in a
match. The referee then does what it does in a match: the ball goes out, and after its wait
it is put back on the throw-in rule's spot (``throw_in`` event). Nobody touched it, so that
spot is where it went out; a player that did not see its team touch the ball guesses the
other team did and expects it 1 m off that until it is put back (in a match the guess is
often right). The trial ends at the first touch after that, or ``--seconds`` after the
put-back; a match asks for that touch within 10 s.

Outcomes: ``home`` or ``away`` (who touched first), ``none`` (no touch in time), ``in``
(the ball never went out: a robot stopped it). The output lists every trial, the share of
put-backs touched within 10 s with its 95% Wilson interval, and the median wait; the
world's ground truth gives where each team's nearest robot stood at the put-back.

    python examples/throw_in_drill.py --home team --away team --trials 40 --out out/throw_in
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

from agents.policies import make_policy
from match.events import EventKind
from match.game import Match, MatchConfig
from match.protocol import GameState, Side, roster
from match.referee import RefereeConfig
from match.runner import run_match
from scenarios.cli.arguments import int_in, policy_name
from scenarios.common.io import write_json
from scenarios.tournament.statistics import wilson_interval

QUICK_PAUSES = {"initial_seconds": 0.2, "ready_seconds": 0.4, "set_seconds": 0.2}  # s: to the kick-off at once
ROLL_AFTER_S = 0.5  # the ball is rolled out this long into the first PLAYING
ROLL_FROM_Y_M = 1.2  # ... from this far off the middle line (m) ...
ROLL_MAX_X_M = 2.0  # ... anywhere within this of the halfway line along the field ...
ROLL_MPS = 1.2  # ... at this speed toward the nearer side line: out within about a second
NOT_PUT_BACK_S = 8.0  # no put-back this long after the roll: a robot kept the ball in
QUICK_S = 10.0  # a first touch within this of the put-back: in time
OUTCOMES = ("home", "away", "none", "in")


@dataclass(frozen=True)
class Trial:
    """One trial: its seed, where the ball was rolled from (m, field frame), where the referee put it back
    (None: it never went out), the outcome, the wait from the put-back to the first touch (s; None: none),
    who touched, and each team's nearest robot's distance from the spot at the put-back (m)."""

    seed: int
    roll_x: float
    roll_y: float
    spot_x: float | None
    spot_y: float | None
    outcome: str
    wait_s: float | None
    toucher: str | None
    home_nearest_m: float | None
    away_nearest_m: float | None


class Referee:
    """Rolls the ball out once the play has begun, then watches the match's events (see the module)."""

    def __init__(self, roll_xy: tuple[float, float], limit_s: float):
        self.roll_xy, self.limit_s = roll_xy, limit_s
        self.rolled_s: float | None = None
        self.throw_in: dict | None = None  # the put-back: time, spot, nearest robots
        self.outcome: tuple[str, float | None, str | None] | None = None
        self._playing_since: float | None = None

    def decided(self, match: Match, actions) -> None:
        now = match.world.time_s
        if match.state is GameState.PLAYING and self._playing_since is None:
            self._playing_since = now
        if self.rolled_s is None and self._playing_since is not None and now - self._playing_since >= ROLL_AFTER_S:
            x, y = self.roll_xy
            match.world.place_ball(x, y, 0.0, math.copysign(ROLL_MPS, y))
            self.rolled_s = now

    def done(self, match: Match) -> bool:
        if self.outcome is not None:
            return True
        now = match.world.time_s
        for event in match.events:
            if self.throw_in is None and event.kind is EventKind.THROW_IN and self.rolled_s is not None \
                    and event.time_s >= self.rolled_s:
                self.throw_in = {"time_s": event.time_s, "x": event.details["x"], "y": event.details["y"],
                                 **_nearest(match, event.details["x"], event.details["y"])}
            elif self.throw_in is not None and event.kind is EventKind.TOUCH \
                    and event.time_s >= self.throw_in["time_s"]:
                robot = event.details.get("robot")
                self.outcome = (str(robot).split("_")[0], event.time_s - self.throw_in["time_s"], robot)
                return True
        if self.throw_in is not None and now - self.throw_in["time_s"] >= self.limit_s:
            self.outcome = ("none", None, None)
        elif self.throw_in is None and self.rolled_s is not None and now - self.rolled_s >= NOT_PUT_BACK_S:
            self.outcome = ("in", None, None)
        return self.outcome is not None


def _nearest(match: Match, x: float, y: float) -> dict:
    """Each team's nearest robot's distance (m) from (x, y), from the world's ground truth (evaluation only)."""
    distances: dict[str, float] = {}
    for robot in match.agent_names:
        pose = match.world.robot_pose(robot)
        side = robot.split("_")[0]
        distances[side] = min(distances.get(side, math.inf), math.hypot(pose.x - x, pose.y - y))
    return {f"{side}_nearest_m": round(d, 3) for side, d in distances.items()}


def play_trial(home: str, away: str, players: int, seed: int, limit_s: float) -> Trial:
    rng = np.random.default_rng(seed)
    roll = (float(rng.uniform(-ROLL_MAX_X_M, ROLL_MAX_X_M)), ROLL_FROM_Y_M if rng.random() < 0.5 else -ROLL_FROM_Y_M)
    config = MatchConfig(referee=RefereeConfig(**QUICK_PAUSES), home_players=players, away_players=players)
    policies = {str(a): make_policy(home if a.side is Side.HOME else away) for a in roster(players, players)}
    referee = Referee(roll, limit_s)
    run_match(config, policies, seed=seed, progress=False, observer=referee)
    outcome, wait_s, toucher = referee.outcome or ("none", None, None)
    put_back = referee.throw_in or {}
    return Trial(seed, round(roll[0], 3), roll[1], put_back.get("x"), put_back.get("y"), outcome,
                 None if wait_s is None else round(wait_s, 2), toucher, put_back.get("home_nearest_m"),
                 put_back.get("away_nearest_m"))


def summarize(trials: list[Trial]) -> dict:
    put_back = [t for t in trials if t.spot_x is not None]
    quick = sum(1 for t in put_back if t.wait_s is not None and t.wait_s <= QUICK_S)
    waits = [t.wait_s for t in put_back if t.wait_s is not None]
    outcomes = [t.outcome for t in trials]
    return {
        "trials": len(trials),
        "outcomes": {name: outcomes.count(name) for name in OUTCOMES},
        "put_back": len(put_back),
        "touched_within_10_s": quick,
        "touched_within_10_s_ci95": wilson_interval(quick, len(put_back)) if put_back else None,
        "wait_s_median": float(np.median(waits)) if waits else None,
        "wait_s_max": max(waits) if waits else None,
    }


def parse_args(argv: list[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--home", type=policy_name, default="team",
                        help="the home team's policy, attacking +x first (default team)")
    parser.add_argument("--away", type=policy_name, default="team", help="the away team's policy (default team)")
    parser.add_argument("--players", type=int_in(1, 4), default=4, metavar="N", help="players per side, 1-4 (default 4)")
    parser.add_argument("--trials", type=int_in(1, 10_000), default=40, metavar="N", help="trials, 1-10000 (default 40)")
    parser.add_argument("--seed", type=int_in(0, 2**32 - 1 - 10_000), default=0, metavar="N",
                        help="the first trial's seed; trial k has seed + k (default 0)")
    parser.add_argument("--seconds", type=int_in(1, 600), default=20, metavar="S",
                        help="how long after the put-back a trial waits for a touch, 1-600 s (default 20)")
    parser.add_argument("--out", type=Path, default=None, help="write results.json here")
    return parser.parse_args(argv)


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    logging.basicConfig(level=logging.WARNING, format="%(levelname)s %(name)s: %(message)s")
    started = time.perf_counter()
    trials = []
    for k in range(args.trials):
        trial = play_trial(args.home, args.away, args.players, args.seed + k, float(args.seconds))
        trials.append(trial)
        where = "never out" if trial.spot_x is None else (
            f"put back at ({trial.spot_x:+.2f}, {trial.spot_y:+.2f}), nearest home {trial.home_nearest_m:.2f} m, "
            f"away {trial.away_nearest_m:.2f} m")
        wait = "" if trial.wait_s is None else f" after {trial.wait_s:.1f} s ({trial.toucher})"
        print(f"trial {k + 1}/{args.trials} seed {trial.seed}: rolled from ({trial.roll_x:+.2f}, {trial.roll_y:+.2f}); "
              f"{where}: {trial.outcome}{wait}", flush=True)
    summary = summarize(trials)
    interval = summary["touched_within_10_s_ci95"]
    within = "no put-backs" if interval is None else (
        f"{summary['touched_within_10_s']}/{summary['put_back']} touched within 10 s "
        f"({interval[0]:.0%}-{interval[1]:.0%}), median wait {_seconds(summary['wait_s_median'])}, "
        f"longest {_seconds(summary['wait_s_max'])}")
    print(f"outcomes {summary['outcomes']}; {within}; wall {time.perf_counter() - started:.0f} s")
    if args.out is not None:
        settings = {"home": args.home, "away": args.away, "players": args.players, "trials": args.trials,
                    "seed": args.seed, "seconds": args.seconds}
        write_json(args.out / "results.json",
                   {"settings": settings, "summary": summary, "trials": [asdict(t) for t in trials]})
    return 0


def _seconds(value: float | None) -> str:
    return "none" if value is None else f"{value:.1f} s"


if __name__ == "__main__":
    sys.exit(main())
