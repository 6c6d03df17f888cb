"""Game-control data: what the referee broadcasts to every robot every 0.5 s.

The broadcast itself names teams by side (home/away); :meth:`GameControlData.view_for`
turns it into one robot's view (own/opponent), which is what observations carry.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

from match.protocol.ids import Side
from world.field import GoalColor
from world.teams import TeamColor


class GameState(enum.IntEnum):
    """The SPL game states, in their order in a half."""

    INITIAL = 0
    READY = 1
    SET = 2
    PLAYING = 3
    FINISHED = 4


class SecondaryState(enum.IntEnum):
    NORMAL = 0
    PENALTY_SHOOTOUT = 1


class KickOff(enum.IntEnum):
    """Who kicks off, from one robot's point of view."""

    OWN_TEAM = 0
    OPPONENT = 1
    NONE = 2


class DropIn(enum.IntEnum):
    """Which team put the ball out before the last throw-in (the SPL's drop-in team), from one
    robot's point of view; NONE when nobody touched it or there was no throw-in this half."""

    OWN_TEAM = 0
    OPPONENT = 1
    NONE = 2


@dataclass(frozen=True)
class GameControlData:
    """One broadcast of the referee.

    ``seconds_remaining`` is the playing time left in the half (the clock runs only in
    PLAYING). ``half`` is 1 or 2 (the shoot-out keeps 2). ``home_defends`` is the goal the
    home team defends now (it changes at half-time and between shoot-out kicks).
    ``score`` counts goals of normal play; ``shootout_score`` the shoot-out's.
    ``drop_in_team`` is the side that put the ball out before the last throw-in (None: nobody
    touched it, or no throw-in yet this half); ``seconds_since_drop_in`` the simulated time
    since the referee put the ball back (inf when there was none this half).
    """

    state: GameState
    secondary: SecondaryState
    kickoff: Side | None
    score: tuple[int, int]  # (home, away)
    shootout_score: tuple[int, int]  # (home, away)
    seconds_remaining: float
    half: int
    home_color: TeamColor
    home_defends: GoalColor
    time_s: float  # simulated time of the broadcast
    drop_in_team: Side | None = None
    seconds_since_drop_in: float = math.inf

    def color_of(self, side: Side) -> TeamColor:
        return self.home_color if side is Side.HOME else self.home_color.other

    def defended_goal(self, side: Side) -> GoalColor:
        return self.home_defends if side is Side.HOME else self.home_defends.other

    def view_for(self, side: Side) -> GameControlView:
        if self.kickoff is None:
            kickoff = KickOff.NONE
        else:
            kickoff = KickOff.OWN_TEAM if self.kickoff is side else KickOff.OPPONENT
        if self.drop_in_team is None:
            drop_in = DropIn.NONE
        else:
            drop_in = DropIn.OWN_TEAM if self.drop_in_team is side else DropIn.OPPONENT
        own, opponent = (0, 1) if side is Side.HOME else (1, 0)
        return GameControlView(
            state=self.state,
            secondary=self.secondary,
            kickoff=kickoff,
            own_score=self.score[own],
            opponent_score=self.score[opponent],
            own_shootout_score=self.shootout_score[own],
            opponent_shootout_score=self.shootout_score[opponent],
            seconds_remaining=self.seconds_remaining,
            half=self.half,
            team_color=self.color_of(side),
            defended_goal=self.defended_goal(side),
            drop_in_team=drop_in,
            seconds_since_drop_in=self.seconds_since_drop_in,
        )


@dataclass(frozen=True)
class GameControlView:
    """Game-control data as one robot reads it: its own team first."""

    state: GameState
    secondary: SecondaryState
    kickoff: KickOff
    own_score: int
    opponent_score: int
    own_shootout_score: int
    opponent_shootout_score: int
    seconds_remaining: float
    half: int
    team_color: TeamColor
    defended_goal: GoalColor
    drop_in_team: DropIn = DropIn.NONE
    seconds_since_drop_in: float = math.inf  # since the last throw-in's placement (inf: none this half)

    @property
    def attacked_goal(self) -> GoalColor:
        return self.defended_goal.other
