"""The role registry: every role the team agent can play, by name, and how a robot of it plays.

A role is a name (the radio carries its code, :data:`agents.radio.ROLE_CODES`) and a factory
of its player: an object whose ``play(world, situation)`` returns the step's motion request. The
assignment (:mod:`.assignment`) gives player 0 the goalkeeper, the robot that reaches the ball first
the striker, and the other field players :data:`FIELD_ROLES` by player number. A new role is a file
that calls :func:`register` (and a free radio code, :func:`agents.radio.register_role_code`);
placing it in :data:`FIELD_ROLES` (or choosing it in a subclass of the behaviour) puts it on the field.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol

from agents.team.behavior.requests import MotionRequest
from agents.team.modelling.representations import WorldModel
from agents.team.params import TeamParams


@dataclass(frozen=True)
class Situation:
    """What a role is played by this step: ``play_xy``: the ball, or the spot a ball going out comes back on
    (field frame; None: no ball known); ``restart``: that spot; ``following_kick``: its own kick went off
    lately; ``looking_near_feet``: the head's search looks near the feet first."""

    play_xy: tuple[float, float] | None
    restart: tuple[float, float] | None
    following_kick: bool
    looking_near_feet: bool


class RolePlayer(Protocol):
    def play(self, world: WorldModel, situation: Situation) -> MotionRequest: ...


class Kit(Protocol):
    """What role factories are given: the parameters and the shared striker option (a goalkeeper clears
    with it)."""

    params: TeamParams
    striker: object


@dataclass(frozen=True)
class RoleSpec:
    name: str
    make: Callable[[Kit], RolePlayer]
    doc: str = ""


REGISTRY: dict[str, RoleSpec] = {}


def register(spec: RoleSpec) -> RoleSpec:
    """Adds a role to the registry (a name taken already is refused)."""
    if spec.name in REGISTRY and REGISTRY[spec.name] is not spec:
        raise ValueError(f"role {spec.name!r} is registered already")
    REGISTRY[spec.name] = spec
    return spec
