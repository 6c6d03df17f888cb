"""What drives a robot: the policy protocol every controller implements, built-in or the user's.

A policy is built without arguments (or with its own keyword options), then
:meth:`Policy.reset` tells it which robot it plays and seeds it before every match;
:meth:`Policy.act` maps each new observation (:func:`match.protocol.spaces.observation_space`)
to an action (an :class:`~match.protocol.actions.Action` or an action dict).

Two optional reports, for evaluation only (nothing in the match reads them): a policy that
also implements :class:`PoseReporter` has its pose estimate recorded in the match log beside
the truth; one that implements :class:`AgentReporter` has its :class:`AgentReport` (its ball,
the team's ball, its role, the landmarks it saw) recorded there too. The runner asks for
both after every step; a report that raises or does not fit its type is not a fault of
play: the log records nothing for that robot that step (:class:`~match.errors.InvalidReportError`).

An optional :class:`Thinker` moves work out of the step: a controller process calls its
``think`` after the step's actions went out, while the simulator plays the next step.

What a name such as ``package.module:Name`` may stand for is a policy class (its instances
have ``reset`` and ``act``), a ``functools.partial`` of one, or a function marked with
:func:`policy_builder`; :func:`policy_factory_problem` says why anything else is not (a
function such as ``os.system`` is callable, but calling it is no policy).
"""

from __future__ import annotations

import functools
import itertools
import math
import operator
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any, Protocol, TypeVar, runtime_checkable

from match.errors import InvalidReportError
from world.field import FIELD

PoseTuple = tuple[float, float, float]  # x m, y m, theta rad, in the field frame

MAX_REPORT_M = 100.0  # a reported position farther than this from the centre spot is garbage
MAX_ROLE_CHARS = 32
MAX_LANDMARK_ITEMS = 1000  # more items than this in landmarks_seen is garbage (it may never end)


@runtime_checkable
class Policy(Protocol):
    """A robot's controller."""

    def reset(self, agent_id: str, seed: int) -> None:
        """Forget the last match; play robot ``agent_id`` (``home_0`` .. ``away_3``) with this seed."""

    def act(self, observation: Mapping[str, Any]) -> Any:
        """The action for this control step (40 ms), from this step's observation only."""


POLICY_METHODS = ("reset", "act")
_BUILDER_MARK = "__robotstadium_policy_builder__"
Builder = TypeVar("Builder")


def policy_builder(factory: Builder) -> Builder:
    """Mark a function that builds policies (``def striker(**options) -> Striker``), so that a policy name
    may stand for it as for a class; what it builds is checked when it is called."""
    setattr(factory, _BUILDER_MARK, True)
    return factory


def policy_factory_problem(factory: object) -> str | None:
    """Why ``factory`` cannot stand for a policy (one phrase), None when it can: a class whose instances
    have a callable ``reset`` and ``act``, a ``functools.partial`` of one, or a function marked with
    :func:`policy_builder`."""
    while isinstance(factory, functools.partial):
        factory = factory.func
    if isinstance(factory, type):
        for method in POLICY_METHODS:
            if not callable(getattr(factory, method, None)):
                return f"has no {method}() method"
        return None
    if callable(factory) and getattr(factory, _BUILDER_MARK, False) is True:
        return None
    return f"is a {type(factory).__name__}, not a policy class"


@runtime_checkable
class Thinker(Protocol):
    """A policy with work that can wait until its action has gone out (a camera frame's perception, say).

    A controller process calls :meth:`think` right after it sent a step's actions, so that the work
    overlaps the simulator's next step; nothing calls it in the simulator's process. Whether it was
    called or not, :meth:`Policy.act` must give the same action: ``act`` first does whatever
    ``think`` left undone. An error it raises is the robot's fault, recorded with the next step.
    """

    def think(self) -> None:
        """Do the work the last :meth:`Policy.act` left for later."""


@runtime_checkable
class PoseReporter(Protocol):
    """A policy that can tell where it believes its robot is."""

    def pose_estimate(self) -> PoseTuple | None:
        """The robot's pose as the policy believes it now (field frame), or None when it has none."""


