"""Tournaments end to end on tiny matches: outputs, the same results for any worker count or
backend, resume after an interrupt, refusals, a crashing and a raising policy, bad input,
the replay pages and figures."""

from __future__ import annotations

import json
import logging
import shutil
from pathlib import Path

import numpy as np
import pytest

import scenarios.tournament.run as tournament_run
from scenarios import cli
from scenarios.common.batch import BatchOptions
from scenarios.tournament.settings import TournamentSettings

# 1 v 1, 2 s halves, short pauses before the kick-offs, no shoot-out: a match is about 5 s simulated
# A step budget far above any answer's time: on a loaded machine a controller answering late
# would stand its robot for a step, and runs compared byte for byte would differ.
QUICK = ["--matches", "2", "--players", "1", "--half-seconds", "2", "--pauses", "0.2,0.4,0.2", "--no-shootout",
         "--seed", "3", "--no-progress", "--step-budget", "60"]


def tournament(out: Path, *arguments: str, policies: tuple[str, ...] = ("scripted", "stand")) -> int:
    return cli.main(["tournament", *policies, *QUICK, "--out", str(out), *arguments])


@pytest.fixture(scope="module")
def one_worker(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("one_worker") / "tournament"
    assert tournament(out, "--workers", "1") == cli.EXIT_OK
    return out


@pytest.mark.render
def test_a_tournament_writes_every_output(one_worker: Path) -> None:
    for name in ("results.csv", "summary.json", "table.md", "standings.png"):
        assert (one_worker / name).stat().st_size > 0
    assert not (one_worker / "ratings.png").exists()  # two policies: no rating
    lines = (one_worker / "results.csv").read_text(encoding="utf-8").splitlines()
    assert len(lines) == 3
    assert lines[1].startswith("0,0,") and ",scripted,stand,ok," in lines[1] and ",stand,scripted,ok," in lines[2]
    for index in ("000", "001"):
        match = one_worker / "matches" / index
        data = json.loads((match / "summary.json").read_text(encoding="utf-8"))
        assert set(data["statistics"]) == {"playing_seconds", "restart_waits_s", "restart_max_s", "restarts_slow",
                                           "home", "away"}
        assert data["statistics"]["playing_seconds"] == pytest.approx(4.0, abs=0.05)
        assert data["radio"]["by_side"]["home"]["sent"] >= 0
        assert (match / "events.jsonl").stat().st_size > 0
        assert np.load(match / "match_log.npz")["robots"].shape[1] == 2
    summary = json.loads((one_worker / "summary.json").read_text(encoding="utf-8"))
    assert summary["matches"] == {"planned": 2, "played": 2, "failed": 0}
    assert set(summary["standings"]) == {"scripted", "stand"} and summary["ratings"] is None
    assert len(summary["verdicts"]) == 1 and "over 2 matches" in summary["verdicts"][0]
    assert "## Verdicts" in (one_worker / "table.md").read_text(encoding="utf-8")


@pytest.mark.render
def test_a_tournament_plays_every_match_with_its_camera_profile(tmp_path: Path) -> None:
    out = tmp_path / "profiled"
    assert tournament(out, "--workers", "1", "--no-replay", "--matches", "1", "--camera-profile", "nao") == cli.EXIT_OK
    match = json.loads((out / "matches" / "000" / "summary.json").read_text(encoding="utf-8"))
    assert match["config"]["world"]["camera_profile"] == "nao"
    assert json.loads((out / "summary.json").read_text(encoding="utf-8"))["settings"]["camera_profile"] == "nao"
    assert "camera profile nao" in (out / "table.md").read_text(encoding="utf-8")
    # another profile is another tournament: --resume refuses it, naming both
    assert tournament(out, "--workers", "1", "--no-replay", "--matches", "1", "--resume") == cli.EXIT_USAGE


def test_an_unknown_camera_profile_is_refused_before_anything_is_written(tmp_path: Path, capsys) -> None:
    with pytest.raises(SystemExit) as refused:
        tournament(tmp_path / "none", "--camera-profile", "fisheye")
    assert refused.value.code == cli.EXIT_USAGE
    assert "--camera-profile: expected one of clean, robotstadium, nao, got 'fisheye'" in capsys.readouterr().err and not (tmp_path / "none").exists()


@pytest.mark.render
def test_every_match_has_its_replay_page_and_no_figures(one_worker: Path) -> None:
    for index in ("000", "001"):
        match = one_worker / "matches" / index
        assert "robotstadium-replay/1" in (match / "replay.html").read_text(encoding="utf-8")
        assert not (match / "traces.png").exists() and not (match / "localization.png").exists()


@pytest.mark.render
def test_no_replay_writes_no_page_and_keeps_the_fingerprint(one_worker: Path, tmp_path: Path) -> None:
    assert tournament(tmp_path, "--workers", "1", "--no-replay") == cli.EXIT_OK
    assert sorted(p.name for p in (tmp_path / "matches").glob("*/replay.html")) == []
    assert (tmp_path / "matches" / "001" / "match_log.npz").exists()
    assert (tmp_path / "results.csv").read_bytes() == (one_worker / "results.csv").read_bytes()
    marker = json.loads((tmp_path / "tournament.json").read_text(encoding="utf-8"))
    assert marker == json.loads((one_worker / "tournament.json").read_text(encoding="utf-8"))


@pytest.mark.render
def test_plots_for_writes_the_figures_of_that_match_only(one_worker: Path, tmp_path: Path,
                                                          capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "copy"
    shutil.copytree(one_worker, out)
    # --resume accepts the finished tournament (the same fingerprint) and plays nothing more
    assert tournament(out, "--workers", "1", "--resume", "--plots-for", "0", "--no-replay") == cli.EXIT_OK
    figures = [out / "matches" / "000" / name for name in ("traces.png", "localization.png")]
    assert [str(f) for f in figures] == capsys.readouterr().out.splitlines()[-2:]
    assert all(f.stat().st_size > 0 for f in figures)
    assert sorted(p.name for p in (out / "matches" / "001").iterdir()) == [
        "events.jsonl", "match_log.npz", "replay.html", "summary.json"]
    assert (out / "results.csv").read_bytes() == (one_worker / "results.csv").read_bytes()


def no_page(directory: Path) -> list[Path]:
    """A page writer that always fails (the workers import it from this module)."""
    raise OSError(f"disk full under {directory.name}")


@pytest.mark.render
def test_a_page_that_fails_is_a_warning_and_the_match_is_kept(tmp_path: Path, caplog: pytest.LogCaptureFixture) -> None:
    settings = TournamentSettings(("scripted", "stand"), 1, 2.0, 1, 3, False, (0.2, 0.4, 0.2))
    with caplog.at_level(logging.WARNING, logger=tournament_run.__name__):
        report = tournament_run.run_tournament(settings, tmp_path, BatchOptions(1, progress=False), page=no_page)
    assert not report.failed and report.records[0]["home_goals"] is not None
    assert sorted(p.name for p in (tmp_path / "matches" / "000").iterdir()) == [
        "events.jsonl", "match_log.npz", "summary.json"]
    assert any("no replay page (OSError: disk full" in r.getMessage() for r in caplog.records)


@pytest.mark.render
def test_two_workers_give_the_same_results(one_worker: Path, tmp_path: Path) -> None:
    assert tournament(tmp_path, "--workers", "2") == cli.EXIT_OK
    assert (tmp_path / "results.csv").read_bytes() == (one_worker / "results.csv").read_bytes()


@pytest.mark.render
def test_resume_after_an_interrupt_plays_only_the_rest(one_worker: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                       capsys: pytest.CaptureFixture[str]) -> None:
    execute = tournament_run.execute

    def interrupted(tasks, *args, **kwargs):
        for result in execute(tasks, *args, **kwargs):
            yield result
            raise KeyboardInterrupt  # Ctrl-C after the first match

    monkeypatch.setattr(tournament_run, "execute", interrupted)
    assert tournament(tmp_path, "--workers", "1") == cli.EXIT_INTERRUPTED
    assert "--resume" in capsys.readouterr().err
    assert [p.name for p in sorted((tmp_path / "runs").glob("match_*.json"))] == ["match_0000.json"]

    played: list[int] = []

    def counted(tasks, *args, **kwargs):
        played.extend(t.index for t in tasks)
        return execute(tasks, *args, **kwargs)

    monkeypatch.setattr(tournament_run, "execute", counted)
    assert tournament(tmp_path, "--workers", "1", "--resume") == cli.EXIT_OK
    assert played == [1]
    assert (tmp_path / "results.csv").read_bytes() == (one_worker / "results.csv").read_bytes()


@pytest.mark.render
def test_resume_refuses_other_settings_naming_both(one_worker: Path, tmp_path: Path,
                                                   capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "copy"
    shutil.copytree(one_worker, out)
    before = (out / "results.csv").read_bytes()
    code = cli.main(["tournament", "scripted", "stand", *QUICK, "--matches", "3", "--out", str(out), "--resume"])
    assert code == cli.EXIT_USAGE
    error = capsys.readouterr().err
    assert "matches=2" in error and "matches=3" in error and "--resume" in error
    assert (out / "results.csv").read_bytes() == before


@pytest.mark.render
def test_a_crashing_match_fails_alone_and_a_raising_policy_is_a_fault(tmp_path: Path) -> None:
    # in process, a policy that ends its process ends its match's worker
    policies = ("tests.user_policies:ExitsAtHome", "tests.user_policies:RaisesEveryTenth")
    assert tournament(tmp_path, "--workers", "2", "--in-process", policies=policies) == cli.EXIT_OK
    crashed = json.loads((tmp_path / "runs" / "match_0000.json").read_text(encoding="utf-8"))
    assert crashed["status"] == "failed" and "exit code 3" in crashed["error"] and crashed["attempts"] == 2
    assert "exit code 3" in (tmp_path / "matches" / "000" / "error.txt").read_text(encoding="utf-8")
    played = json.loads((tmp_path / "runs" / "match_0001.json").read_text(encoding="utf-8"))
    assert played["status"] == "ok" and played["home_policy"] == policies[1]
    assert played["statistics"]["home"]["faults"] > 0 and played["statistics"]["away"]["faults"] == 0
    summary = json.loads((tmp_path / "summary.json").read_text(encoding="utf-8"))
    assert summary["matches"]["failed"] == 1 and summary["failures"][0]["match"] == 0
    rows = (tmp_path / "results.csv").read_text(encoding="utf-8").splitlines()
    assert ",failed," in rows[1] and ",ok," in rows[2]


@pytest.mark.render
def test_in_controller_processes_a_policy_that_ends_its_process_costs_only_its_robots(tmp_path: Path) -> None:
    policies = ("tests.user_policies:ExitsAtHome", "stand")
    assert tournament(tmp_path, "--workers", "1", "--matches", "1", "--controller-per", "robot",
                      policies=policies) == cli.EXIT_OK
    played = json.loads((tmp_path / "runs" / "match_0000.json").read_text(encoding="utf-8"))
    assert played["status"] == "ok"
    summary = json.loads((tmp_path / "matches" / "000" / "summary.json").read_text(encoding="utf-8"))
    assert summary["completed"] and summary["statistics"]["away"]["faults"] == 0
    died = [d for d in summary["faults"]["details"] if d["error"].startswith("ControllerDied")]
    assert died and {d["agent"] for d in died} == {f"home_{i}" for i in range(summary["config"]["home_players"])}
    assert all("exit code 3" in d["error"] for d in died)


@pytest.mark.parametrize("arguments, words", [
    (["scripted", "striker"], ["POLICY", "unknown policy 'striker'"]),
    (["scripted", "stand", "--matches", "0"], ["argument --matches", "got 0"]),
    (["scripted"], ["POLICY", "'scripted'"]),
    (["scripted", "stand", "--half-seconds", "-1"], ["argument --half-seconds", "got -1"]),
    (["scripted", "stand", "--matches", "2", "--plots-for", "99"], ["--plots-for 99", "from 0 to 1", "2 matches"]),
])
def test_bad_input_exits_2_with_one_line_and_writes_nothing(arguments: list[str], words: list[str], tmp_path: Path,
                                                            capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "out"
    try:
        code = cli.main(["tournament", *arguments, "--out", str(out), "--no-progress"])
    except SystemExit as refused:  # refused while parsing
        code = refused.code
    assert code == cli.EXIT_USAGE
    error = capsys.readouterr().err
    assert error.count("\n") == 1 and error.startswith("robotstadium tournament: error: ")
    for word in words:
        assert word in error
    assert not out.exists()


@pytest.mark.render
@pytest.mark.slow
def test_ray_backend_gives_the_same_results(one_worker: Path, tmp_path: Path) -> None:
    pytest.importorskip("ray")
    assert tournament(tmp_path, "--workers", "2", "--backend", "ray") == cli.EXIT_OK
    assert (tmp_path / "results.csv").read_bytes() == (one_worker / "results.csv").read_bytes()
