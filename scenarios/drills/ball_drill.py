"""Drills in free play that end by where the ball is: :class:`BallDrill` and its observer :class:`BallWatch`.

A ball drill places its robots and the ball (:mod:`match.free_play`: always PLAYING, no
referee) and says, in :meth:`BallDrill.judge`, what a ball at a point means: an outcome, or
play on. A trial ends at the first outcome, from the world's ground truth, or with ``none``
after the drill's ``seconds``; it records the ball's spot (m, field frame) and when the
outcome came (s).
"""

from __future__ import annotations

from abc import abstractmethod
from collections.abc import Callable, Mapping
from typing import Any

from match.free_play import FreePlay
from match.game import Match, MatchConfig
from match.protocol import Pose2D
from match.protocol.actions import Action
from scenarios.drills.base import Drill, Score, Setup, parameter

TIME_DECIMALS = 2
DEFAULT_SECONDS = 30
MAX_SECONDS = 600
SECONDS_HELP = "a trial's longest simulated time"

Judge = Callable[[float, float], "str | None"]


def trial_time_s(match: Match) -> float:
    """Simulated time since the trial's first step (s): the control steps played times their length."""
    return match.step_index * match.config.world.physics.control_step_s


class BallWatch:
    """Ends a trial once ``judge(x, y)`` names an outcome for the ball's position (m, field frame), or with
    ``none`` after ``limit_s`` (s); ``outcome`` is then (name, trial time in s)."""

    def __init__(self, judge: Judge, limit_s: float):
        self.judge, self.limit_s = judge, limit_s
        self.outcome: tuple[str, float] | None = None

    def decided(self, match: Match, actions: Mapping[str, Action | None]) -> None:
        """Nothing: the ball decides (a subclass may record more here)."""

    def done(self, match: Match) -> bool:
        ball = match.world.ball()
        time_s = trial_time_s(match)
        name = self.judge(ball.x, ball.y)
        if name is None and time_s >= self.limit_s:
            name = "none"
        if name is not None:
            self.outcome = (name, time_s)
        return self.outcome is not None

    def score(self) -> Score:
        """The outcome and when it came (``time_s``, s); ``none`` at the limit if the match ended first."""
        name, time_s = self.outcome or ("none", self.limit_s)
        return Score(name, {"time_s": round(time_s, TIME_DECIMALS)})


class BallDrill(Drill):
    """A drill in free play that ends by where the ball is (see the module). ``seconds`` (``--seconds``)
    bounds a trial's simulated time; a subclass gives its default with the class keyword ``seconds``:
    ``class Shooting(BallDrill, seconds=40)``."""

    COLUMNS = {"ball_x": float, "ball_y": float, "time_s": float}

    seconds: int = parameter(DEFAULT_SECONDS, 1, MAX_SECONDS, "s", SECONDS_HELP)

    def __init_subclass__(cls, seconds: int | None = None, **kwargs: Any) -> None:
        if seconds is not None:  # the subclass's own default, before the base makes it a dataclass
            cls.__annotations__ = {**cls.__dict__.get("__annotations__", {}), "seconds": int}
            cls.seconds = parameter(seconds, 1, MAX_SECONDS, "s", SECONDS_HELP)
        super().__init_subclass__(**kwargs)

    @abstractmethod
    def judge(self, x: float, y: float) -> str | None:
        """The outcome of a ball at (x, y) (m, field frame); None: play on."""

    def free_play(self, starts: Mapping[str, Pose2D], ball: tuple[float, float], roles: Mapping[str, str],
                  placed: bool = False) -> Setup:
        """A trial of the robots at ``starts`` (robot -> pose, m and rad, field frame, in the order they are
        built) and the ball at ``ball`` (m); ``roles``: robot -> role; ``placed``: every robot is told its start."""
        config = MatchConfig(free_play=FreePlay(tuple(starts.items()), ball_xy=ball))
        return Setup(config, roles, {"ball_x": ball[0], "ball_y": ball[1]}, dict(starts) if placed else {})

    def observe(self, setup: Setup) -> BallWatch:
        return BallWatch(self.judge, float(self.seconds))

    def score(self, setup: Setup, observer: BallWatch) -> Score:
        return observer.score()
