"""Typed errors of the vision pipeline."""

from __future__ import annotations


class VisionError(Exception):
    """Base class of the errors raised by :mod:`agents.vision`."""


class VisionInputError(VisionError, ValueError):
    """A camera frame or its head angles are not what the pipeline accepts."""


class ColorTableError(VisionError, ValueError):
    """A colour-threshold file is missing, malformed or inconsistent."""


class VisionConfigError(VisionError, ValueError):
    """A vision setting (camera model name, threshold, scan plan) is not allowed."""
