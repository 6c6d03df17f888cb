"""The penalty shoot-out: who kicks, where everyone stands, how a kick ends, and the tally.

Five kicks each, taken alternately, then (if asked) sudden death in pairs of kicks, up
to ``max_sudden_death_rounds`` pairs. Every kick is taken at :data:`SHOOTOUT_GOAL`.
:class:`PenaltyShootout` makes the shoot-out's decisions; the referee stays the state
machine that calls it, places what it says and logs the events. Positions are in the
field frame (:mod:`world.field`: metres, +x toward the yellow goal, theta CCW from +x).
"""

from __future__ import annotations

import enum
import math
from collections.abc import Sequence
from dataclasses import dataclass, field

from match.protocol.ids import AgentId, Side
from match.protocol.kickoff import GOALKEEPER_LINE_X_M, PENALTY_KICKER_BEHIND_BALL_M
from match.rules import ball_out, goal_crossed
from world.ball import BallState
from world.field import FIELD, GoalColor, Pose2D

SHOOTOUT_GOAL = GoalColor.YELLOW  # every shoot-out kick is taken at this goal
BALL_AT_REST_MPS = 0.02  # a ball slower than this (m/s, on the ground plane) is at rest
OFF_FIELD_Y_M = FIELD.carpet_half_width + 0.3  # |y| of the line where robots out of a kick wait
WAITING_FIRST_X_M = -2.5  # x of the first waiting robot ...
WAITING_SPACING_M = 0.6  # ... and the gap to the next, along +x


class ShootoutOutcome(enum.StrEnum):
    """How a shoot-out kick ended: the ``reason`` of its event (serializes as the plain value)."""

    GOAL = "goal"  # the ball crossed the shoot-out goal's line
    OUT = "out"  # the ball left the field elsewhere (or went into the other goal)
    TIME = "time"  # the attempt's time ran out
    STOPPED = "stopped"  # the kicker touched the ball and it then lay at rest long enough


@dataclass(frozen=True)
class ShootoutKick:
    """One kick taken: the kicking side, robot ids of kicker and keeper (None: no keeper)."""

    side: Side
    kicker: str
    keeper: str | None
    scored: bool
    reason: ShootoutOutcome


@dataclass
class ShootoutTally:
    """The kicks taken so far and whether that decides the shoot-out."""

    first: Side
    kicks_each: int = 5
    sudden_death: bool = True
    max_sudden_death_rounds: int = 5
    kicks: list[ShootoutKick] = field(default_factory=list)

    def taken(self, side: Side) -> int:
        return sum(1 for k in self.kicks if k.side is side)

    def goals(self, side: Side) -> int:
        return sum(1 for k in self.kicks if k.side is side and k.scored)

    @property
    def next_side(self) -> Side:
        return self.first if len(self.kicks) % 2 == 0 else self.first.other

    def record(self, kick: ShootoutKick) -> None:
        self.kicks.append(kick)

    def winner(self) -> Side | None:
        home, away = self.goals(Side.HOME), self.goals(Side.AWAY)
        return None if home == away else (Side.HOME if home > away else Side.AWAY)

    def is_over(self) -> bool:
        """Decided, or out of kicks (a draw when no sudden death or its rounds ran out)."""
        home_taken, away_taken = self.taken(Side.HOME), self.taken(Side.AWAY)
        home, away = self.goals(Side.HOME), self.goals(Side.AWAY)
        if home_taken <= self.kicks_each and away_taken <= self.kicks_each:
            home_left = self.kicks_each - home_taken
            away_left = self.kicks_each - away_taken
            if home > away + away_left or away > home + home_left:
                return True
            if home_left or away_left:
                return False
            if home != away:
                return True
            return not self.sudden_death or self.max_sudden_death_rounds == 0
        if home_taken != away_taken:
            return False  # a sudden-death pair is half taken
        if home != away:
            return True
        return home_taken - self.kicks_each >= self.max_sudden_death_rounds


@dataclass
class ShootoutAttempt:
    """The kick under way: robot ids of kicker and keeper, and what was seen of the ball (simulated s)."""

    side: Side
    kicker: str
    keeper: str | None
    start_s: float | None = None  # PLAYING began
    kicker_touched: bool = False
    rest_since_s: float | None = None

    @property
    def home_defends(self) -> GoalColor:
        """The goal the home team defends for this kick: the keeper's team defends :data:`SHOOTOUT_GOAL`."""
        return SHOOTOUT_GOAL.other if self.side is Side.HOME else SHOOTOUT_GOAL


