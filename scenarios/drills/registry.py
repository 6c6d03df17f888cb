"""The drills by name: what ``robotstadium drill NAME`` plays. A new drill is a module of this package
with a :class:`~scenarios.drills.base.Drill` subclass, named here."""

from __future__ import annotations

from scenarios.drills.base import Drill, DrillError
from scenarios.drills.duel import Duel
from scenarios.drills.goal_line import GoalLine
from scenarios.drills.shooting import Shooting
from scenarios.drills.throw_in import ThrowIn

DRILLS: dict[str, type[Drill]] = {drill.NAME: drill for drill in (ThrowIn, Shooting, Duel, GoalLine)}


def drill_class(name: str) -> type[Drill]:
    """The drill of that name; a :class:`DrillError` naming the drills there are otherwise."""
    try:
        return DRILLS[name]
    except (KeyError, TypeError):
        raise DrillError(f"unknown drill {str(name)[:40]!r}; expected one of {', '.join(DRILLS)}") from None
