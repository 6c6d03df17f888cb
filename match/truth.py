"""The match's truth after a step, as rewards see it: frozen values, never an agent's observation.

Positions are in the field frame (:mod:`world.field`: metres, +x toward the yellow goal,
theta rad CCW from +x, in [-pi, pi]); velocities m/s; times simulated seconds. A robot's
``attack_sign`` is +1 when its team attacks the goal at +x (the yellow one) and -1 otherwise:
``attack_sign * x`` grows toward the goal it shoots at, whatever the half.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType

from match.events import MatchEvent
from match.protocol.game_control import GameState
from match.protocol.ids import Side


@dataclass(frozen=True)
class RobotTruth:
    """One robot: its torso pose (x m, y m, theta rad), whether it is down, its side ("home" or "away")
    and the direction it attacks (+1: toward +x)."""

    x: float
    y: float
    theta: float
    fallen: bool
    side: str
    attack_sign: int


@dataclass(frozen=True)
class BallTruth:
    """The ball: centre (x, y, z m), ground velocity (vx, vy m/s), the robot that touched it last and when (s)."""

    x: float
    y: float
    z: float
    vx: float
    vy: float
    last_toucher: str | None
    last_touch_time_s: float | None


@dataclass(frozen=True)
class MatchTruth:
    """The match after a step (or a reset).

    ``step``: control steps since the reset; ``state``: the game state; ``score`` and
    ``shootout_score``: goals by side name; ``goals``: the side names that scored in this step
    (shoot-out goals included), one entry per goal; ``events``: the referee's events of this step;
    ``robots``: by agent id.
    """

    time_s: float
    step: int
    state: GameState
    half: int
    score: Mapping[str, int]
    shootout_score: Mapping[str, int]
    goals: tuple[str, ...]
    events: tuple[MatchEvent, ...]
    ball: BallTruth
    robots: Mapping[str, RobotTruth]

    def teammates(self, agent: str) -> tuple[str, ...]:
        """The agent ids of ``agent``'s team, itself included."""
        side = self.robots[agent].side
        return tuple(name for name, robot in self.robots.items() if robot.side == side)


def match_truth(match, goals: tuple[Side, ...] = (), events: tuple[MatchEvent, ...] = ()) -> MatchTruth:
    """The truth of ``match`` (a :class:`match.game.Match`) now; ``goals`` and ``events``: those of its last step."""
    world, referee = match.world, match.referee
    gc = referee.game_control()
    robots = {}
    for agent in match.agents:
        robot = world.robot_truth(str(agent))
        attack_sign = referee.defended_goal(agent.side).other.sign
        robots[str(agent)] = RobotTruth(robot.pose.x, robot.pose.y, robot.pose.theta, bool(robot.fallen),
                                        agent.side.value, int(attack_sign))
    ball = world.ball()
    return MatchTruth(
        time_s=world.time_s,
        step=match.step_index,
        state=match.state,
        half=gc.half,
        score=MappingProxyType({"home": gc.score[0], "away": gc.score[1]}),
        shootout_score=MappingProxyType({"home": gc.shootout_score[0], "away": gc.shootout_score[1]}),
        goals=tuple(side.value for side in goals),
        events=tuple(events),
        ball=BallTruth(ball.x, ball.y, ball.z, ball.vx, ball.vy, ball.last_toucher, ball.last_touch_time_s),
        robots=MappingProxyType(robots),
    )
