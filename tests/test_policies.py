"""Policies by name and the typed observation every agent decodes."""

from __future__ import annotations

import numpy as np
import pytest

from agents.behavior.policies.scan_localize import ScanLocalizeAgent
from agents.behavior.policies.scripted import ScriptedPlayer
from agents.behavior.policies.stand import StandPolicy
from agents.observation import Observation, ObservationError
from agents.policies import BUILTIN_POLICIES, PolicyNameError, make_policy, policy_factory
from match.protocol import CameraChoice, GameState, GoalColor, Motion, observation_space
from match.protocol import Policy
from tests.user_policies import Spinner


@pytest.mark.parametrize(
    "name, cls", [("scripted", ScriptedPlayer), ("scan_localize", ScanLocalizeAgent), ("stand", StandPolicy)]
)
def test_builtin_names_build_their_policy(name: str, cls: type) -> None:
    policy = make_policy(name)
    assert isinstance(policy, cls) and isinstance(policy, Policy)


def test_a_user_class_is_found_by_its_import_path() -> None:
    assert policy_factory("tests.user_policies:Spinner") is Spinner
    assert isinstance(make_policy("tests.user_policies:Spinner"), Spinner)


@pytest.mark.parametrize(
    "name, words",
    [
        ("striker", "unknown policy 'striker'"),
        ("", "unknown policy ''"),
        ("tests.no_such_module:Foo", "cannot import module 'tests.no_such_module'"),
        ("tests.user_policies:Missing", "has no class or function 'Missing'"),
        ("tests.user_policies:NOT_A_CLASS", "has no class or function 'NOT_A_CLASS'"),
        ("tests.user_policies:NoReset", "has no reset() method"),
        ("tests.user_policies:", "unknown policy"),
        ("os:system; rm", "unknown policy"),
        ("os:system", "system is a builtin_function_or_method, not a policy class; expected a class with reset("),
        ("os:getcwd", "getcwd is a builtin_function_or_method, not a policy class"),
        ("builtins:object", "object has no reset() method"),
        ("functools:partial", "partial has no reset() method"),
        ("tests.user_policies:unmarked_builder", "unmarked_builder is a function, not a policy class"),
    ],
)
def test_bad_names_are_refused_naming_the_known_ones(name: str, words: str) -> None:
    with pytest.raises(PolicyNameError) as error:
        make_policy(name)
    assert words in str(error.value)
    if "unknown" in words:
        for known in BUILTIN_POLICIES:
            assert known in str(error.value)


def test_a_marked_builder_stands_for_a_policy_as_a_class_does() -> None:
    from tests.user_policies import spinner_builder

    assert policy_factory("tests.user_policies:spinner_builder") is spinner_builder
    assert isinstance(make_policy("tests.user_policies:spinner_builder"), Spinner)


def test_bad_options_are_refused_with_the_name() -> None:
    with pytest.raises(PolicyNameError, match="'stand' cannot be built with options \\['speed'\\]"):
        make_policy("stand", speed=3)


def _sample_observation(seed: int = 0) -> dict:
    space = observation_space()
    space.seed(seed)
    return space.sample()


def test_observation_view_reads_every_field() -> None:
    raw = _sample_observation()
    obs = Observation.of(raw)
    assert Observation.of(obs) is obs
    assert obs.camera is CameraChoice(int(raw["camera"]))
    assert (obs.image is None) == (obs.camera is CameraChoice.OFF)
    assert obs.head_yaw_rad == float(raw["head"][0]) and obs.head_pitch_rad == float(raw["head"][1])
    assert obs.gyro_radps == tuple(float(v) for v in raw["gyro"])
    assert obs.game.state is GameState(int(raw["game"]["state"]))
    assert obs.game.defended_goal is (GoalColor.BLUE if int(raw["game"]["defended_goal"]) == 0 else GoalColor.YELLOW)
    assert obs.player == int(raw["game"]["player"])
    assert obs.odometry.forward_m == float(raw["odometry"][0])
    assert len(obs.packets) == int(raw["radio"]["count"])
    for i, packet in enumerate(obs.packets):
        assert packet.sender == int(raw["radio"]["sender"][i])
        assert packet.data == raw["radio"]["data"][i][: int(raw["radio"]["length"][i])].tobytes()
    assert obs.motion is None or isinstance(obs.motion, Motion)


def test_observation_view_is_frozen() -> None:
    obs = Observation.of(_sample_observation(1))
    with pytest.raises(AttributeError):
        obs.fallen = True  # type: ignore[misc]


@pytest.mark.parametrize("key", ["camera", "head", "game", "radio", "odometry"])
def test_observation_without_a_key_is_refused_naming_it(key: str) -> None:
    raw = _sample_observation(2)
    del raw[key]
    with pytest.raises(ObservationError, match=repr(key)):
        Observation.of(raw)


@pytest.mark.parametrize("bad", [None, 3, "obs", [1, 2]])
def test_observation_of_another_type_is_refused(bad: object) -> None:
    with pytest.raises(ObservationError, match="must be a dict"):
        Observation.of(bad)  # type: ignore[arg-type]


def test_observation_with_a_bad_head_is_refused() -> None:
    raw = _sample_observation(3)
    raw["head"] = np.zeros(3, dtype=np.float32)
    with pytest.raises(ObservationError, match="head must be"):
        Observation.of(raw)
