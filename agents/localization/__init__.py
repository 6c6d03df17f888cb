"""Self-localization (thesis chapter 5): where the robot is, from a head scan's landmark percepts.

:func:`localizer` builds one by name (``thesis``, ``particle``, ``hybrid``, ``odometry``);
each has ``reset(pose)``, ``move(displacement)`` and ``localize(percepts)``.
"""

from agents.localization.circles import CircleCase, CircleIntersection, intersect_circles
from agents.localization.constraint import Candidate, ConstraintSolution, solve
from agents.localization.disambiguation import corner_table, disambiguate, junction_table
from agents.localization.errors import LocalizationConfigError, LocalizationError, LocalizationInputError
from agents.localization.estimate import EstimateSource, LandmarkObservation, PoseEstimate
from agents.localization.hybrid import HybridLocalizer
from agents.localization.localizers import LOCALIZERS, Localizer, OdometryLocalizer, localizer
from agents.localization.odometry import Odometer, compose
from agents.localization.particle import ParticleConfig, ParticleLocalizer
from agents.localization.thesis_method import ThesisConfig, ThesisLocalizer

__all__ = [
    "LOCALIZERS",
    "Candidate",
    "CircleCase",
    "CircleIntersection",
    "ConstraintSolution",
    "EstimateSource",
    "HybridLocalizer",
    "LandmarkObservation",
    "LocalizationConfigError",
    "LocalizationError",
    "LocalizationInputError",
    "Localizer",
    "Odometer",
    "OdometryLocalizer",
    "ParticleConfig",
    "ParticleLocalizer",
    "PoseEstimate",
    "ThesisConfig",
    "ThesisLocalizer",
    "compose",
    "corner_table",
    "disambiguate",
    "intersect_circles",
    "junction_table",
    "localizer",
    "solve",
]
