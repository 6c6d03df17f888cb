"""``robotstadium drill NAME``: every drill plays the trials recorded in tests/fixtures/drill_figures.json to
the same figures and writes results.csv, summary.json and table.md; --resume plays only the trials not kept;
a trial whose policy fails is listed and counts for nothing. (Refusals: tests/test_cli_refusals.py.)

The recorded trials are played by the command in a process of its own, as a user runs it: a trial's
figures can depend on the order in which a process first imported the simulation's native libraries."""

from __future__ import annotations

import csv
import json
import subprocess
import sys
from pathlib import Path

import pytest

from scenarios import cli
from scenarios.drills import run as drill_run

FIXTURE = Path(__file__).resolve().parent / "fixtures" / "drill_figures.json"
RECORDED = json.loads(FIXTURE.read_text(encoding="utf-8"))["drills"]
QUICK = ["shooting", "--striker", "stand", "--keeper", "stand", "--seconds", "1", "--trials", "3"]


class Broken:
    """A policy that cannot be built."""

    def __init__(self):
        raise RuntimeError("broken on purpose")

    def reset(self, agent_id: str, seed: int) -> None:
        pass

    def act(self, observation) -> dict:
        return {}


def _drill(argv: list[str], out: Path) -> int:
    return cli.main(["drill", *argv, "--workers", "1", "--no-progress", "--out", str(out)])


def _rows(out: Path) -> list[dict[str, str]]:
    with (out / "results.csv").open(encoding="utf-8", newline="") as handle:
        return list(csv.DictReader(handle))


def _as_csv(value: object) -> str:
    return "" if value is None else str(value)


@pytest.mark.render
@pytest.mark.parametrize("name", list(RECORDED))
def test_a_drill_gives_the_recorded_figures_and_writes_its_report(name: str, tmp_path: Path) -> None:
    recorded = RECORDED[name]
    out = tmp_path / name
    command = [sys.executable, "-m", "scenarios.cli", "drill", name, *recorded["flags"], "--workers", "1",
               "--no-progress", "--out", str(out)]
    done = subprocess.run(command, capture_output=True, text=True, timeout=600)
    assert done.returncode == cli.EXIT_OK, done.stderr
    summary = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    assert summary["summary"] == recorded["summary"]
    rows = _rows(out)
    assert len(rows) == len(recorded["trials"])
    for row, trial in zip(rows, recorded["trials"]):
        assert row["status"] == "ok" and {key: row[key] for key in trial} == {k: _as_csv(v) for k, v in trial.items()}
    seeds = [trial["seed"] for trial in recorded["trials"]]
    assert summary["seeds"]["first"] == seeds[0] and summary["seeds"]["last"] == seeds[-1]
    assert summary["trials"] == {"planned": len(seeds), "played": len(seeds), "failed": 0}
    policies = summary["played_by"]["policies"]
    assert policies and all(entry == {"policy": "team"} for entry in policies.values())
    assert set(summary["played_by"]["roles"].values()) == set(summary["settings"]["policies"])
    assert summary["command_line"] and summary["versions"]["robotstadium"] and summary["machine"]
    table = (out / "table.md").read_text(encoding="utf-8")
    assert summary["headline"] in table and f"| {rows[0]['outcome']} |" in table
    assert f"{len(seeds)} trials played, 0 failed" in done.stdout


@pytest.mark.render
def test_resume_plays_only_the_trials_not_kept(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    out = tmp_path / "drill"
    assert _drill(QUICK, out) == cli.EXIT_OK
    first = _rows(out)
    (out / "runs" / "trial_0001.json").unlink()
    played = []

    def counted(task, tick=None):
        played.append(task.index)
        return play_trial(task, tick)

    play_trial = drill_run.play_trial
    monkeypatch.setattr(drill_run, "play_trial", counted)
    assert _drill([*QUICK, "--resume"], out) == cli.EXIT_OK
    assert played == [1]
    assert [{k: v for k, v in row.items() if k != "wall_seconds"} for row in _rows(out)] == \
        [{k: v for k, v in row.items() if k != "wall_seconds"} for row in first]
    played.clear()
    assert _drill(QUICK, out) == cli.EXIT_OK  # without --resume: all of them again
    assert played == [0, 1, 2]


@pytest.mark.render
def test_a_trial_whose_policy_fails_is_listed_and_counts_for_nothing(tmp_path: Path) -> None:
    out = tmp_path / "drill"
    argv = ["duel", "--home", f"{__name__}:Broken", "--away", "stand", "--seconds", "1", "--trials", "2"]
    assert _drill(argv, out) == cli.EXIT_OK
    summary = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    assert summary["trials"] == {"planned": 2, "played": 0, "failed": 2}
    assert summary["summary"]["outcomes"] == {"home": 0, "away": 0, "out": 0, "none": 0}
    assert [f["error"] for f in summary["failures"]] == ["RuntimeError: broken on purpose"] * 2
    assert [row["status"] for row in _rows(out)] == ["failed", "failed"]
    assert "0 of 2 trials played" in (out / "table.md").read_text(encoding="utf-8")


@pytest.mark.render
def test_an_interrupted_drill_keeps_its_finished_trials_and_ends_with_130(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "drill"

    def stopped_after_one(task, tick=None):
        if task.index == 1:
            raise KeyboardInterrupt
        return play_trial(task, tick)

    play_trial = drill_run.play_trial
    monkeypatch.setattr(drill_run, "play_trial", stopped_after_one)
    assert _drill(QUICK, out) == cli.EXIT_INTERRUPTED
    assert "interrupted; finished trials are kept" in capsys.readouterr().err
    assert [p.name for p in (out / "runs").iterdir()] == ["trial_0000.json"]
    assert not (out / "summary.json").exists()