@dataclass(frozen=True)
class ShootoutPlacement:
    """Where the referee puts the ball (x, y in m) and each robot (by id, in roster order) before a kick."""

    ball: tuple[float, float]
    robots: tuple[tuple[str, Pose2D], ...]


class PenaltyShootout:
    """The shoot-out's decisions for the robots ``agents`` (robot id = ``str(agent)``).

    ``attempt_seconds``: simulated time a kick may take from PLAYING on; ``rest_seconds``:
    how long a ball the kicker touched must lie at rest to end the kick.
    """

    def __init__(self, agents: Sequence[AgentId], tally: ShootoutTally, attempt_seconds: float, rest_seconds: float):
        self.agents = tuple(agents)
        self.tally = tally
        self.attempt_seconds = attempt_seconds
        self.rest_seconds = rest_seconds
        self.attempt: ShootoutAttempt | None = None

    def next_kick(self) -> ShootoutAttempt:
        """Start the next kick: the side due, its kicker and the other side's goalkeeper (player 0)."""
        side = self.tally.next_side
        keepers = [a for a in self.agents if a.side is side.other and a.player == 0]
        keeper = str(keepers[0]) if keepers else None
        self.attempt = ShootoutAttempt(side=side, kicker=self._kicker(side), keeper=keeper)
        return self.attempt

    def _kicker(self, side: Side) -> str:
        """Field players take turns (the goalkeeper kicks only in a team of one)."""
        players = [a for a in self.agents if a.side is side]
        field_players = [a for a in players if a.player != 0] or players
        return str(field_players[self.tally.taken(side) % len(field_players)])

    def placement(self) -> ShootoutPlacement:
        """Ball on the penalty mark, kicker behind it facing the goal, keeper on the goal line, others off the field."""
        sign = SHOOTOUT_GOAL.sign
        attempt = self.attempt
        facing_goal = 0.0 if sign > 0 else math.pi
        mark_x = sign * FIELD.penalty_mark_x
        robots = []
        waiting = 0
        for agent in self.agents:
            robot = str(agent)
            if robot == attempt.kicker:
                pose = Pose2D(mark_x - sign * PENALTY_KICKER_BEHIND_BALL_M, 0.0, facing_goal)
            elif robot == attempt.keeper:
                pose = Pose2D(sign * GOALKEEPER_LINE_X_M, 0.0, facing_goal + math.pi)
            else:
                pose = Pose2D(WAITING_FIRST_X_M + WAITING_SPACING_M * waiting, -OFF_FIELD_Y_M, math.pi / 2.0)
                waiting += 1
            robots.append((robot, pose))
        return ShootoutPlacement((mark_x, 0.0), tuple(robots))

    def begin(self, now: float) -> None:
        """The kick's PLAYING began at ``now`` (simulated s)."""
        self.attempt.start_s = now

    def holds(self, robot: str) -> bool:
        """Whether ``robot`` must stand still: everyone but the kicker and the keeper during a kick."""
        return self.attempt is not None and robot not in (self.attempt.kicker, self.attempt.keeper)

    def judge(self, ball: BallState, now: float) -> ShootoutKick | None:
        """Judge the kick under way after one control step (``now`` in simulated s).

        Returns None while it goes on; else the kick, recorded in the tally, and the
        attempt is over (call :meth:`next_kick` unless :meth:`ShootoutTally.is_over`).
        """
        attempt = self.attempt
        if ball.last_toucher == attempt.kicker:
            attempt.kicker_touched = True
        goal = goal_crossed(ball.x, ball.y, ball.z)
        outcome = None
        if goal is SHOOTOUT_GOAL:
            outcome = ShootoutOutcome.GOAL
        elif goal is not None or ball_out(ball.x, ball.y, ball.z) is not None:
            outcome = ShootoutOutcome.OUT
        elif now - attempt.start_s >= self.attempt_seconds - 1e-9:
            outcome = ShootoutOutcome.TIME
        elif ball.last_toucher is not None and attempt.kicker_touched:
            if math.hypot(ball.vx, ball.vy) < BALL_AT_REST_MPS:
                attempt.rest_since_s = attempt.rest_since_s if attempt.rest_since_s is not None else now
                if now - attempt.rest_since_s >= self.rest_seconds - 1e-9:
                    outcome = ShootoutOutcome.STOPPED
            else:
                attempt.rest_since_s = None
        if outcome is None:
            return None
        kick = ShootoutKick(attempt.side, attempt.kicker, attempt.keeper, outcome is ShootoutOutcome.GOAL, outcome)
        self.tally.record(kick)
        self.attempt = None
        return kick
