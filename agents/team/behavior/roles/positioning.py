"""A role that walks to its spot (:mod:`agents.behavior.tactics.roles`), holding it at the other team's kick-off."""

from __future__ import annotations

from collections.abc import Callable

from agents.behavior import skills
from agents.behavior.tactics.roles import position_from_spot
from agents.radio import Intention
from agents.team.behavior.requests import MotionRequest
from agents.team.behavior.roles.registry import Situation
from agents.team.behavior.set_plays.kickoff_lane import HOLD, holds_lane
from agents.team.modelling.representations import WorldModel
from agents.team.params import TeamParams

Spot = Callable[[float, float], tuple[float, float]]


class Positioning:
    """Plays a role by its spot (own-goal frame, a function of the ball there)."""

    def __init__(self, params: TeamParams, spot: Spot, keeps_kickoff_lane: bool = True):
        self.params, self.spot, self.keeps_kickoff_lane = params, spot, keeps_kickoff_lane

    def play(self, world: WorldModel, situation: Situation) -> MotionRequest:
        if self.keeps_kickoff_lane and holds_lane(world, self.params):
            return HOLD
        target = position_from_spot(self.spot, situation.play_xy, world.game.attack)
        return MotionRequest.of(skills.walk_to(world.robot.pose_field, target), Intention.POSITION)
