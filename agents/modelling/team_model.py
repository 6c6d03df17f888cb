"""The team model: what the teammates said over the radio, and the ball the team believes in.

Messages (:mod:`agents.radio`) are kept per teammate with the time they arrived;
after :data:`MESSAGE_TIMEOUT_S` a teammate is forgotten (fallen silent, penalized or
gone). The team ball is the freshest and most certain estimate among the robot's own and
its teammates' (field frame).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from agents.modelling.ball_model import ROLL_DECAY_S, BallEstimate
from agents.radio import TeamMessage

MESSAGE_TIMEOUT_S = 2.0
BALL_TIMEOUT_S = 4.0  # a ball older than this is no ball
AGE_WEIGHT_M_PER_S = 0.5  # one second of age counts as much as 0.5 m of sigma


@dataclass(frozen=True)
class Teammate:
    """A teammate as its last message described it, ``age_s`` seconds ago."""

    message: TeamMessage
    age_s: float


class TeamModel:
    def __init__(self, own_player: int):
        self.own_player = own_player
        self._heard: dict[int, tuple[TeamMessage, float]] = {}

    def hear(self, message: TeamMessage, now_s: float) -> None:
        if message.player != self.own_player:
            self._heard[message.player] = (message, now_s)

    def silent_for_s(self, now_s: float) -> float:
        """Seconds since any teammate was last heard (``now_s`` itself when none ever was: the own clock
        starts at the reset)."""
        return now_s - max((heard_s for _, heard_s in self._heard.values()), default=0.0)

    def teammates(self, now_s: float) -> tuple[Teammate, ...]:
        """The teammates heard within :data:`MESSAGE_TIMEOUT_S`, by player number."""
        fresh = []
        for player in sorted(self._heard):
            message, heard_s = self._heard[player]
            if now_s - heard_s <= MESSAGE_TIMEOUT_S:
                fresh.append(Teammate(message, now_s - heard_s))
        return tuple(fresh)

    def team_ball(
        self, own: BallEstimate | None, now_s: float, max_age_s: float = BALL_TIMEOUT_S,
        teammates: tuple[Teammate, ...] | None = None,
    ) -> tuple[BallEstimate, int] | None:
        """The best ball estimate in the field frame and whose it is (a player number), or None.

        Sightings older than ``max_age_s`` (and than :data:`BALL_TIMEOUT_S`) count for nothing:
        after a throw-in, for example, every sighting from before it shows a ball that is gone.
        ``teammates``: :meth:`teammates` at ``now_s`` if the caller has it already."""
        max_age_s = min(max_age_s, BALL_TIMEOUT_S)
        candidates: list[tuple[float, int, BallEstimate]] = []
        if own is not None and own.age_s <= max_age_s:
            candidates.append((_score(own), self.own_player, own))
        for mate in self.teammates(now_s) if teammates is None else teammates:
            m = mate.message
            if m.ball_xy is None or m.fallen:
                continue
            age = m.ball_age_s + mate.age_s
            if age > max_age_s:
                continue
            # Let the reported ball roll on for the time the message took.
            decay = math.exp(-mate.age_s / ROLL_DECAY_S)
            roll = ROLL_DECAY_S * (1.0 - decay)
            estimate = BallEstimate(m.ball_xy[0] + m.ball_velocity[0] * roll, m.ball_xy[1] + m.ball_velocity[1] * roll,
                                    m.ball_velocity[0] * decay, m.ball_velocity[1] * decay, m.ball_sigma_m, age)
            candidates.append((_score(estimate), m.player, estimate))
        if not candidates:
            return None
        _, player, best = min(candidates, key=lambda c: (c[0], c[1]))
        return best, player


def _score(ball: BallEstimate) -> float:
    return ball.sigma_m + AGE_WEIGHT_M_PER_S * ball.age_s
