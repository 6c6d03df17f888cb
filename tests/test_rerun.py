"""``robotstadium rerun``: a match played again from its summary alone, its refusals and its report."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.render

ROOT = Path(__file__).resolve().parents[1]
POLICY = '''
from match.protocol import CameraChoice, Motion, make_action


class Walker:
    def reset(self, agent_id, seed):
        pass

    def act(self, observation):
        return make_action(Motion.WALK, walk=({speed}, 0.0, 0.2), camera=CameraChoice.OFF)
'''


def _robotstadium(cwd: Path, *argv: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "scenarios.cli", *argv], cwd=cwd, capture_output=True, text=True,
                          env={**os.environ, "PYTHONPATH": str(ROOT)}, timeout=300)


@pytest.fixture(scope="module")
def played(tmp_path_factory) -> Path:
    """A short match of a user's policy (its module in the working directory) in controller processes."""
    work = tmp_path_factory.mktemp("rerun")
    (work / "walkers.py").write_text(POLICY.format(speed=0.1), encoding="utf-8")
    done = _robotstadium(work, "match", "--home", "walkers:Walker", "--away", "stand", "--home-players", "2",
                         "--away-players", "1", "--half-seconds", "2", "--no-shootout", "--no-progress",
                         "--no-replay", "--out", "original")
    assert done.returncode == 0, done.stderr
    return work


def test_a_match_played_again_from_its_directory_is_the_same(played: Path) -> None:
    done = _robotstadium(ROOT, "rerun", str(played / "original"), "--out", str(played / "again"), "--no-progress")
    assert done.returncode == 0, done.stderr
    assert "identical" in done.stdout
    for name in ("events.jsonl", "match_log.npz"):
        assert (played / "original" / name).read_bytes() == (played / "again" / name).read_bytes()
    assert json.loads((played / "again" / "rerun.json").read_text())["identical"] is True


def test_a_changed_policy_file_is_refused_then_forced_and_the_first_difference_reported(played: Path) -> None:
    (played / "walkers.py").write_text(POLICY.format(speed=0.2), encoding="utf-8")
    try:
        refused = _robotstadium(played, "rerun", "original", "--out", "changed", "--no-progress")
        assert refused.returncode == 2 and not (played / "changed").exists()
        assert refused.stderr.count("\n") <= 2 and "walkers.py" in refused.stderr and "--force" in refused.stderr
        forced = _robotstadium(played, "rerun", "original", "--out", "changed", "--force", "--no-progress")
        assert forced.returncode == 1, forced.stderr
        record = json.loads((played / "changed" / "rerun.json").read_text())
        assert record["identical"] is False and record["forced_over"]
        first = record["first_difference"]
        assert first["file"] == "match_log.npz" and first["robot"] in ("home_0", "home_1") and first["step"] > 0
        assert "differs" in forced.stdout
    finally:
        (played / "walkers.py").write_text(POLICY.format(speed=0.1), encoding="utf-8")


def test_a_record_without_who_played_is_refused_with_one_line(tmp_path: Path) -> None:
    old = tmp_path / "old"
    old.mkdir()
    (old / "summary.json").write_text(json.dumps({"seed": 0, "config": {}}), encoding="utf-8")
    done = _robotstadium(ROOT, "rerun", str(old), "--out", str(tmp_path / "new"))
    assert done.returncode == 2 and "played_by" in done.stderr and "Traceback" not in done.stderr
    assert not (tmp_path / "new").exists()


def test_a_tournament_match_is_played_again_from_its_directory(tmp_path: Path) -> None:
    done = _robotstadium(tmp_path, "tournament", "scripted", "stand", "--matches", "2", "--players", "1",
                         "--half-seconds", "2", "--pauses", "0.2,0.4,0.2", "--no-shootout", "--no-replay",
                         "--no-progress", "--workers", "1", "--out", "t")
    assert done.returncode == 0, done.stderr
    match = tmp_path / "t" / "matches" / "001"  # the second match: the policies at the other ends
    summary = json.loads((match / "summary.json").read_text())
    assert {record["policy"] for record in summary["played_by"]["policies"].values()} == {"scripted", "stand"}
    done = _robotstadium(tmp_path, "rerun", str(match), "--out", "again", "--no-progress")
    assert done.returncode == 0, done.stderr
    for name in ("events.jsonl", "match_log.npz"):
        assert (match / name).read_bytes() == (tmp_path / "again" / name).read_bytes()


def test_a_record_played_with_other_numpy_kernels_is_refused_unless_forced(played: Path) -> None:
    from scenarios.matches.rerun import RerunError, rerun_plan

    summary = json.loads((played / "original" / "summary.json").read_text())
    rerun_plan(summary)  # as recorded: it plays
    summary["machine"]["numpy_simd"] = [*summary["machine"]["numpy_simd"], "X86_V5"]
    with pytest.raises(RerunError, match="numpy's SIMD kernels"):
        rerun_plan(summary)
    assert any("numpy's SIMD kernels" in warning for warning in rerun_plan(summary, force=True).warnings)
