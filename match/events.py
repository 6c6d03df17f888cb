"""The match event log: one frozen record per thing that happened."""

from __future__ import annotations

import enum
from dataclasses import dataclass, field


class EventKind(enum.Enum):
    STATE = "state"  # the game state changed
    KICKOFF = "kickoff"
    TOUCH = "touch"
    GOAL = "goal"
    GOAL_DISALLOWED = "goal_disallowed"  # the kick-off-shot rule
    BALL_OUT = "ball_out"
    THROW_IN = "throw_in"  # the ball placed back after it went out
    FALL = "fall"
    ROBOT_PLACED = "robot_placed"  # not in a legal position when SET began
    ROBOT_REPLACED = "robot_replaced"  # left the carpet or down too long: back at the side line
    HALF_TIME = "half_time"
    SHOOTOUT_KICK = "shootout_kick"
    END = "end"
    FAULT = "fault"  # an agent's policy failed (recorded by the runner)


@dataclass(frozen=True)
class MatchEvent:
    """``details`` holds plain JSON values only (str, int, float, bool, lists, dicts)."""

    time_s: float
    kind: EventKind
    details: dict = field(default_factory=dict)

    def to_json(self) -> dict:
        return {"time_s": round(self.time_s, 3), "kind": self.kind.value, **self.details}
