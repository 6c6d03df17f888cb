"""The defender: between the ball and its own goal, in its own half."""

from __future__ import annotations

from agents.behavior.tactics.roles import defender_spot
from agents.radio import Role
from agents.team.behavior.roles.positioning import Positioning
from agents.team.behavior.roles.registry import RoleSpec, register

DEFENDER = register(RoleSpec(Role.DEFENDER, lambda kit: Positioning(kit.params, defender_spot),
                             "between the ball and its own goal"))
