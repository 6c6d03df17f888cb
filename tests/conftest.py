"""Shared fixtures: worlds are expensive to build (~0.4 s), so tests share them and reset.

Hypothesis runs derandomized by default (profile ``repeatable``): the same examples in every
run, so a run passes or fails on the code, not on the draw. ``HYPOTHESIS_PROFILE=explore``
draws new examples each run to look for counterexamples; pin any it finds with ``@example``.
"""

from __future__ import annotations

import os

import pytest
from hypothesis import settings

from world.config import RobotSpec
from world.robot_model import TeamColor
from world.world import World

settings.register_profile("repeatable", derandomize=True, database=None)
settings.register_profile("explore")
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "repeatable"))


@pytest.fixture(scope="module")
def shared_world():
    world = World([RobotSpec("a", TeamColor.BLUE), RobotSpec("b", TeamColor.RED)])
    yield world
    world.close()


@pytest.fixture
def world(shared_world):
    """A two-robot world ("a" blue, "b" red) reset to its initial state with seed 0."""
    shared_world.reset(0)
    return shared_world
