"""Which landmarks a frame showed, as indices into ``world.field.FIELD.landmarks`` (for the agent's report).

A percept is matched to a landmark as the particle filter's measurement model matches it
(:func:`agents.localization.measurement.possible_landmarks`): the landmark it names itself
(posts of known side, goal centres, the circle), else the one of its possible landmarks (a
post of its goal, any L corner, either T junction) nearest to where the robot's pose puts
the percept on the field. Evaluation only: the agent's play does not read it.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

from agents.localization.measurement import possible_landmarks
from agents.vision.percepts import LandmarkPercept
from match.protocol import Pose2D
from world.field import FIELD

_INDEX = {landmark.id: i for i, landmark in enumerate(FIELD.landmarks)}


def landmarks_seen(percepts: Iterable[LandmarkPercept], pose: Pose2D) -> frozenset[int]:
    """The indices into ``FIELD.landmarks`` of the landmarks ``percepts`` show, seen from ``pose`` (field frame)."""
    c, s = math.cos(pose.theta), math.sin(pose.theta)
    seen = set()
    for percept in percepts:
        options = possible_landmarks(percept)
        if not options:
            continue
        x = pose.x + c * percept.x_m - s * percept.y_m
        y = pose.y + s * percept.x_m + c * percept.y_m
        nearest = min(options, key=lambda landmark: math.hypot(landmark.x - x, landmark.y - y))
        seen.add(_INDEX[nearest.id])
    return frozenset(seen)
