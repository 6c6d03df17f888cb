"""The shooting drill (examples/shooting_drill.py): a trial ends on its outcome, the results are written,
bad flags end it with exit code 2 before anything is written."""

from __future__ import annotations

import importlib.util
import json
import sys
from pathlib import Path

import pytest

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "shooting_drill.py"


@pytest.fixture(scope="module")
def drill():
    spec = importlib.util.spec_from_file_location("shooting_drill", EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclasses look their module up
    spec.loader.exec_module(module)
    return module


@pytest.mark.render
def test_a_short_drill_plays_its_trials_and_writes_them(drill, tmp_path) -> None:
    out = tmp_path / "drill"
    assert drill.main(["--trials", "2", "--seconds", "2", "--out", str(out)]) == 0
    results = json.loads((out / "results.json").read_text())
    assert [t["seed"] for t in results["trials"]] == [0, 1]
    for trial in results["trials"]:  # 2 s: the striker, 2 m or more away, has not reached the ball
        assert trial["outcome"] == "none" and trial["time_s"] == pytest.approx(2.0)
        assert 0.8 <= trial["ball_x"] <= 2.2 and abs(trial["ball_y"]) <= 1.2
    assert results["summary"]["outcomes"]["none"] == 2 and results["summary"]["goal_share"] == 0.0


@pytest.mark.parametrize("flags", [
    ["--trials", "0"], ["--trials", "nan"], ["--seconds", "601"], ["--seed", "-1"],
    ["--striker", "no_such_policy"], ["--keeper", "no.such.module:Keeper"],
])
def test_bad_flags_exit_2_and_write_nothing(drill, tmp_path, capsys, flags) -> None:
    out = tmp_path / "drill"
    with pytest.raises(SystemExit) as stopped:
        drill.main([*flags, "--out", str(out)])
    assert stopped.value.code == 2
    assert not out.exists()
    assert flags[0] in capsys.readouterr().err
