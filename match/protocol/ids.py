"""Agent ids: ``home_0 .. home_3`` and ``away_0 .. away_3``; player 0 is the goalkeeper."""

from __future__ import annotations

import enum
from dataclasses import dataclass

MAX_PLAYERS_PER_TEAM = 4


class Side(enum.Enum):
    """The two teams of a match, named by who they are, not by colour (colours swap)."""

    HOME = "home"
    AWAY = "away"

    @property
    def other(self) -> Side:
        return Side.AWAY if self is Side.HOME else Side.HOME


@dataclass(frozen=True, order=True)
class AgentId:
    """One player: its side and its number (0 is the goalkeeper)."""

    side: Side
    player: int

    def __str__(self) -> str:
        return f"{self.side.value}_{self.player}"

    @property
    def is_goalkeeper(self) -> bool:
        return self.player == 0

    @classmethod
    def parse(cls, agent: object) -> AgentId:
        """The id of ``"home_2"``-like text; ValueError naming the text otherwise."""
        if isinstance(agent, AgentId):
            return agent
        if isinstance(agent, str):
            side, _, number = agent.partition("_")
            if side in ("home", "away") and number.isdigit() and int(number) < MAX_PLAYERS_PER_TEAM:
                return cls(Side(side), int(number))
        raise ValueError(
            f"agent id {agent!r} is not one of home_0..home_{MAX_PLAYERS_PER_TEAM - 1}, "
            f"away_0..away_{MAX_PLAYERS_PER_TEAM - 1}"
        )


def roster(home_players: int, away_players: int) -> tuple[AgentId, ...]:
    """The agents of a match with the given team sizes (1-4 each), home first."""
    for side, count in (("home", home_players), ("away", away_players)):
        if not isinstance(count, int) or not 1 <= count <= MAX_PLAYERS_PER_TEAM:
            raise ValueError(f"{side} players = {count!r}; expected an integer in [1, {MAX_PLAYERS_PER_TEAM}]")
    return tuple(AgentId(Side.HOME, p) for p in range(home_players)) + tuple(
        AgentId(Side.AWAY, p) for p in range(away_players)
    )
