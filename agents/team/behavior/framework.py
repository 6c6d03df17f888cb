"""Options and cards: the behaviour's two building blocks, in the spirit of B-Human's.

An :class:`Option` is a state machine with named states: the state it is in, and since when (the own
clock, s); its owner moves it with :meth:`Option.goto` (a new state only) or :meth:`Option.enter`
(the state entered again, its time restarted). A :class:`Card` plays one situation: it looks at its
context and returns a request, or None when the situation is not its own; a :func:`deck` plays the
first card of an ordered sequence that returns one. A card may keep an option of its own.

Both are plain Python objects called once per step: a step costs a few attribute reads and calls,
where a general behaviour-tree or state-machine library (py_trees, transitions) would add ticks,
callbacks and bookkeeping for features this agent does not use (docs/design/team-agent.md, "The team agent's
structure").
"""

from __future__ import annotations

import enum
import math
from collections.abc import Iterable
from typing import Generic, Protocol, TypeVar

S = TypeVar("S", bound=enum.Enum)
C = TypeVar("C", contravariant=True)
R = TypeVar("R", covariant=True)


class Option(Generic[S]):
    """A named-state machine: ``state``, entered at ``since_s`` (own clock)."""

    def __init__(self, initial: S):
        self.initial = initial
        self.state = initial
        self.since_s = -math.inf

    def goto(self, state: S, now_s: float) -> None:
        """Change to ``state`` at ``now_s``; staying in the state keeps its time."""
        if state is not self.state:
            self.state, self.since_s = state, now_s

    def enter(self, state: S, now_s: float) -> None:
        """Be in ``state`` as of ``now_s``: its time restarts even if it was in it already."""
        self.state, self.since_s = state, now_s

    def reset(self) -> None:
        self.state, self.since_s = self.initial, -math.inf

    def is_in(self, state: S) -> bool:
        return self.state is state

    def for_s(self, now_s: float) -> float:
        """How long it has been in its state (inf when never entered)."""
        return now_s - self.since_s


class Card(Protocol[C, R]):
    """Plays one situation: a request, or None when the situation is not its own."""

    def play(self, context: C) -> R | None: ...


def deck(cards: Iterable[Card[C, R]], context: C) -> R | None:
    """The request of the first card (in order) that plays ``context``; None when none does. Cards after
    it are not asked (their state, if any, stays as it was)."""
    for card in cards:
        request = card.play(context)
        if request is not None:
            return request
    return None
