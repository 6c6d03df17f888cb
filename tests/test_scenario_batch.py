"""Scenario batches: the same results for any number of workers or backend, resume, a refereed run."""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import pytest

from scenarios import cli
from scenarios.localization import batch as scenario_batch
from scenarios.localization.batch import BatchOptions, ScenarioBatchError, run_scenario
from scenarios.localization.file import load_scenario
from scenarios.localization.run import RunTask, simulate_run

ALONE = """
name = "tiny alone"
samples = 4
runs = 2
seed = 5
methods = ["thesis", "odometry"]
[[robots]]
id = "home_1"
policy = "scan_localize"
measured = true
"""

FILES = ("results.csv", "summary.json", "table.md", "errors.png", "traces.png")


@pytest.fixture(scope="module")
def alone_spec(tmp_path_factory: pytest.TempPathFactory):
    path = tmp_path_factory.mktemp("spec") / "tiny.toml"
    path.write_text(ALONE, encoding="utf-8")
    return load_scenario(path)


@pytest.fixture(scope="module")
def one_worker(alone_spec, tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("one_worker")
    run_scenario(alone_spec, "tiny", out, BatchOptions(workers=1, progress=False))
    return out


@pytest.mark.render
def test_a_batch_writes_every_output(one_worker: Path) -> None:
    for name in FILES:
        assert (one_worker / name).stat().st_size > 0
    summary = json.loads((one_worker / "summary.json").read_text())
    assert set(summary["methods"]) == {"thesis", "odometry"}
    for stats in summary["methods"].values():
        assert stats["samples"] == 4
        assert stats["position_mean_cm"] >= 0.0
    assert len((one_worker / "results.csv").read_text().splitlines()) == 1 + 4 * 2


@pytest.mark.render
def test_two_workers_give_the_same_results(alone_spec, one_worker: Path, tmp_path: Path) -> None:
    run_scenario(alone_spec, "tiny", tmp_path, BatchOptions(workers=2, progress=False))
    assert (tmp_path / "results.csv").read_bytes() == (one_worker / "results.csv").read_bytes()


@pytest.mark.render
def test_several_scenarios_share_one_pool_and_give_each_its_own_results(alone_spec, one_worker: Path,
                                                                         tmp_path: Path) -> None:
    """Two scenarios in one pool, runs interleaved: each one's results are those it gives alone."""
    other = dataclasses.replace(alone_spec, name="tiny other", seed=6)
    alone_other = tmp_path / "alone_other"
    run_scenario(other, "other", alone_other, BatchOptions(workers=1, progress=False))
    together = [(alone_spec, "tiny", tmp_path / "tiny"), (other, "other", tmp_path / "other")]
    reports = scenario_batch.run_scenarios(together, BatchOptions(workers=2, progress=False))
    assert [r.key for r in reports] == ["tiny", "other"]
    assert (tmp_path / "tiny" / "results.csv").read_bytes() == (one_worker / "results.csv").read_bytes()
    assert (tmp_path / "other" / "results.csv").read_bytes() == (alone_other / "results.csv").read_bytes()
    assert all(0.0 < r.wall_seconds for r in reports)


def test_the_longest_runs_go_first() -> None:
    match = load_scenario("3-match")
    short, long = (RunTask(load_scenario("1"), 0, 1, samples) for samples in (2, 9))
    tasks = sorted([short, RunTask(match, 0, 1, 1), long], key=scenario_batch._longest_first)
    assert tasks[0].spec is match and tasks[1:] == [long, short]


@pytest.mark.render
def test_resume_keeps_finished_runs(alone_spec, one_worker: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    calls: list[int] = []

    def interrupted(task: RunTask, on_sample=None):
        calls.append(task.run)
        if task.run == 1:
            raise KeyboardInterrupt
        return simulate_run(task, on_sample)

    monkeypatch.setattr(scenario_batch, "simulate_run", interrupted)
    with pytest.raises(KeyboardInterrupt):
        run_scenario(alone_spec, "tiny", tmp_path, BatchOptions(workers=1, progress=False))
    assert [p.name for p in sorted((tmp_path / "runs").glob("run_*.json"))] == ["run_0000.json"]

    calls.clear()
    monkeypatch.setattr(scenario_batch, "simulate_run", lambda task, on_sample=None: calls.append(task.run) or
                        simulate_run(task, on_sample))
    run_scenario(alone_spec, "tiny", tmp_path, BatchOptions(workers=1, resume=True, progress=False))
    assert calls == [1]  # run 0 was not recomputed
    assert (tmp_path / "results.csv").read_bytes() == (one_worker / "results.csv").read_bytes()


@pytest.mark.render
def test_resume_refuses_the_runs_of_other_settings(alone_spec, tmp_path: Path) -> None:
    run_scenario(alone_spec, "tiny", tmp_path, BatchOptions(workers=1, progress=False))
    changed = scenario_batch.with_overrides(alone_spec, seed=6)
    with pytest.raises(ScenarioBatchError, match="fingerprint"):
        run_scenario(changed, "tiny", tmp_path, BatchOptions(workers=1, resume=True, progress=False))


@pytest.mark.render
@pytest.mark.slow
def test_ray_backend_gives_the_same_results(alone_spec, one_worker: Path, tmp_path: Path) -> None:
    pytest.importorskip("ray")
    run_scenario(alone_spec, "tiny", tmp_path, BatchOptions(workers=2, backend="ray", progress=False))
    assert (tmp_path / "results.csv").read_bytes() == (one_worker / "results.csv").read_bytes()


@pytest.mark.render
@pytest.mark.slow
def test_a_refereed_run_starts_from_the_kickoff_position() -> None:
    spec = scenario_batch.with_overrides(load_scenario("2"), samples=2, methods=("thesis", "odometry"))
    spec = dataclasses.replace(spec, warmup_seconds=0.0)
    task = RunTask(spec, 0, 11, 2)
    outcome = simulate_run(task)
    assert outcome.complete
    assert {s.robot for s in outcome.samples} == {"home_1"}
    assert outcome.sim_seconds > 20.0  # INITIAL, READY and SET come before play
    first = outcome.samples[0]
    # home_1 defends the blue goal and kicks off: it starts just behind the centre spot.
    assert math.hypot(first.true_x + 0.22, first.true_y) < 0.6
    odometry = [s for s in outcome.samples if s.method == "odometry"][0]
    assert odometry.position_error_m < 0.3  # reset at the kick-off position, then one motion


def test_bad_options_are_rejected() -> None:
    with pytest.raises(ScenarioBatchError, match="workers = 0"):
        BatchOptions(workers=0)
    with pytest.raises(ScenarioBatchError, match="backend = 'dask'"):
        BatchOptions(backend="dask")


def test_a_malformed_file_stops_the_command_before_anything_runs(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "bad.toml"
    bad.write_text(ALONE.replace("samples = 4", "samples = -4"), encoding="utf-8")
    out = tmp_path / "out"
    assert cli.main(["scenario", "1", str(bad), "--out", str(out), "--no-progress"]) == cli.EXIT_USAGE
    error = capsys.readouterr().err
    assert str(bad) in error and "samples" in error and "-4" in error
    assert not out.exists()  # scenario 1, named first, did not run either


def test_an_unknown_scenario_name_is_rejected(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert cli.main(["scenario", "4", "--out", str(tmp_path / "out"), "--no-progress"]) == cli.EXIT_USAGE
    assert "'4'" in capsys.readouterr().err
