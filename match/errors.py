"""Typed errors of the match layer. Every message names the bad value and what was expected.

Every refusal of a step (:meth:`match.game.Match.step`, :meth:`match.env.RobotStadiumEnv.step`)
is a :class:`StepRefusedError`, raised before anything of the step happens::

    MatchError
    ├── StepRefusedError (also ValueError): actions not a dict, step before reset, after the end or after close
    │   ├── UnknownAgentError (also LookupError): an agent id not in the match
    │   └── InvalidActionError: one field of one agent's action
    │       └── RadioPacketError: a radio packet that is not bytes of at most 128
    └── EnvClosedError (also RuntimeError): reset, state or render of a closed env
"""

from __future__ import annotations

import reprlib

SHOWN_CHARS = 120  # longest value shown in a message
_SHOWN_INT_BITS = 1024  # ints longer than this (about 300 digits) are shown by type and size only
_REPR = reprlib.Repr()  # containers shortened at every level before they are printed
_REPR.maxstring = _REPR.maxother = _REPR.maxlong = SHOWN_CHARS


class MatchError(Exception):
    """Base class of everything the match layer refuses."""


def shown(value: object) -> str:
    """``repr(value)`` for a message, at most :data:`SHOWN_CHARS` long; never raises.

    Long containers and strings are shortened (:mod:`reprlib`) and the text is put on one
    line; an int too long to print or a repr that fails is replaced by its type.
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


class InvalidReportError(MatchError, ValueError):
    """What a policy reports for the log (a pose estimate, an :class:`~match.protocol.policy.AgentReport`)
    that does not fit its type: the log records nothing for that robot that step."""
