"""The goal-line drill (examples/goal_line_drill.py): the robots start where it puts them and the team agents
know it, a trial ends on its outcome, the results are written, bad flags end it with exit code 2 before
anything is written."""

from __future__ import annotations

import importlib.util
import json
import math
import sys
from pathlib import Path

import pytest

from agents.policies import make_policy
from match.protocol import Pose2D

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "goal_line_drill.py"


@pytest.fixture(scope="module")
def drill():
    spec = importlib.util.spec_from_file_location("goal_line_drill", EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclasses look their module up
    spec.loader.exec_module(module)
    return module


def test_a_placed_team_agent_believes_where_it_was_put(drill) -> None:
    pose = Pose2D(-2.2, 1.1, 2.5)
    placed = drill.Placed(make_policy("team"), pose)
    placed.reset("away_1", 0)
    believed = placed.policy.pose_estimate()
    assert math.dist(believed[:2], (pose.x, pose.y)) < 1e-9 and believed[2] == pytest.approx(pose.theta)


@pytest.mark.render
def test_a_short_drill_plays_its_trials_and_writes_them(drill, tmp_path) -> None:
    out = tmp_path / "drill"
    assert drill.main(["--trials", "2", "--seconds", "1", "--out", str(out)]) == 0
    results = json.loads((out / "results.json").read_text())
    assert [t["seed"] for t in results["trials"]] == [0, 1]
    for trial in results["trials"]:  # 1 s: nobody has moved the ball far
        assert trial["outcome"] == "none" and trial["time_s"] == pytest.approx(1.0)
        assert -2.95 <= trial["ball_x"] <= -2.7 and 0.9 <= abs(trial["ball_y"]) <= 1.5
    assert results["summary"]["outcomes"]["none"] == 2 and results["summary"]["goal_share"] == 0.0


@pytest.mark.parametrize("flags", [
    ["--trials", "0"], ["--seconds", "601"], ["--seed", "-1"], ["--defenders", "no_such_policy"],
    ["--attacker", "no.such.module:Attacker"],
])
def test_bad_flags_exit_2_and_write_nothing(drill, tmp_path, capsys, flags) -> None:
    out = tmp_path / "drill"
    with pytest.raises(SystemExit) as stopped:
        drill.main([*flags, "--out", str(out)])
    assert stopped.value.code == 2
    assert not out.exists()
    assert flags[0] in capsys.readouterr().err
