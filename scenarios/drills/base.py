"""The base of every drill: one situation played many times, each trial a short match cut off once its
question is answered.

A drill is a class that extends :class:`Drill`; it is made a frozen dataclass when it is defined
(no decorator). Its fields are its parameters, each declared with :func:`parameter` (bounds, unit
and help: the command line makes a flag of it). Its name is its class name in kebab case
(``GoalLine``: ``goal-line``) and its help the first line of its docstring. From a trial's random
generator (numpy's ``default_rng`` of the trial's seed) it says

- :meth:`Drill.setup`: what the trial plays, a :class:`Setup` (the match, the role that plays each
  robot, the seeded facts recorded with the trial, the robots told where they stand);
- :meth:`Drill.observe`: what watches the trial, a :class:`~match.runner.MatchObserver` that ends it;
- :meth:`Drill.score`: what the trial came to, a :class:`Score` (its outcome and figures);
- :meth:`Drill.summarize`: what the trials came to together (plain JSON; by default the count of
  each outcome), and :meth:`Drill.headline`, that in one line.

Its class variables name the roles a policy is chosen for (``ROLES``), its outcomes (``OUTCOMES``)
and a trial's columns (``COLUMNS``: the seeded facts, then the score's figures). The batch
(:mod:`scenarios.drills.run`) plays the trials, keeps them and writes the report.
"""

from __future__ import annotations

import dataclasses
import inspect
import math
import re
from abc import ABC, abstractmethod
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, ClassVar, dataclass_transform

import numpy as np

from match.game import MatchConfig
from match.protocol import Pose2D
from match.runner import MatchObserver

if TYPE_CHECKING:
    from scenarios.drills.records import TrialRecord

Value = float | int | str | None  # a fact or figure of a trial
COLUMN_KINDS = (float, int, str)
RESERVED_COLUMNS = ("trial", "seed", "status", "outcome", "sim_seconds", "wall_seconds", "error", "attempts")
# names the command line gives its own flags and results: no role or parameter may take one
RESERVED_NAMES = ("trials", "seed", "workers", "backend", "ray_address", "resume", "out", "progress", "verbose",
                  "help", "command", "handler", "drill", "drill_class")
FACT_DECIMALS = 3  # the seeded facts (m, field frame) are recorded to the millimetre


class DrillError(ValueError):
    """A drill that cannot be played as asked; the message names the flag or value and what was expected."""


@dataclass(frozen=True)
class Parameter:
    """How a drill's field is bounded and told: ``low`` to ``high`` in ``unit`` (``""``: a count)."""

    low: float
    high: float
    unit: str
    help: str


def parameter(default: int | float, low: int | float, high: int | float, unit: str, help: str) -> Any:
    """A drill's field with its bounds (checked when the drill is made), unit and help (the flag's)."""
    return field(default=default, metadata={"parameter": Parameter(low, high, unit, help)})


@dataclass(frozen=True)
class Role:
    """Who a policy is chosen for (the flag ``--NAME``), e.g. ``home`` or ``striker``."""

    name: str
    help: str


@dataclass(frozen=True)
class Setup:
    """What one trial plays.

    ``config``: the match; ``roles``: robot -> role, in the order the policies are built; ``facts``:
    the seeded numbers recorded with the trial (m, field frame), exact (recorded to the millimetre);
    ``placed``: robots whose policy is told where it stands (a team agent's pose is set there at its
    reset, as at a kick-off).
    """

    config: MatchConfig
    roles: Mapping[str, str]
    facts: Mapping[str, float]
    placed: Mapping[str, Pose2D] = field(default_factory=dict)


@dataclass(frozen=True)
class Score:
    """What one trial came to: its outcome (one of the drill's ``OUTCOMES``) and its figures (None: none)."""

    outcome: str
    figures: Mapping[str, Value]


