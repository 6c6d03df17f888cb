"""How a pair's matches flowed: goals in play, own goals, and how soon restarts were played.

From the match statistics of each played match (:mod:`match.statistics`), pooled over the
pair's matches: how many matches had a goal in playing time (the penalty shoot-out's goals
are not goals), the goals and own goals, and every kick-off's and throw-in's wait to the
first touch (``restart_waits_s``): how many there were, how many took longer than
:data:`match.statistics.RESTART_SLOW_S`, their median and the longest. Matches recorded
without the waits (by an older version) count for the goals only; the restart figures are
None when no match has them.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from match.statistics import RESTART_SLOW_S, SIDES
from scenarios.common.statistics import median


@dataclass(frozen=True)
class GameFlow:
    """A pair's game flow (module docstring); times in seconds."""

    matches: int
    matches_with_goals: int
    goals: int
    own_goals: int
    restarts: int | None
    restarts_slow: int | None
    restart_median_s: float | None
    restart_max_s: float | None

    def to_json(self) -> dict:
        return {"matches": self.matches, "matches_with_goals": self.matches_with_goals, "goals": self.goals,
                "own_goals": self.own_goals, "restarts": self.restarts, "restarts_slow": self.restarts_slow,
                "restart_slow_s": RESTART_SLOW_S, "restart_median_s": self.restart_median_s,
                "restart_max_s": self.restart_max_s}


def game_flow(records: Sequence[Mapping], first: str, second: str) -> GameFlow:
    """The flow of the played matches between entrants ``first`` and ``second`` (either at home)."""
    pair = {first, second}
    played = [r["statistics"] for r in records
              if r["status"] == "ok" and r.get("statistics") and {r["home_entrant"], r["away_entrant"]} == pair]
    goals_per_match = [sum(int(s[side]["goals"]) for side in SIDES) for s in played]
    waits = [float(w) for s in played for w in (s.get("restart_waits_s") or ())]
    timed = any("restart_waits_s" in s for s in played)
    return GameFlow(
        matches=len(played),
        matches_with_goals=sum(1 for goals in goals_per_match if goals > 0),
        goals=sum(goals_per_match),
        own_goals=sum(int(s[side]["own_goals"]) for s in played for side in SIDES),
        restarts=len(waits) if timed else None,
        restarts_slow=sum(1 for w in waits if w > RESTART_SLOW_S) if timed else None,
        restart_median_s=round(median(waits), 3) if waits else None,
        restart_max_s=max(waits) if waits else None,
    )
