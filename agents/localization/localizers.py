"""The localizers an agent can choose from, behind one interface, by name.

Use: ``reset(pose)`` at kick-off positions; ``move(displacement)`` after each finished
motion with its nominal displacement; ``localize(percepts)`` after each head scan. Every
localizer answers ``localize`` with a :class:`PoseEstimate`, or None when the scan gave no
usable percept (empty, or every measurement NaN) or it knows no pose yet; its belief
(``pose``) is then kept. Wrong input types, NaN poses or displacements raise
:class:`LocalizationInputError` and change nothing.

Names: ``thesis`` (constraint-based with the odometer rules, thesis chapter 5),
``particle`` (Monte Carlo localization), ``hybrid`` (particle filter corrected by the
constraint solver), ``odometry`` (the odometer alone).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from typing import Protocol, runtime_checkable

from agents.localization.errors import LocalizationConfigError
from agents.localization.estimate import EstimateSource, PoseEstimate
from agents.localization.hybrid import HybridLocalizer
from agents.localization.odometry import Odometer
from agents.localization.particle import ParticleConfig, ParticleLocalizer
from agents.localization.thesis_method import ThesisConfig, ThesisLocalizer
from agents.localization.validation import usable_percepts
from agents.vision.percepts import LandmarkPercept
from match.protocol import Displacement
from world.field import Pose2D


@runtime_checkable
class Localizer(Protocol):
    """What every localizer offers (module docstring)."""

    name: str

    @property
    def pose(self) -> Pose2D | None:
        """The current belief (None until known)."""

    def reset(self, pose: Pose2D) -> None:
        """Set the pose (kick-off positions)."""

    def move(self, displacement: Displacement) -> None:
        """Account for a finished motion's nominal displacement."""

    def localize(self, percepts: Sequence[LandmarkPercept]) -> PoseEstimate | None:
        """Estimate the pose from a head scan's percepts."""


class OdometryLocalizer:
    """The odometer alone (thesis 5.5): percepts are checked but never change the pose."""

    name = "odometry"

    def __init__(self, initial_pose: Pose2D | None = None):
        self.odometer = Odometer(initial_pose)

    @property
    def pose(self) -> Pose2D | None:
        return self.odometer.pose

    def reset(self, pose: Pose2D) -> None:
        self.odometer.reset(pose)

    def move(self, displacement: Displacement) -> None:
        self.odometer.move(displacement)

    def localize(self, percepts: Sequence[LandmarkPercept]) -> PoseEstimate | None:
        pose = self.odometer.pose
        if not usable_percepts(percepts) or pose is None:
            return None
        return PoseEstimate(pose.x, pose.y, pose.theta, self.name, EstimateSource.ODOMETER)


def _build_thesis(seed: int | None, initial_pose: Pose2D | None, **options: object) -> Localizer:
    return ThesisLocalizer(_config(ThesisConfig, "thesis", options), initial_pose=initial_pose)


def _build_particle(seed: int | None, initial_pose: Pose2D | None, **options: object) -> Localizer:
    return ParticleLocalizer(_config(ParticleConfig, "particle", options), seed, initial_pose=initial_pose)


def _build_hybrid(seed: int | None, initial_pose: Pose2D | None, **options: object) -> Localizer:
    return HybridLocalizer(_config(ParticleConfig, "hybrid", options), seed, initial_pose=initial_pose)


def _build_odometry(seed: int | None, initial_pose: Pose2D | None, **options: object) -> Localizer:
    if options:
        raise LocalizationConfigError(f"localizer 'odometry' takes no options; got {sorted(options)}")
    return OdometryLocalizer(initial_pose)


LOCALIZERS: dict[str, Callable[..., Localizer]] = {
    "thesis": _build_thesis,
    "particle": _build_particle,
    "hybrid": _build_hybrid,
    "odometry": _build_odometry,
}


def _config(kind: type, name: str, options: dict[str, object]):
    allowed = sorted(f.name for f in dataclasses.fields(kind))
    unknown = sorted(set(options) - set(allowed))
    if unknown:
        raise LocalizationConfigError(f"unknown option(s) {unknown} for localizer {name!r}; expected some of {allowed}")
    return dataclasses.replace(kind(), **options)


def localizer(name: str, seed: int | None = None, initial_pose: Pose2D | None = None, **options: object) -> Localizer:
    """The localizer called ``name`` (one of :data:`LOCALIZERS`), with config fields as ``options``.

    ``seed`` seeds the particle filters' generator; ``initial_pose`` is as a first
    ``reset``. Raises :class:`LocalizationConfigError` for an unknown name or option.
    """
    if not isinstance(name, str) or name not in LOCALIZERS:
        raise LocalizationConfigError(f"unknown localizer {name!r}; expected one of {sorted(LOCALIZERS)}")
    return LOCALIZERS[name](seed, initial_pose, **options)