@dataclass_transform(frozen_default=True, field_specifiers=(parameter,))
@dataclass(frozen=True)
class Drill(ABC):
    """A drill's parameters and what it does with them (see the module)."""

    NAME: ClassVar[str]
    HELP: ClassVar[str]
    ROLES: ClassVar[tuple[Role, ...]]
    OUTCOMES: ClassVar[tuple[str, ...]]
    COLUMNS: ClassVar[Mapping[str, type]]  # fact or figure -> float, int or str, in a row's order

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        if "NAME" not in cls.__dict__:
            cls.NAME = re.sub(r"(?<!^)(?=[A-Z])", "-", cls.__name__).lower()
        if "HELP" not in cls.__dict__:  # before the dataclass writes a docstring of its own
            cls.HELP = " ".join(inspect.cleandoc(cls.__doc__ or "").split("\n\n")[0].split()).rstrip(".")
        dataclass(frozen=True)(cls)
        if not inspect.isabstract(cls):
            check_class(cls)

    def __post_init__(self) -> None:
        for name, bounds, default in self.parameters():
            check_value(name, getattr(self, name), bounds, integer=isinstance(default, int))

    @classmethod
    def parameters(cls) -> tuple[tuple[str, Parameter, int | float], ...]:
        """(name, bounds, default) of every parameter, in the order declared."""
        return tuple((f.name, f.metadata["parameter"], f.default) for f in dataclasses.fields(cls)
                     if "parameter" in f.metadata)

    def to_json(self) -> dict[str, int | float]:
        """The parameters' values, by name."""
        return {name: getattr(self, name) for name, _, _ in self.parameters()}

    def trial_setup(self, seed: int) -> Setup:
        """The setup of the trial of ``seed``: :meth:`setup` with numpy's ``default_rng(seed)``."""
        return self.setup(np.random.default_rng(seed))

    @abstractmethod
    def setup(self, rng: np.random.Generator) -> Setup:
        """What a trial plays, drawn from ``rng`` (the same draws, the same setup)."""

    @abstractmethod
    def observe(self, setup: Setup) -> MatchObserver:
        """A new observer of the trial of ``setup``: it ends the trial once its outcome is known."""

    @abstractmethod
    def score(self, setup: Setup, observer: MatchObserver) -> Score:
        """The trial's outcome and figures (``COLUMNS`` less the facts), from its observer after the match."""

    def summarize(self, records: Sequence[TrialRecord]) -> dict:
        """What the played trials came to together (plain JSON): here their count and the trials of each
        outcome (``trials``, ``outcomes``), which a drill's own summary keeps."""
        from scenarios.drills.summaries import counts

        return {"trials": len(records), "outcomes": counts(records, self.OUTCOMES)}

    def headline(self, summary: Mapping[str, Any]) -> str:
        """The summary in one line."""
        return f"outcomes {summary['outcomes']}"


def check_class(cls: type[Drill]) -> None:
    """A :class:`DrillError` when a drill class's class variables do not describe a drill."""
    where = f"drill class {cls.__name__}"
    if not re.fullmatch(r"[a-z][a-z0-9]*(-[a-z0-9]+)*", cls.NAME):
        raise DrillError(f"{where}: NAME = {cls.NAME!r}; expected lower-case words joined by '-', e.g. 'throw-in'")
    if not cls.HELP:
        raise DrillError(f"{where}: no help; expected a docstring whose first line says what the drill plays")
    names = [role.name for role in getattr(cls, "ROLES", ())] + [name for name, _, _ in cls.parameters()]
    taken = [name for name in names if name in RESERVED_NAMES or names.count(name) > 1]
    if not getattr(cls, "ROLES", ()) or taken:
        raise DrillError(f"{where}: roles and parameters {', '.join(names) or 'none'}; expected one or more roles, "
                         f"distinct names and none of {', '.join(RESERVED_NAMES)}")
    outcomes = getattr(cls, "OUTCOMES", ())
    if not outcomes or len(set(outcomes)) != len(outcomes):
        raise DrillError(f"{where}: OUTCOMES = {outcomes!r}; expected one or more distinct names")
    for column, kind in getattr(cls, "COLUMNS", {}).items():
        if column in RESERVED_COLUMNS or kind not in COLUMN_KINDS:
            raise DrillError(f"{where}: column {column!r} of {kind!r}; expected float, int or str, and a name "
                             f"other than {', '.join(RESERVED_COLUMNS)}")


def check_value(name: str, value: object, bounds: Parameter, integer: bool) -> None:
    """A :class:`DrillError` naming the flag when ``value`` is not a number within ``bounds``."""
    unit = f" {bounds.unit}" if bounds.unit else ""
    kind = "an integer" if integer else "a number"
    expected = f"expected {kind} from {bounds.low:g} to {bounds.high:g}{unit}"
    number = isinstance(value, int) or (not integer and isinstance(value, float))
    if isinstance(value, bool) or not number or not (math.isfinite(value) and bounds.low <= value <= bounds.high):
        raise DrillError(f"--{flag_of(name)} {value!r:.40}: {expected}")


def flag_of(name: str) -> str:
    """A parameter's or role's flag, without its dashes: ``spread_m`` -> ``spread-m``."""
    return name.replace("_", "-")


def rounded(facts: Mapping[str, float]) -> dict[str, float]:
    """The seeded facts as a trial records them: to the millimetre."""
    return {name: round(value, FACT_DECIMALS) for name, value in facts.items()}
