"""The goalkeeper: on its line, following the ball's side; it leaves the line to clear a ball close to it
in its own goal area (``keeper.clear_ball_within_m``, ``keeper.clear_area_depth_m``), as the striker plays."""

from __future__ import annotations

from agents.behavior.tactics.roles import goalkeeper_spot
from agents.radio import Role
from agents.team.behavior.requests import MotionRequest
from agents.team.behavior.roles.positioning import Positioning
from agents.team.behavior.roles.registry import Kit, RoleSpec, Situation, register
from agents.team.modelling.representations import WorldModel
from world.field import FIELD


class Goalkeeper:
    def __init__(self, kit: Kit):
        self.params, self.striker = kit.params, kit.striker
        self.position = Positioning(kit.params, goalkeeper_spot, keeps_kickoff_lane=False)

    def play(self, world: WorldModel, situation: Situation) -> MotionRequest:
        if self.clears(world):
            return self.striker.play(world, situation.following_kick, situation.looking_near_feet)
        return self.position.play(world, situation)

    def clears(self, world: WorldModel) -> bool:
        ball = world.ball.recent
        if ball is None or ball.distance_m > self.params.keeper.clear_ball_within_m:
            return False
        return world.robot.pose_field.x * world.game.attack < -FIELD.half_length + self.params.keeper.clear_area_depth_m


GOALKEEPER = register(RoleSpec(Role.GOALKEEPER, Goalkeeper, "on its line; clears a ball close to it"))
