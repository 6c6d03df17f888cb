"""Who plays what: this robot's role from its time to the ball and its teammates' last messages.

The rules are :func:`agents.behavior.tactics.roles.assign_role`'s (the striker keeps its role unless another is
faster by a margin); here the candidates come from the team model. A goalkeeper that heard no teammate
for :data:`~agents.behavior.skills.LONE_SILENCE_S` plays alone (a team of one, or every teammate
silent): it plays the field. In a penalty shoot-out the kicking team's robot on the field strikes, the
other team's player 0 keeps the goal, everyone else (held off the field) stands.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from agents.behavior import skills
from agents.behavior.tactics.roles import FIELD_ROLES, Candidate, assign_role, time_to_ball
from agents.radio import Role
from agents.team.modelling.representations import WorldModel


def lone(world: WorldModel) -> bool:
    """Whether this goalkeeper plays alone (:func:`agents.behavior.skills.plays_alone`, shared with the
    scripted policy)."""
    return skills.plays_alone(world.player, world.team.silent_for_s)


def assign(world: WorldModel, play_xy: tuple[float, float] | None, current: str,
           field_roles: Sequence[str] = FIELD_ROLES) -> tuple[str, float]:
    """This robot's role and its time to the ball at ``play_xy`` (s; inf without a ball)."""
    pose = world.robot.pose_field
    own_time = math.inf if play_xy is None else time_to_ball(pose, play_xy, world.posture.fallen)
    others = [Candidate(m.message.player, m.message.time_to_ball_s, m.message.role == Role.STRIKER)
              for m in world.team.teammates if not m.message.fallen]
    role = assign_role(Candidate(world.player, own_time), others, current, lone=lone(world), field_roles=field_roles)
    return role, own_time


def shootout_role(world: WorldModel) -> str:
    if world.game.own_kickoff:
        return Role.STRIKER
    return Role.GOALKEEPER if world.player == 0 else Role.NONE
