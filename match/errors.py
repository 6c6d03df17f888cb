"""Typed errors of the match layer. Every message names the bad value and what was expected.

Every refusal of a step (:meth:`match.game.Match.step`, :meth:`match.env.RobotStadiumEnv.step`)
is a :class:`StepRefusedError`, raised before anything of the step happens::

    MatchError
    ├── StepRefusedError (also ValueError): actions not a dict, step before reset, after the end or after close
    │   ├── UnknownAgentError (also LookupError): an agent id not in the match
    │   └── InvalidActionError: one field of one agent's action
    │       └── RadioPacketError: a radio packet that is not bytes of at most 128
    ├── EnvClosedError (also RuntimeError): reset, state or render of a closed env
    ├── MatchConfigError (also ValueError): a setting, option or seed outside its range
    └── RewardError (also ValueError): a reward function's result that is not a finite reward per agent
"""

from __future__ import annotations

import dataclasses
import reprlib
from itertools import islice

SHOWN_CHARS = 120  # longest value shown in a message
SHOWN_PREFIX = 40  # a longer text or bytes shows its type, its length and its first this many characters
_SHOWN_INT_BITS = 1024  # ints longer than this (about 300 digits) are shown by type and size only


class _ShortRepr(reprlib.Repr):
    """:mod:`reprlib`'s shortening at every level, costing the size of the text it returns, never of the value:
    bytes are cut before they are printed, dicts and sets are read in their own order (never sorted),
    subclasses of the built-in containers are shown as those, a dataclass shows its fields shortened."""

    def repr_bytes(self, x: bytes, level: int) -> str:
        return _head(x, bytes(memoryview(x)[:SHOWN_PREFIX]), memoryview(x).nbytes)

    repr_bytearray = repr_bytes

    def repr_str(self, x: str, level: int) -> str:
        size = str.__len__(x)
        return _head(x, str.__getitem__(x, slice(0, SHOWN_PREFIX)), size)

    def repr_dict(self, x: dict, level: int) -> str:
        if not x:
            return "{}"
        if level <= 0:
            return "{...}"
        pieces = [f"{self.repr1(k, level - 1)}: {self.repr1(v, level - 1)}"
                  for k, v in islice(dict.items(x), self.maxdict)]
        return "{" + ", ".join(pieces + ["..."] * (dict.__len__(x) > self.maxdict)) + "}"

    def repr_set(self, x: set | frozenset, level: int) -> str:
        name = type(x).__name__
        if not x:
            return f"{name}()"
        if level <= 0:
            return "{...}"
        pieces = [self.repr1(item, level - 1) for item in islice(x, self.maxset)]
        return "{" + ", ".join(pieces + ["..."] * (len(x) > self.maxset)) + "}"

    repr_frozenset = repr_set

    def repr_instance(self, x: object, level: int) -> str:
        if isinstance(x, (bytes, bytearray)):  # a subclass: its bytes, whatever it overrides
            return self.repr_bytes(x, level)
        if isinstance(x, str):
            return self.repr_str(x, level)
        if isinstance(x, dict):
            return self.repr_dict(x, level)
        if isinstance(x, (set, frozenset)):
            return self.repr_set(x, level)
        if isinstance(x, list):  # one item past the limit shows that there are more
            return self.repr_list(list.__getitem__(x, slice(0, self.maxlist + 1)), level)
        if isinstance(x, tuple):
            return self.repr_tuple(tuple.__getitem__(x, slice(0, self.maxtuple + 1)), level)
        if dataclasses.is_dataclass(x) and not isinstance(x, type):
            fields = ", ".join(f"{f.name}={self.repr1(getattr(x, f.name, '<missing>'), level - 1)}"
                               for f in dataclasses.fields(x))
            return f"{type(x).__name__}({fields})"
        return super().repr_instance(x, level)


def _head(value: object, head: bytes | str, size: int) -> str:
    """A text or bytes value in full when short, else as its type, its length and its first characters."""
    if size <= SHOWN_PREFIX:
        return repr(head)
    return f"<{type(value).__name__} of length {size}: {head!r}...>"


_REPR = _ShortRepr()  # containers shortened at every level before they are printed
_REPR.maxstring = _REPR.maxother = _REPR.maxlong = SHOWN_CHARS


class MatchError(Exception):
    """Base class of everything the match layer refuses."""


def shown(value: object) -> str:
    """``repr(value)`` for a message, at most :data:`SHOWN_CHARS` long; never raises.

    Long containers are shortened (:mod:`reprlib`), a text or bytes longer than
    :data:`SHOWN_PREFIX` is shown as its type, length and first characters, and the text is
    put on one line; an int too long to print or a repr that fails is replaced by its type.
    What it costs follows from the length of the text, not from the size of the value, so a
    refusal of a huge value is as cheap as any other.
    """
    kind = type(value).__name__
    try:
        if isinstance(value, int) and int.bit_length(value) > _SHOWN_INT_BITS:
            return f"<{kind} of {int.bit_length(value)} bits>"
        text = _REPR.repr(value)
        if not isinstance(text, str):
            raise TypeError("repr is not a str")
    except Exception:  # a value's own repr may raise anything
        return f"<{kind} whose repr failed>"
    text = " ".join(text.split())  # one line
    return text if len(text) <= SHOWN_CHARS else text[: SHOWN_CHARS - 3] + "..."


class StepRefusedError(MatchError, ValueError):
    """A step refused before anything of it happened: no packet, no command, no random draw, no time.

    ``agent`` is the agent id the refusal is about (None when it is about the whole step).
    """

    def __init__(self, message: str, agent: object = None):
        super().__init__(message)
        self.agent = agent


class UnknownAgentError(StepRefusedError, LookupError):
    """An agent id that is not in the match (also raised by the env's space lookups)."""

    def __init__(self, agent: object, known: tuple[str, ...] | list[str]):
        super().__init__(f"unknown agent id {shown(agent)}; expected one of {list(known)}", agent)


class InvalidActionError(StepRefusedError):
    """An action (or one field of it) outside the action space; nothing was applied."""

    def __init__(self, agent: str, field: str, value: object, expected: str):
        super().__init__(
            f"agent {shown(agent)}: action field {shown(field)} = {shown(value)} is invalid; expected {expected}", agent
        )
        self.field = field
        self.value = value
        self.expected = expected


class RadioPacketError(InvalidActionError):
    """A radio packet that does not fit the packet space (wrong type or over 128 bytes)."""


class EnvClosedError(MatchError, RuntimeError):
    """A use of a closed :class:`~match.env.RobotStadiumEnv` (reset, state, render); build a new one."""


class MatchConfigError(MatchError, ValueError):
    """A match, referee or radio setting outside its allowed range."""


class RewardError(MatchError, ValueError):
    """What an env's ``reward_fn`` returned that is not a finite number per known agent (NaN, a string, an
    unknown agent id)."""


class InvalidReportError(MatchError, ValueError):
    """What a policy reports for the log (a pose estimate, an :class:`~match.protocol.policy.AgentReport`)
    that does not fit its type: the log records nothing for that robot that step."""
