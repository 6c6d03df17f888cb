"""Typed errors of the world. Every message names the bad value and what was expected."""

from __future__ import annotations


class WorldError(Exception):
    """Base class of everything the world refuses."""


class UnknownRobotError(WorldError, LookupError):
    def __init__(self, robot_id: object, known: tuple[str, ...]):
        super().__init__(f"unknown robot id {robot_id!r}; expected one of {list(known)}")
        self.robot_id = robot_id


class InvalidPoseError(WorldError, ValueError):
    """A pose or position that is not finite or lies outside the world."""


class JointLimitError(WorldError, ValueError):
    """A joint target outside the joint's range."""


class UnknownMotionError(WorldError, ValueError):
    """A motion name that is not in the catalogue."""


class InvalidCommandError(WorldError, ValueError):
    """A command with a value outside its allowed range (e.g. a walk velocity)."""


class UnknownCameraProfileError(WorldError, ValueError):
    """A camera profile name that is not one of the profiles (:mod:`world.camera_profiles`)."""

    def __init__(self, name: object, known: tuple[str, ...]):
        super().__init__(f"unknown camera profile {name!r}; expected one of {', '.join(known)}")
        self.name = name
