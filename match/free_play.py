"""Free play: a match with no ball in play and no referee decisions (scenario runs alone on the field).

The robots stand where they were placed, the game state is always PLAYING and nobody is
held, so a policy plays exactly as in a refereed match, through the same
:meth:`match.game.Match.step`. The ball waits on the carpet beyond the side line.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from match.errors import MatchConfigError
from match.protocol.game_control import GameControlData, GameState, SecondaryState
from match.protocol.ids import AgentId
from world.field import GoalColor, Pose2D
from world.teams import TeamColor

OFF_FIELD_BALL_XY = (0.0, 3.0)  # m, field frame: on the carpet beyond the left side line
SETTLE_STEPS = 10  # control steps the placed robots stand before the first observation
FREE_PLAY_SECONDS = 600.0  # the clock shown in the game-control data; it never runs


@dataclass(frozen=True)
class FreePlay:
    """Where everything starts in free play.

    ``starts``: (agent id, pose in the field frame: m, m, rad) of every robot on the field,
    in the order the robots are built; ``ball_xy``: where the ball waits (m, field frame);
    ``settle_steps``: control steps (40 ms) the robots stand after being placed, before the
    first observation.
    """

    starts: tuple[tuple[str, Pose2D], ...]
    ball_xy: tuple[float, float] = OFF_FIELD_BALL_XY
    settle_steps: int = SETTLE_STEPS

    def __post_init__(self) -> None:
        if not self.starts:
            raise MatchConfigError("free play needs at least one robot in starts")
        ids = [robot for robot, _ in self.starts]
        for robot in ids:
            try:
                AgentId.parse(robot)
            except ValueError as error:
                raise MatchConfigError(f"free play start: {error}") from None
        if len(set(ids)) != len(ids):
            raise MatchConfigError(f"free play starts name a robot twice: {ids}")
        for robot, pose in self.starts:
            if not isinstance(pose, Pose2D) or not all(math.isfinite(v) for v in (pose.x, pose.y, pose.theta)):
                raise MatchConfigError(f"free play start of {robot}: {pose!r}; expected a finite Pose2D")
        if not all(isinstance(v, (int, float)) and math.isfinite(v) for v in self.ball_xy) or len(self.ball_xy) != 2:
            raise MatchConfigError(f"free play ball_xy = {self.ball_xy!r}; expected two finite numbers (m)")
        if not isinstance(self.settle_steps, int) or self.settle_steps < 0:
            raise MatchConfigError(f"free play settle_steps = {self.settle_steps!r}; expected an integer >= 0")

    @property
    def agents(self) -> tuple[AgentId, ...]:
        return tuple(AgentId.parse(robot) for robot, _ in self.starts)


def free_play_control(time_s: float) -> GameControlData:
    """The game-control data of free play: PLAYING, no kick-off, home blue defending the blue goal."""
    return GameControlData(
        state=GameState.PLAYING,
        secondary=SecondaryState.NORMAL,
        kickoff=None,
        score=(0, 0),
        shootout_score=(0, 0),
        seconds_remaining=FREE_PLAY_SECONDS,
        half=1,
        home_color=TeamColor.BLUE,
        home_defends=GoalColor.BLUE,
        time_s=time_s,
    )
