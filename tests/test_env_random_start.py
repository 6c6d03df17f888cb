"""The env's ``reset(options={"random_start": True})``: start poses drawn from the seed."""

from __future__ import annotations

import math

import numpy as np
import pytest

from match.env import RobotStadiumEnv
from match.errors import MatchConfigError
from match.game import RANDOM_START_MARGIN_M, RANDOM_START_SPACING_M
from world.field import FIELD


def _poses(env: RobotStadiumEnv) -> dict[str, tuple[float, float, float]]:
    return {agent: robot["pose"] for agent, robot in env.match.truth()["robots"].items()}


@pytest.fixture(scope="module")
def env():
    env = RobotStadiumEnv(2, 2)
    yield env
    env.close()


def test_random_starts_are_drawn_from_the_seed_inside_the_field_and_apart(env) -> None:
    def starts(seed: int, random_start: bool) -> dict[str, tuple[float, float, float]]:
        env.reset(seed=seed, options={"random_start": random_start})
        return _poses(env)

    kickoff, first, again, other = starts(5, False), starts(5, True), starts(5, True), starts(6, True)
    assert first == again  # the same seed, the same starts
    assert first != other and first != kickoff
    ball = env.match.truth()["ball"]["position"]
    points = [(x, y) for x, y, _ in other.values()]
    for x, y in points:
        assert abs(x) <= FIELD.half_length - RANDOM_START_MARGIN_M + 0.05
        assert abs(y) <= FIELD.half_width - RANDOM_START_MARGIN_M + 0.05
        assert math.hypot(x - ball[0], y - ball[1]) >= RANDOM_START_SPACING_M - 0.05
    for i, a in enumerate(points):
        for b in points[i + 1:]:
            assert math.hypot(a[0] - b[0], a[1] - b[1]) >= RANDOM_START_SPACING_M - 0.05


def test_the_same_random_start_gives_the_same_observations(env) -> None:
    one, _ = env.reset(seed=11, options={"random_start": True})
    two, _ = env.reset(seed=11, options={"random_start": True})
    for agent in one:
        assert one[agent]["image"] is not None and np.array_equal(one[agent]["image"], two[agent]["image"])


@pytest.mark.parametrize("options", [{"random_start": 1}, {"random_start": "yes"}, ["random_start"], "random_start"])
def test_bad_reset_options_are_refused_before_anything_changes(env, options) -> None:
    env.reset(seed=3)
    env.step({agent: {} for agent in env.agents})
    before = (env.match.step_index, _poses(env), list(env.agents))
    with pytest.raises(MatchConfigError) as error:
        env.reset(seed=4, options=options)
    assert "option" in str(error.value)
    assert (env.match.step_index, _poses(env), list(env.agents)) == before


def test_other_options_are_ignored_with_a_warning(env, caplog) -> None:
    """PettingZoo's own API test resets with options of its own."""
    env.reset(seed=5)
    kickoff = _poses(env)
    env.reset(seed=5, options={"random_starts": True})
    assert _poses(env) == kickoff and "random_starts" in caplog.text

