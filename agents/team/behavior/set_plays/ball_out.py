"""A ball going out: the striker waits ``ball_out.throw_in_wait_back_m`` on its own side of the spot the
referee will put it back on (:mod:`agents.team.modelling.restart`), facing the opponent goal."""

from __future__ import annotations

import math

from agents.behavior import skills
from agents.radio import Intention
from agents.team.behavior.requests import MotionRequest
from match.protocol import Pose2D


def wait_pose(spot_xy: tuple[float, float], attack: float, back_m: float) -> Pose2D:
    """Where a striker waits for a ball going out (field frame): ``back_m`` on its own side of the spot
    the referee will put it on (on the throw-in line), facing the opponent goal."""
    return Pose2D(spot_xy[0] - attack * back_m, spot_xy[1], 0.0 if attack > 0 else math.pi)


def wait_for_restart(pose: Pose2D, spot_xy: tuple[float, float], attack: float, back_m: float) -> MotionRequest:
    return MotionRequest.of(skills.walk_to(pose, wait_pose(spot_xy, attack, back_m)), Intention.GO_TO_BALL)
