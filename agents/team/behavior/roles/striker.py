"""The striker role: plays the ball (:mod:`agents.team.behavior.striker.play`), or waits for a ball going out."""

from __future__ import annotations

from agents.radio import Role
from agents.team.behavior.requests import MotionRequest
from agents.team.behavior.roles.registry import Kit, RoleSpec, Situation, register
from agents.team.modelling.representations import WorldModel


class StrikerRole:
    def __init__(self, kit: Kit):
        self.striker = kit.striker

    def play(self, world: WorldModel, situation: Situation) -> MotionRequest:
        return self.striker.play(world, situation.following_kick, situation.looking_near_feet, situation.restart)


STRIKER = register(RoleSpec(Role.STRIKER, StrikerRole, "goes for the ball and kicks it at the goal"))
