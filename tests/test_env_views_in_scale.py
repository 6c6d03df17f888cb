"""Every learner view's observations lie in its space and within its documented scale over 1,000 steps of a
real match: 2 v 2 with the referee's pauses, random choices of motion, head, camera and radio symbol, a ball
put out once for a throw-in."""

from __future__ import annotations

import numpy as np
import pytest

from agents.learning import PerceptObservations
from match import parallel_env
from match.protocol import CameraChoice
from match.referee import RefereeConfig
from match.game import MatchConfig
from match.wrappers import ActionSet, DiscreteActions, FlatObservations, ImageObservations

pytestmark = [pytest.mark.render, pytest.mark.slow]

STEPS = 1000
OUT_AT_STEP = 400  # the ball is put over the side line then: a throw-in follows


def test_every_learner_view_stays_in_its_space_and_scale_for_1000_steps():
    referee = RefereeConfig(initial_seconds=1.0, ready_seconds=2.0, set_seconds=1.0)
    env = DiscreteActions(parallel_env(2, 2, config=MatchConfig(referee=referee)),
                          ActionSet(cameras=(CameraChoice.TOP, CameraChoice.BOTTOM, CameraChoice.OFF),
                                    radio_symbols=3))
    raw = env.unwrapped
    views = {
        "image": ImageObservations(raw),
        "flat": FlatObservations(raw),
        "flat_radio": FlatObservations(raw, radio=True),
        "flat_units": FlatObservations(raw, scaled=False),
        "percepts": PerceptObservations(raw),
    }
    convert = {name: (view.percepts if name == "percepts" else view._convert) for name, view in views.items()}
    for agent in raw.possible_agents:
        env.action_space(agent).seed(raw.possible_agents.index(agent))
    observations, _ = env.reset(seed=3)
    seen = {name: [] for name in views}
    extremes = {name: [np.inf, -np.inf] for name in views}
    for step in range(STEPS):
        for agent, observation in observations.items():
            assert raw.observation_space(agent).contains(observation), (step, agent)
            for name, view in views.items():
                value = convert[name](observation) if name == "percepts" else convert[name](agent, observation)
                assert view.observation_space(agent).contains(value), (step, agent, name)
                extremes[name] = [min(extremes[name][0], float(value.min())), max(extremes[name][1], float(value.max()))]
                if agent == "home_1":
                    seen[name].append(value)
        if step == OUT_AT_STEP:
            raw.match.world.place_ball(0.5, 2.3)
        if not env.agents:
            observations, _ = env.reset()
        else:
            observations, *_ = env.step({a: env.action_space(a).sample() for a in env.agents})
    for name in ("flat", "flat_radio"):
        assert -1.0 <= extremes[name][0] and extremes[name][1] <= 1.0, name
        flags = {label: np.array([v[views[name].labels.index(label)] for v in seen[name]])
                 for label in ("motion_remaining_s/endless", "game/seconds_since_drop_in/none")}
        for label, values in flags.items():
            assert set(np.unique(values)) == {-1.0, 1.0}, (name, label)  # the flag both set and clear
    assert extremes["flat_units"][1] >= 1e5  # the placeholders the scaled views replace
    assert extremes["image"][0] == 0.0 and 200.0 < extremes["image"][1] <= 255.0
    assert extremes["percepts"][0] >= -np.pi - 1e-6 and extremes["percepts"][1] <= 10.0
    assert any(v[3] == 1.0 for v in seen["percepts"])  # the ball was seen
    raw.close()
