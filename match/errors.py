"""Typed errors of the match layer. Every message names the bad value and what was expected."""

from __future__ import annotations


class MatchError(Exception):
    """Base class of everything the match layer refuses."""


class UnknownAgentError(MatchError, LookupError):
    def __init__(self, agent: object, known: tuple[str, ...] | list[str]):
        super().__init__(f"unknown agent id {agent!r}; expected one of {list(known)}")
        self.agent = agent


class InvalidActionError(MatchError, ValueError):
    """An action (or one field of it) outside the action space; nothing was applied."""

    def __init__(self, agent: str, field: str, value: object, expected: str):
        shown = repr(value)
        if len(shown) > 120:
            shown = shown[:117] + "..."
        super().__init__(f"agent {agent!r}: action field {field!r} = {shown} is invalid; expected {expected}")
        self.agent = agent
        self.field = field
        self.value = value
        self.expected = expected


class RadioPacketError(InvalidActionError):
    """A radio packet that does not fit the packet space (wrong type or over 128 bytes)."""


class MatchConfigError(MatchError, ValueError):
    """A match, referee or radio setting outside its allowed range."""


class InvalidReportError(MatchError, ValueError):
    """What a policy reports for the log (a pose estimate, an :class:`~match.protocol.policy.AgentReport`)
    that does not fit its type: the log records nothing for that robot that step."""