@dataclass(frozen=True)
class AgentReport:
    """What a robot believes beside its pose, for the match log (field frame, metres).

    ``ball_xy``: its own ball estimate, None when it has none; ``team_ball_xy``: the ball the
    team agreed on, None when none; ``role``: the name of its role (e.g. ``striker``), None
    when it has none; ``landmarks_seen``: indices into ``world.field.FIELD.landmarks`` of the
    landmarks its last camera frame showed. Checked and normalized on creation (positions to
    float pairs, indices to a frozenset of ints); a bad value raises
    :class:`~match.errors.InvalidReportError`.
    """

    ball_xy: tuple[float, float] | None = None
    team_ball_xy: tuple[float, float] | None = None
    role: str | None = None
    landmarks_seen: frozenset[int] = field(default_factory=frozenset)

    def __post_init__(self) -> None:
        object.__setattr__(self, "ball_xy", _point("ball_xy", self.ball_xy))
        object.__setattr__(self, "team_ball_xy", _point("team_ball_xy", self.team_ball_xy))
        role = self.role
        if role is not None and not (isinstance(role, str) and 0 < len(role) <= MAX_ROLE_CHARS and role.isprintable()):
            raise InvalidReportError(f"report field 'role' = {_shown(role)}; expected None or a name of "
                                     f"1-{MAX_ROLE_CHARS} printable characters")
        object.__setattr__(self, "landmarks_seen", _indices(self.landmarks_seen))

    @classmethod
    def check(cls, value: object) -> AgentReport | None:
        """``value`` as a valid report (None stays None); :class:`InvalidReportError` otherwise."""
        if value is None:
            return None
        if not isinstance(value, AgentReport):
            raise InvalidReportError(f"report() returned {_shown(value)}; expected an AgentReport or None")
        return cls(value.ball_xy, value.team_ball_xy, value.role, value.landmarks_seen)  # checked again


@runtime_checkable
class AgentReporter(Protocol):
    """A policy that can tell what it believes beside its pose (its ball, team ball, role, landmarks)."""

    def report(self) -> AgentReport | None:
        """What the policy believes now, or None when it has nothing to report."""


def check_pose(value: object) -> PoseTuple | None:
    """A reported pose estimate as (x, y, theta) floats (None stays None); :class:`InvalidReportError` otherwise."""
    if value is None:
        return None
    numbers = _numbers("pose_estimate()", value, 3)
    if max(abs(numbers[0]), abs(numbers[1])) > MAX_REPORT_M:
        raise InvalidReportError(f"pose_estimate() = {_shown(value)}; expected a position within {MAX_REPORT_M:g} m")
    return numbers[0], numbers[1], numbers[2]


def _point(name: str, value: object) -> tuple[float, float] | None:
    if value is None:
        return None
    x, y = _numbers(f"report field {name!r}", value, 2)
    if max(abs(x), abs(y)) > MAX_REPORT_M:
        raise InvalidReportError(f"report field {name!r} = {_shown(value)}; expected a position within {MAX_REPORT_M:g} m")
    return x, y


def _numbers(name: str, value: object, count: int) -> tuple[float, ...]:
    expected = f"expected {count} finite numbers"
    if isinstance(value, (str, bytes)) or not isinstance(value, Iterable):
        raise InvalidReportError(f"{name} = {_shown(value)}; {expected}")
    try:
        items = list(value)
    except Exception:
        raise InvalidReportError(f"{name} = {_shown(value)}; {expected}") from None
    if len(items) != count or any(isinstance(v, (bool, str, bytes)) for v in items):
        raise InvalidReportError(f"{name} = {_shown(value)}; {expected}")
    try:
        numbers = tuple(float(v) for v in items)
    except (TypeError, ValueError):
        raise InvalidReportError(f"{name} = {_shown(value)}; {expected}") from None
    if not all(math.isfinite(v) for v in numbers):
        raise InvalidReportError(f"{name} = {_shown(value)}; {expected}")
    return numbers


def _indices(value: object) -> frozenset[int]:
    count = len(FIELD.landmarks)
    expected = f"expected indices 0-{count - 1} into FIELD.landmarks"
    if isinstance(value, (str, bytes)) or not isinstance(value, Iterable):
        raise InvalidReportError(f"report field 'landmarks_seen' = {_shown(value)}; {expected}")
    items = list(itertools.islice(value, MAX_LANDMARK_ITEMS + 1))
    if len(items) > MAX_LANDMARK_ITEMS:
        raise InvalidReportError(f"report field 'landmarks_seen' has over {MAX_LANDMARK_ITEMS} items; {expected}")
    found = set()
    for item in items:
        try:
            index = operator.index(item) if not isinstance(item, bool) else -1
        except TypeError:
            index = -1
        if not 0 <= index < count:
            raise InvalidReportError(f"report field 'landmarks_seen' holds {_shown(item)}; {expected}")
        found.add(int(index))
    return frozenset(found)


def _shown(value: object) -> str:
    try:
        text = repr(value)
    except Exception:
        text = f"<{type(value).__name__}>"
    return text if len(text) <= 80 else text[:77] + "..."
