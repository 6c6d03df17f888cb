"""Shared fixtures: worlds are expensive to build (~0.4 s), so tests share them and reset."""

from __future__ import annotations

import pytest

from world.config import RobotSpec
from world.robot_model import TeamColor
from world.world import World


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
