"""Checks of what callers hand to a localizer: typed errors for wrong types, unusable percepts dropped."""

from __future__ import annotations

import logging
import math
import numbers
from collections.abc import Sequence

from agents.localization.errors import LocalizationInputError
from agents.vision.percepts import CornerShape, LandmarkPercept
from match.protocol import Displacement
from world.field import FIELD, GoalColor, LandmarkId, LandmarkKind, Pose2D, normalize_angle

LOG = logging.getLogger(__name__)

# No landmark is farther from a robot on the carpet than the carpet's diagonal.
MAX_DISTANCE_M = math.hypot(2.0 * FIELD.carpet_half_length, 2.0 * FIELD.carpet_half_width)


def _finite_number(value: object) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool) and math.isfinite(value)


def checked_pose(pose: object) -> Pose2D:
    """``pose`` with its angle normalized; :class:`LocalizationInputError` unless a finite Pose2D."""
    if not isinstance(pose, Pose2D) or not all(_finite_number(v) for v in (pose.x, pose.y, pose.theta)):
        raise LocalizationInputError(f"pose must be a Pose2D with finite x, y, theta; got {pose!r}")
    return Pose2D(float(pose.x), float(pose.y), normalize_angle(float(pose.theta)))


def checked_displacement(displacement: object) -> Displacement:
    """``displacement`` itself; :class:`LocalizationInputError` unless a finite Displacement."""
    values = (
        (displacement.forward_m, displacement.left_m, displacement.turn_rad) if isinstance(displacement, Displacement) else ()
    )
    if not values or not all(_finite_number(v) for v in values):
        raise LocalizationInputError(
            f"displacement must be a Displacement with finite forward_m, left_m, turn_rad; got {displacement!r}"
        )
    return displacement


def usable_percepts(percepts: object) -> tuple[LandmarkPercept, ...]:
    """The percepts a localizer can use: a finite bearing and a distance in [0, MAX_DISTANCE_M].

    Raises :class:`LocalizationInputError` when ``percepts`` is not a sequence of
    :class:`LandmarkPercept` (or one names its landmark, goal or corner shape with a value
    of the wrong type, or a landmark of another kind); drops (with a debug log) percepts whose measurements are NaN,
    infinite, negative or beyond any landmark, which vision may produce and which mean
    "nothing usable".
    """
    if isinstance(percepts, (str, bytes)) or not isinstance(percepts, Sequence):
        raise LocalizationInputError(f"percepts must be a sequence of LandmarkPercept; got {percepts!r}")
    kept: list[LandmarkPercept] = []
    for percept in percepts:
        if not isinstance(percept, LandmarkPercept) or not isinstance(percept.kind, LandmarkKind):
            raise LocalizationInputError(f"percepts must be LandmarkPercept instances; got {percept!r}")
        for name, kind in (("landmark_id", LandmarkId), ("goal", GoalColor), ("corner", CornerShape)):
            value = getattr(percept, name)
            if value is not None and not isinstance(value, kind):
                raise LocalizationInputError(f"percept {name} must be a {kind.__name__} or None; got {value!r}")
        if percept.landmark_id is not None and FIELD.landmark(percept.landmark_id).kind is not percept.kind:
            raise LocalizationInputError(
                f"percept of kind {percept.kind.value} names landmark {percept.landmark_id.value} of another kind"
            )
        usable = _finite_number(percept.distance_m) and _finite_number(percept.bearing_rad)
        usable = usable and 0.0 <= percept.distance_m <= MAX_DISTANCE_M
        if usable:
            kept.append(percept)
        else:
            LOG.debug("dropped unusable percept %r", percept)
    return tuple(kept)
