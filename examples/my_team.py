"""A team of one's own from the team agent's parts: a marker in place of the supporter.

Only this file is added: it registers a role (:mod:`agents.team.behavior.roles.registry`) with a free
radio code, and a :class:`Team` that is the ``team`` agent whose field players beside the striker
are a defender and this marker. The marker stands :data:`MARK_M` goal-side of the nearest opponent
it saw (field frame), facing it; with none seen, or while the other team's kick-off lane is kept,
it plays the supporter's spot. Play it as any policy of your own:

    robotstadium match --home examples.my_team:Team --away team --half-seconds 60 --out out/my_team

Everything else (the parameters, other roles, the striker's cards) is the ``team`` agent's; a
parameter file still applies: ``Team(params=TeamParams.load("mine.toml"))``.
"""

from __future__ import annotations

import math

from agents.behavior import skills
from agents.behavior.tactics.roles import supporter_spot
from agents.modelling.obstacle_model import ObstacleKind
from agents.radio import Intention, Role, register_role_code
from agents.team.agent import TeamAgent
from agents.team.behavior.requests import MotionRequest
from agents.team.behavior.roles.positioning import Positioning
from agents.team.behavior.roles.registry import REGISTRY, Kit, RoleSpec, Situation, register
from agents.team.behavior.root import Behavior
from agents.team.behavior.set_plays.kickoff_lane import holds_lane
from agents.team.modelling.representations import WorldModel
from match.protocol import Pose2D
from world.field import FIELD

MARKER = "marker"
MARKER_CODE = 16  # the radio's code for it (the built-in roles use 0-4)
MARK_M = 0.5  # goal-side of the opponent, this far (m)


class Marker:
    """The marker role's player."""

    def __init__(self, kit: Kit):
        self.params = kit.params
        self.otherwise = Positioning(kit.params, supporter_spot)

    def play(self, world: WorldModel, situation: Situation) -> MotionRequest:
        opponent = nearest_opponent(world)
        if opponent is None or holds_lane(world, self.params):
            return self.otherwise.play(world, situation)
        own_goal = (-world.game.attack * FIELD.half_length, 0.0)
        dx, dy = own_goal[0] - opponent[0], own_goal[1] - opponent[1]
        reach = math.hypot(dx, dy)
        share = min(MARK_M / reach, 1.0) if reach > 0.0 else 0.0
        x, y = opponent[0] + share * dx, opponent[1] + share * dy
        target = Pose2D(x, y, math.atan2(opponent[1] - y, opponent[0] - x))
        return MotionRequest.of(skills.walk_to(world.robot.pose_field, target), Intention.POSITION)


def nearest_opponent(world: WorldModel) -> tuple[float, float] | None:
    """The nearest robot of the other team it believes in (field frame), or None."""
    pose = world.robot.pose_field
    c, s = math.cos(pose.theta), math.sin(pose.theta)
    for o in world.obstacles.torso:  # nearest first
        if o.kind is ObstacleKind.OPPONENT:
            return pose.x + c * o.x_m - s * o.y_m, pose.y + s * o.x_m + c * o.y_m
    return None


if MARKER not in REGISTRY:
    register(RoleSpec(MARKER, Marker, "goal-side of the nearest opponent"))
register_role_code(MARKER, MARKER_CODE)


class Team(TeamAgent):
    """The team agent with a defender and a marker beside the striker."""

    def make_behavior(self) -> Behavior:
        return Behavior(self.params, field_roles=(Role.DEFENDER, MARKER))
