"""Typed errors of self-localization."""

from __future__ import annotations


class LocalizationError(Exception):
    """Base class of the errors raised by :mod:`agents.localization`."""


class LocalizationInputError(LocalizationError, ValueError):
    """A pose, displacement or percept handed to a localizer is not what it accepts."""


class LocalizationConfigError(LocalizationError, ValueError):
    """A localizer name or option is not allowed."""
