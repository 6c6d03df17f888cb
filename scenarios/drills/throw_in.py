"""The throw-in drill: after the kick-off the ball rolls out over a side line; how long until the
throw-in's first touch?

Each trial is a refereed match (short pauses before the kick-off, :data:`QUICK_PAUSES`) of
``--players`` per side, cut short. :data:`ROLL_AFTER_S` into the first PLAYING, the drill puts the
ball at a seeded spot :data:`ROLL_FROM_Y_M` from the middle line, anywhere along the field within
:data:`ROLL_MAX_X_M` of the middle, rolling at :data:`ROLL_MPS` toward the nearer side line, where
the players can see it go out, as in a match. The referee then does what it does in a match: the
ball goes out, and after its wait it is put back on the throw-in rule's spot (``throw_in`` event).
Nobody touched it, so that spot is where it went out; a player that did not see its team touch the
ball guesses the other team did and expects it 1 m off that until it is put back. The trial ends at
the first touch after that, or ``--seconds`` after the put-back; a match asks for that touch within
:data:`QUICK_S`.

Outcomes: ``home`` or ``away`` (who touched first), ``none`` (no touch in time), ``in`` (the ball
never went out: a robot stopped it). A trial records where the ball was rolled from and put back,
the wait to the first touch, who touched, and how far each team's nearest robot stood from the spot
at the put-back (the world's ground truth). The summary: the share of put-backs touched within
:data:`QUICK_S` with its 95% Wilson interval, the median and longest wait.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np

from match.events import EventKind
from match.game import Match, MatchConfig
from match.protocol import GameState, Side, roster
from match.protocol.actions import Action
from match.referee import RefereeConfig
from scenarios.common.statistics import wilson_interval
from scenarios.drills.base import Drill, Role, Score, Setup, parameter
from scenarios.drills.records import TrialRecord
from scenarios.drills.summaries import counts, interval, median, seconds, values

QUICK_PAUSES = {"initial_seconds": 0.2, "ready_seconds": 0.4, "set_seconds": 0.2}  # s: to the kick-off at once
ROLL_AFTER_S = 0.5  # the ball is rolled out this long into the first PLAYING (s) ...
ROLL_FROM_Y_M = 1.2  # ... from this far off the middle line (m) ...
ROLL_MAX_X_M = 2.0  # ... anywhere within this of the halfway line along the field (m) ...
ROLL_MPS = 1.2  # ... at this speed toward the nearer side line (m/s): out within about a second
NOT_PUT_BACK_S = 8.0  # no put-back this long after the roll: a robot kept the ball in (s)
QUICK_S = 10.0  # a first touch within this of the put-back is in time (s)
NEAREST_DECIMALS = 3
WAIT_DECIMALS = 2


class ThrowInWatch:
    """Rolls the ball out once the play has begun, then watches the match's events (see the module).

    ``throw_in``: the put-back (time s, spot m, each team's nearest robot's distance m), None until
    then; ``outcome``: (outcome, wait s or None, the robot that touched or None), None until known.
    """

    def __init__(self, roll_xy: tuple[float, float], limit_s: float):
        self.roll_xy, self.limit_s = roll_xy, limit_s
        self.rolled_s: float | None = None
        self.throw_in: dict | None = None
        self.outcome: tuple[str, float | None, str | None] | None = None
        self._playing_since: float | None = None

    def decided(self, match: Match, actions: Mapping[str, Action | None]) -> None:
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
                x, y = event.details["x"], event.details["y"]
                self.throw_in = {"time_s": event.time_s, "x": x, "y": y, **nearest(match, x, y)}
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


def nearest(match: Match, x: float, y: float) -> dict[str, float]:
    """Each team's nearest robot's distance (m) from (x, y), from the world's ground truth."""
    distances: dict[str, float] = {}
    for robot in match.agent_names:
        pose = match.world.robot_pose(robot)
        side = robot.split("_")[0]
        distances[side] = min(distances.get(side, math.inf), math.hypot(pose.x - x, pose.y - y))
    return {f"{side}_nearest_m": round(d, NEAREST_DECIMALS) for side, d in distances.items()}


class ThrowIn(Drill):
    """The ball rolls out over a side line after the kick-off: how long until the throw-in's first touch."""

    ROLES = (Role("home", "the home team's policy, attacking +x first"), Role("away", "the away team's policy"))
    OUTCOMES = ("home", "away", "none", "in")
    COLUMNS = {"roll_x": float, "roll_y": float, "spot_x": float, "spot_y": float, "wait_s": float, "toucher": str,
               "home_nearest_m": float, "away_nearest_m": float}

    players: int = parameter(4, 1, 4, "", "players per side")
    seconds: int = parameter(20, 1, 600, "s", "how long after the put-back a trial waits for a touch")

    def setup(self, rng: np.random.Generator) -> Setup:
        roll_x = float(rng.uniform(-ROLL_MAX_X_M, ROLL_MAX_X_M))
        roll_y = ROLL_FROM_Y_M if rng.random() < 0.5 else -ROLL_FROM_Y_M
        config = MatchConfig(referee=RefereeConfig(**QUICK_PAUSES), home_players=self.players,
                             away_players=self.players)
        roles = {str(a): "home" if a.side is Side.HOME else "away" for a in roster(self.players, self.players)}
        return Setup(config, roles, {"roll_x": roll_x, "roll_y": roll_y})

    def observe(self, setup: Setup) -> ThrowInWatch:
        return ThrowInWatch((setup.facts["roll_x"], setup.facts["roll_y"]), float(self.seconds))

    def score(self, setup: Setup, observer: ThrowInWatch) -> Score:
        outcome, wait_s, toucher = observer.outcome or ("none", None, None)
        put_back = observer.throw_in or {}
        return Score(outcome, {
            "spot_x": put_back.get("x"), "spot_y": put_back.get("y"),
            "wait_s": None if wait_s is None else round(wait_s, WAIT_DECIMALS), "toucher": toucher,
            "home_nearest_m": put_back.get("home_nearest_m"), "away_nearest_m": put_back.get("away_nearest_m"),
        })

    def summarize(self, records: Sequence[TrialRecord]) -> dict:
        put_back = [r for r in records if r.values["spot_x"] is not None]
        waits = values(put_back, "wait_s")
        quick = sum(1 for wait in waits if wait <= QUICK_S)
        return {
            "trials": len(records),
            "outcomes": counts(records, self.OUTCOMES),
            "put_back": len(put_back),
            "touched_within_10_s": quick,
            "touched_within_10_s_ci95": wilson_interval(quick, len(put_back)) if put_back else None,
            "wait_s_median": median(waits),
            "wait_s_max": max(waits) if waits else None,
        }

    def headline(self, summary: dict) -> str:
        if summary["touched_within_10_s_ci95"] is None:
            return f"outcomes {summary['outcomes']}; no put-backs"
        return (f"outcomes {summary['outcomes']}; {summary['touched_within_10_s']}/{summary['put_back']} touched "
                f"within 10 s ({interval(summary['touched_within_10_s_ci95'])}), median wait "
                f"{seconds(summary['wait_s_median'])}, longest {seconds(summary['wait_s_max'])}")
