"""The match event log: one frozen record per thing that happened (times in simulated s)."""

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


class DisallowedReason(enum.StrEnum):
    """Why a goal was disallowed: the ``reason`` of a GOAL_DISALLOWED event."""

    KICKOFF_SHOT = "kickoff_shot"  # the kick-off team scored before the ball was played again (see the referee)


class ReplacedReason(enum.StrEnum):
    """Why a robot was put back at the side line: the ``reason`` of a ROBOT_REPLACED event."""

    OFF_CARPET = "off_carpet"
    FALLEN = "fallen"  # down longer than the referee's fallen limit


@dataclass(frozen=True)
class MatchEvent:
    """``details`` holds plain JSON values only (str, int, float, bool, lists, dicts).

    A reason enum (:class:`DisallowedReason`, :class:`ReplacedReason`,
    :class:`match.shootout.ShootoutOutcome`) goes in as its ``.value``: a plain str.
    """

    time_s: float
    kind: EventKind
    details: dict = field(default_factory=dict)

    def to_json(self) -> dict:
        return {"time_s": round(self.time_s, 3), "kind": self.kind.value, **self.details}
