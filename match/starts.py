"""Where an episode starts: the kick-off, random poses, or a penalty kick.

Positions are in the field frame (:mod:`world.field`: metres, +x toward the yellow goal,
theta rad CCW from +x). Every start but the kick-off places the robots and the ball after the
referee's start and lets play begin at once (:meth:`match.referee.Referee.play_on`): no
kick-off, no pauses before it.
"""

from __future__ import annotations

import enum
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from match.errors import MatchConfigError, shown
from match.protocol.ids import AgentId, Side
from match.protocol.kickoff import GOALKEEPER_LINE_X_M, PENALTY_KICKER_BEHIND_BALL_M
from world.field import FIELD, GoalColor, Pose2D

RANDOM_MARGIN_M = 0.3  # random robots and the ball lie this far inside the field's lines ...
RANDOM_SPACING_M = 0.5  # ... and this far apart
RANDOM_TRIES = 100  # draws per item before the last one is taken whatever its spacing
WAITING_Y_M = -(FIELD.half_width + 0.35)  # robots out of a penalty wait on this line (on the carpet) ...
WAITING_FIRST_X_M = -2.4  # ... from this x on ...
WAITING_SPACING_M = 0.6  # ... this far apart


class Start(enum.StrEnum):
    """How an episode starts.

    - ``kickoff``: the referee's kick-off (robots at their kick-off poses, the pauses, then play).
    - ``random``: every robot and the ball at uniform spots inside the field's lines, apart from
      each other, robots at uniform headings; play at once.
    - ``penalty``: one attacker (home's last player) behind the ball on the away team's penalty
      mark, facing the goal; one keeper (``away_0``) on its goal line; everyone else standing
      outside the side line (:data:`WAITING_Y_M`), facing the field; play at once.
    """

    KICKOFF = "kickoff"
    RANDOM = "random"
    PENALTY = "penalty"

    @classmethod
    def of(cls, value: object) -> Start:
        """``value`` (a :class:`Start` or its name) as a Start; a :class:`MatchConfigError` naming it otherwise."""
        if isinstance(value, str):
            try:
                return cls(value)
            except ValueError:
                pass
        raise MatchConfigError(f"start = {shown(value)} is invalid; expected one of {[s.value for s in cls]}")


@dataclass(frozen=True)
class Placement:
    """Where a start puts each robot (by id) and the ball (x, y m)."""

    robots: tuple[tuple[str, Pose2D], ...]
    ball: tuple[float, float]


def placement(start: Start, agents: Sequence[AgentId], defended: dict[Side, GoalColor],
              rng: np.random.Generator) -> Placement:
    """The placement of ``start`` (not the kick-off) for ``agents``; ``defended``: the goal each side defends."""
    if start is Start.RANDOM:
        return _random(agents, rng)
    if start is Start.PENALTY:
        return _penalty(agents, defended)
    raise MatchConfigError(f"start {start.value!r} places nothing: the referee's kick-off places the robots")


def _random(agents: Sequence[AgentId], rng: np.random.Generator) -> Placement:
    half_x, half_y = FIELD.half_length - RANDOM_MARGIN_M, FIELD.half_width - RANDOM_MARGIN_M
    taken: list[tuple[float, float]] = []

    def spot() -> tuple[float, float]:
        for _ in range(RANDOM_TRIES):
            x, y = float(rng.uniform(-half_x, half_x)), float(rng.uniform(-half_y, half_y))
            if all(math.hypot(x - px, y - py) >= RANDOM_SPACING_M for px, py in taken):
                break
        taken.append((x, y))
        return x, y

    ball = spot()
    robots = tuple((str(agent), Pose2D(*spot(), float(rng.uniform(-math.pi, math.pi)))) for agent in agents)
    return Placement(robots, ball)


def _penalty(agents: Sequence[AgentId], defended: dict[Side, GoalColor]) -> Placement:
    home = [a for a in agents if a.side is Side.HOME]
    attacker = max(home, key=lambda a: a.player)
    sign = defended[Side.AWAY].sign  # the goal the attacker shoots at
    mark_x = sign * FIELD.penalty_mark_x
    facing = 0.0 if sign > 0 else math.pi
    robots = []
    waiting = 0
    for agent in agents:
        if agent == attacker:
            pose = Pose2D(mark_x - sign * PENALTY_KICKER_BEHIND_BALL_M, 0.0, facing)
        elif agent.side is Side.AWAY and agent.player == 0:
            pose = Pose2D(sign * GOALKEEPER_LINE_X_M, 0.0, facing + math.pi)
        else:
            pose = Pose2D(WAITING_FIRST_X_M + WAITING_SPACING_M * waiting, WAITING_Y_M, math.pi / 2.0)
            waiting += 1
        robots.append((str(agent), pose))
    return Placement(tuple(robots), (mark_x, 0.0))
