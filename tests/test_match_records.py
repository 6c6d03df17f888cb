"""A match's summary says who played, where, with which seeds and settings (scenarios.matches.provenance)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from match.controllers import ControllerLimits
from scenarios.matches.play import Lineup, run_lineup_match
from scenarios.matches.provenance import file_hash, lineup_record, policy_record

pytestmark = pytest.mark.render

USER_POLICY = "tests.user_policies:Counted"


def _strict_json(text: str) -> dict:
    def refuse(constant: str) -> None:
        raise ValueError(f"{constant} is not JSON")

    return json.loads(text, parse_constant=refuse)


def test_the_summary_names_every_robots_policy_its_controllers_seeds_and_settings(tmp_path: Path) -> None:
    lineup = Lineup("stand", USER_POLICY)
    run_lineup_match(tmp_path, lineup, home=1, away=1, half_seconds=1.0, seed=3, shootout=False, progress=False,
                     max_steps=5, controllers=ControllerLimits(group="robot"))
    summary = _strict_json((tmp_path / "summary.json").read_text(encoding="utf-8"))
    policies = summary["played_by"]["policies"]
    assert policies["home_0"] == {"policy": "stand"}
    user_file = Path(__file__).parent / "user_policies.py"
    assert policies["away_0"] == {"policy": USER_POLICY, "file": str(user_file.resolve()),
                                  "file_hash": file_hash(user_file)}
    assert summary["played_by"]["controllers"] == {"in_process": False, "step_budget_s": 0.5, "start_budget_s": 120.0,
                                                   "hang_s": 10.0, "memory_mb": 2048.0, "group": "robot"}
    assert set(summary["policy_seeds"]) == {"home_0", "away_0"} and summary["seed"] == 3
    config = summary["config"]
    assert config["referee"]["half_seconds"] == 1.0 and config["referee"]["shootout"] is False
    assert config["world"]["physics"]["substeps"] > 0 and config["world"]["render"]["renderer"] in ("numba", "tiny")
    assert isinstance(summary["command_line"], list)


def test_a_parameter_file_is_recorded_with_its_hash(tmp_path: Path) -> None:
    params = tmp_path / "mine.toml"
    params.write_text("[head]\nglance_every_s = 3.0\n", encoding="utf-8")
    record = policy_record(f"team:{params}")
    assert record == {"policy": f"team:{params}", "file": str(params.resolve()), "file_hash": file_hash(params)}
    params.write_text("[head]\nglance_every_s = 3.5\n", encoding="utf-8")
    assert policy_record(f"team:{params}")["file_hash"] != record["file_hash"]


def test_in_process_play_is_recorded_as_such() -> None:
    assert lineup_record({"home_0": "stand"}, None) == {"policies": {"home_0": {"policy": "stand"}},
                                                          "controllers": {"in_process": True}}
