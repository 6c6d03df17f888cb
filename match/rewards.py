"""Rewards for learners: functions of the match's truth, never part of an observation.

A reward function is any object with ``reset(truth)`` (called at every env reset) and
``__call__(truth) -> {agent id: reward}`` (called after every step, with the
:class:`~match.truth.MatchTruth` after it); agents it leaves out get 0. Pass one to
``parallel_env(reward_fn=...)``. It may read everything of the truth (the ball, every pose):
it shapes training, it never reaches an agent's observation. It must pickle (copies of the
env carry it): define it at module level.

:class:`Reward` is a base that keeps the previous truth, so a subclass writes
``step(before, after)``. The shaped rewards here are zero-sum between the teams unless said
otherwise; :class:`Weighted` adds several up::

    reward_fn = Weighted((1.0, Goals()), (0.2, BallProgress()), (0.05, Possession()))
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Protocol, runtime_checkable

from match.errors import MatchConfigError, shown
from match.events import EventKind
from match.protocol.game_control import GameState
from match.truth import MatchTruth
from world.field import FIELD

PLACED_BY_REFEREE = frozenset({EventKind.GOAL, EventKind.THROW_IN, EventKind.STATE, EventKind.SHOOTOUT_KICK})
"""Events after which the ball may have been put somewhere by the referee: no progress is counted then."""
MAX_BALL_STEP_M = 1.0  # a ball moving farther than this in one step was placed, not kicked
SHOT_MIN_SPEED_MPS = 0.5  # a shot: the ball leaves a touch at least this fast ...
SHOT_WINDOW_S = 0.3  # ... within this long after the touch ...
SHOT_GOAL_MARGIN_M = 0.1  # ... heading between the posts, widened by this on each side


@runtime_checkable
class RewardFn(Protocol):
    """What ``parallel_env(reward_fn=...)`` takes."""

    def reset(self, truth: MatchTruth) -> None: ...

    def __call__(self, truth: MatchTruth) -> Mapping[str, float]: ...


class Reward:
    """A reward function that sees each step's truth before and after (:meth:`step`)."""

    def __init__(self) -> None:
        self._before: MatchTruth | None = None

    def reset(self, truth: MatchTruth) -> None:
        self._before = truth

    def __call__(self, truth: MatchTruth) -> dict[str, float]:
        before = self._before if self._before is not None else truth
        self._before = truth
        return self.step(before, truth)

    def step(self, before: MatchTruth, after: MatchTruth) -> dict[str, float]:  # pragma: no cover - abstract
        raise NotImplementedError


class Goals(Reward):
    """``points`` to every robot of the team that scored, ``-points`` to every robot of the other, per goal
    (shoot-out goals included): the env's reward without a ``reward_fn``."""

    def __init__(self, points: float = 1.0) -> None:
        super().__init__()
        self.points = _finite("Goals points", points)

    def step(self, before: MatchTruth, after: MatchTruth) -> dict[str, float]:
        rewards = dict.fromkeys(after.robots, 0.0)
        for side in after.goals:
            for agent, robot in after.robots.items():
                rewards[agent] += self.points if robot.side == side else -self.points
        return rewards


class BallProgress(Reward):
    """``per_metre`` times the metres the ball moved toward the goal a robot's team attacks, during play.

    Steps where the referee may have placed the ball (a goal, a throw-in, a change of game
    state) or the ball jumped more than :data:`MAX_BALL_STEP_M` count nothing.
    """

    def __init__(self, per_metre: float = 1.0) -> None:
        super().__init__()
        self.per_metre = _finite("BallProgress per_metre", per_metre)

    def step(self, before: MatchTruth, after: MatchTruth) -> dict[str, float]:
        dx = after.ball.x - before.ball.x
        placed = any(event.kind in PLACED_BY_REFEREE for event in after.events)
        if (placed or after.state is not GameState.PLAYING
                or math.hypot(dx, after.ball.y - before.ball.y) > MAX_BALL_STEP_M):
            return dict.fromkeys(after.robots, 0.0)
        return {agent: self.per_metre * robot.attack_sign * dx for agent, robot in after.robots.items()}


class Possession(Reward):
    """``per_second`` times the step's length to every robot of the team whose robot touched the ball last,
    and the negative to the other team, during play (0 while nobody has touched it)."""

    def __init__(self, per_second: float = 1.0) -> None:
        super().__init__()
        self.per_second = _finite("Possession per_second", per_second)

    def step(self, before: MatchTruth, after: MatchTruth) -> dict[str, float]:
        toucher = after.ball.last_toucher
        if after.state is not GameState.PLAYING or toucher not in after.robots:
            return dict.fromkeys(after.robots, 0.0)
        amount = self.per_second * (after.time_s - before.time_s)
        side = after.robots[toucher].side
        return {agent: amount if robot.side == side else -amount for agent, robot in after.robots.items()}


class Shots(Reward):
    """``points`` to the robot whose touch sent the ball toward the goal its team attacks: within
    :data:`SHOT_WINDOW_S` of the touch the ball moves at least :data:`SHOT_MIN_SPEED_MPS` toward that goal,
    on a straight line that crosses its goal line between the posts. Once per touch; nothing to the others."""

    def __init__(self, points: float = 1.0) -> None:
        super().__init__()
        self.points = _finite("Shots points", points)
        self._credited: tuple[str, float] | None = None

    def reset(self, truth: MatchTruth) -> None:
        super().reset(truth)
        self._credited = None

    def step(self, before: MatchTruth, after: MatchTruth) -> dict[str, float]:
        rewards = dict.fromkeys(after.robots, 0.0)
        ball, toucher, when = after.ball, after.ball.last_toucher, after.ball.last_touch_time_s
        if (after.state is not GameState.PLAYING or toucher not in after.robots or when is None
                or after.time_s - when > SHOT_WINDOW_S or self._credited == (toucher, when)):
            return rewards
        sign = after.robots[toucher].attack_sign
        goal_x = sign * FIELD.half_length
        toward = ball.vx * sign
        if toward < SHOT_MIN_SPEED_MPS:
            return rewards
        y_at_line = ball.y + ball.vy * (goal_x - ball.x) / ball.vx
        if abs(y_at_line) <= FIELD.goal_inner_width / 2.0 + SHOT_GOAL_MARGIN_M:
            rewards[toucher] = self.points
            self._credited = (toucher, when)
        return rewards


class Weighted(Reward):
    """The weighted sum of reward functions: ``Weighted((1.0, Goals()), (0.1, BallProgress()))``."""

    def __init__(self, *terms: tuple[float, RewardFn]) -> None:
        super().__init__()
        if not terms:
            raise MatchConfigError("Weighted() needs at least one (weight, reward function) pair")
        for term in terms:
            if (not isinstance(term, tuple) or len(term) != 2 or not isinstance(term[1], RewardFn)):
                raise MatchConfigError(f"Weighted term {shown(term)}; expected (weight, reward function)")
            _finite("Weighted weight", term[0])
        self.terms = tuple((float(weight), reward) for weight, reward in terms)

    def reset(self, truth: MatchTruth) -> None:
        for _, reward in self.terms:
            reward.reset(truth)

    def __call__(self, truth: MatchTruth) -> dict[str, float]:
        total = dict.fromkeys(truth.robots, 0.0)
        for weight, reward in self.terms:
            for agent, value in reward(truth).items():
                total[agent] += weight * float(value)
        return total


def _finite(name: str, value: object) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise MatchConfigError(f"{name} = {shown(value)} is invalid; expected a finite number")
    return float(value)
