"""Penalty shoot-out bookkeeping: who kicks next, and when the shoot-out is decided.

Five kicks each, taken alternately, then (if asked) sudden death in pairs of kicks, up
to ``max_sudden_death_rounds`` pairs. Pure Python; the referee does the placing.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from match.protocol.ids import Side


@dataclass(frozen=True)
class ShootoutKick:
    side: Side
    kicker: str
    keeper: str | None
    scored: bool
    reason: str  # "goal", "out", "time", "stopped"


@dataclass
class ShootoutTally:
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
