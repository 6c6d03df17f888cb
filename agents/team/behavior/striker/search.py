"""The striker without any ball: follow its kick, then look near the feet standing, then turn to search."""

from __future__ import annotations

from agents.behavior import skills
from agents.radio import Intention
from agents.team.behavior.requests import MotionRequest
from agents.team.params import TeamParams
from match.protocol import Motion


def search(params: TeamParams, following_kick: bool, looking_near_feet: bool) -> MotionRequest:
    """``following_kick``: a kick of its own went off lately (walk on ahead, ``kick.follow_kick_mps``);
    ``looking_near_feet``: the head's first look of its search is not done (stand while it looks)."""
    if following_kick:
        return MotionRequest(Motion.WALK, skills.walk_command(params.kick.follow_kick_mps, 0.0, 0.0), Intention.SEARCH)
    if looking_near_feet:
        return MotionRequest(Motion.STAND, skills.STILL, Intention.SEARCH)
    return MotionRequest(Motion.WALK, skills.walk_command(0.0, 0.0, skills.SEARCH_TURN_RADPS), Intention.SEARCH)
