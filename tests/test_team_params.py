"""The team agent's parameters: the shipped file, a file of one's own, and the errors of a bad one."""

from __future__ import annotations

import dataclasses
import math
import os
import time
from pathlib import Path

import pytest

from agents.policies import PolicyNameError, make_policy, policy_factory
from agents.team.params import ParameterError, TeamParams


def _write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "params.toml"
    path.write_text(text, encoding="utf-8")
    return path


def test_the_shipped_file_sets_every_key_within_its_bounds() -> None:
    params = TeamParams.default()
    for table in dataclasses.fields(params):
        section = getattr(params, table.name)
        for f in dataclasses.fields(section):
            value = getattr(section, f.name)
            if f.metadata.get("switch"):
                assert isinstance(value, bool), f"{table.name}.{f.name}"
                continue
            assert f.metadata["low"] <= value <= f.metadata["high"], f"{table.name}.{f.name}"
    assert params.kick.align_rad == math.radians(35.0)
    assert isinstance(params.head.shot_top_frame_every, int)


def test_a_file_of_ones_own_changes_only_the_keys_it_names(tmp_path: Path) -> None:
    params = TeamParams.load(_write(tmp_path, "[kick]\nalign_deg = 20\n\n[head]\nshot_top_frame_every = 2\n"))
    default = TeamParams.default()
    assert params.kick.align_deg == 20.0 and isinstance(params.kick.align_deg, float)
    assert params.kick.align_rad == math.radians(20.0)
    assert params.head.shot_top_frame_every == 2
    assert params.kick.shooting_range_m == default.kick.shooting_range_m
    assert params.side_tap == default.side_tap
    assert params.replace(kick={"align_deg": 35.0}).kick == default.kick


@pytest.mark.parametrize("text, key, expected", [
    ("[kick]\nalign_deg = 400\n", "kick.align_deg", "a number from 0.0 to 180.0"),
    ("[kick]\nalign_deg = \"wide\"\n", "kick.align_deg", "a number"),
    ("[kick]\nalign_deg = true\n", "kick.align_deg", "a number"),
    ("[kick]\nalign_deg = nan\n", "kick.align_deg", "a number"),
    ("[head]\nshot_top_frame_every = 2.5\n", "head.shot_top_frame_every", "an integer from 1 to 100"),
    ("[clear_line]\nenabled = 1\n", "clear_line.enabled", "true or false"),
    ("[kick]\naling_deg = 20\n", "kick.aling_deg", "one of the keys align_deg,"),
    ("[kicks]\nalign_deg = 20\n", "kicks", "one of the tables ball,"),
    ("kick = 3\n", "kick", "a table"),
    ("[kick\n", "(file)", "TOML"),
])
def test_a_bad_value_is_refused_naming_file_key_value_and_what_was_expected(
        tmp_path: Path, text: str, key: str, expected: str) -> None:
    path = _write(tmp_path, text)
    with pytest.raises(ParameterError) as raised:
        TeamParams.load(path)
    error = raised.value
    assert error.path == str(path) and error.key == key and expected in error.expected
    assert str(error).startswith(f"{path}: {key}")


def test_a_missing_file_is_refused(tmp_path: Path) -> None:
    with pytest.raises(ParameterError, match="readable TOML file"):
        TeamParams.load(tmp_path / "nowhere.toml")


@pytest.mark.parametrize("kind, words", [
    ("pipe", "not a regular file"), ("zero", "not a regular file"), ("big", "more than 1000000 bytes"),
    ("dotted key", "a dotted key of more than 64 parts"), ("deep", "nested deeper than the parser can follow"),
])
def test_a_hostile_parameter_file_is_refused_before_it_is_parsed(tmp_path: Path, kind: str, words: str) -> None:
    path = tmp_path / "p.toml"
    if kind == "pipe":
        os.mkfifo(path)
    elif kind == "zero":
        path.symlink_to("/dev/zero")
    elif kind == "big":
        path.write_text("# " + "x" * 1_000_000 + "\n")
    elif kind == "dotted key":
        path.write_text("kick" + ".a" * 20_000 + " = 1\n")  # the parser's time grows with the square of the parts
    else:
        path.write_text("x = " + "[" * 100_000 + "]" * 100_000 + "\n")
    started = time.perf_counter()
    with pytest.raises(PolicyNameError, match=words):
        policy_factory(f"team:{path}")
    assert time.perf_counter() - started < 1.0


def test_a_policy_name_plays_a_team_agent_with_a_parameter_file(tmp_path: Path) -> None:
    path = _write(tmp_path, "[kick]\nalign_deg = 20\n")
    agent = make_policy(f"team:{path}")
    assert agent.params.kick.align_deg == 20.0
    thesis = make_policy(f"team-thesis:{path}")
    assert thesis.method == "thesis" and thesis.params.kick.align_deg == 20.0
    assert make_policy("team").params == TeamParams.default()


def test_a_bad_parameter_file_or_a_policy_without_parameters_is_refused_by_name(tmp_path: Path) -> None:
    bad = _write(tmp_path, "[kick]\nalign_deg = -1\n")
    with pytest.raises(PolicyNameError, match=r"kick\.align_deg = -1: expected a number from 0.0 to 180.0"):
        policy_factory(f"team:{bad}")
    with pytest.raises(PolicyNameError, match="scripted takes no parameter file"):
        policy_factory(f"scripted:{bad}")
