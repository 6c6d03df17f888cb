"""The supporter: behind the ball, off to the side."""

from __future__ import annotations

from agents.behavior.tactics.roles import supporter_spot
from agents.radio import Role
from agents.team.behavior.roles.positioning import Positioning
from agents.team.behavior.roles.registry import RoleSpec, register

SUPPORTER = register(RoleSpec(Role.SUPPORTER, lambda kit: Positioning(kit.params, supporter_spot),
                              "behind the ball, off to the side"))
