"""Scenario 3 in its literal sense (``3-match``): team agents measured while they play, every second of PLAYING time."""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest

from match.protocol import GameState
from scenarios.localization import run as scenario_run
from scenarios.localization.batch import BatchOptions, run_scenario, scenario_key, with_overrides
from scenarios.localization.file import (
    BUILTIN_SCENARIOS,
    NAMED_SCENARIOS,
    ScenarioFileError,
    builtin_path,
    load_scenario,
    parse_scenario,
)
from scenarios.localization.periodic import PeriodicCollector, UnmeasurableRobotError
from scenarios.localization.run import RunTask, simulate_run
from scenarios.localization.samples import LocalizationSample
from scenarios.localization.statistics import ScenarioReport, playing_statistics
from scenarios.localization.tables import scenario_summary, table_markdown

TINY_ROBOTS = ("home_0", "home_1", "away_0", "away_1")  # two a side: the goalkeepers and one measured player each
TINY_HALF_S = 5.0


# --------------------------------------------------------------------------- the file


def test_the_built_in_file_is_the_literal_scenario_3() -> None:
    spec = load_scenario("3-match")
    assert "3-match" in NAMED_SCENARIOS and "3-match" not in BUILTIN_SCENARIOS  # "all" runs it; 1-3 stay the thesis'
    assert builtin_path("3-match").name == "scenario_3_match.toml" and scenario_key("3-match") == "3-match"
    assert spec.referee and spec.periodic and spec.sample_period_s == 1.0
    assert [r.id for r in spec.robots] == [f"home_{p}" for p in range(4)] + [f"away_{p}" for p in range(4)]
    assert [r.policy for r in spec.robots] == ["team"] * 4 + ["team-blind"] * 4  # the thesis' blind opponents
    assert spec.measured == ("home_1", "home_2", "home_3")
    assert spec.methods == () and spec.half_seconds == 600.0 and spec.runs == 2
    assert (spec.thesis.position_mean_cm, spec.thesis.orientation_mean_deg) == (43.09, 22.91)
    assert spec.fingerprint() == load_scenario("3-match").fingerprint()
    assert with_overrides(spec, half_seconds=120).fingerprint() != spec.fingerprint()


def _doc(extra: str = "", policy: str = "team") -> dict:
    robots = [{"id": "home_0", "policy": policy, "measured": True}, {"id": "away_0", "policy": "team"}]
    data = {"name": "t", "samples": 10, "referee": True, "sampling": {"period_seconds": 1.0}, "robots": robots}
    if extra:
        key, value = extra.split("=")
        data[key] = json.loads(value)
    return data


@pytest.mark.parametrize(("data", "key", "fragment"), [
    (_doc(policy="scripted"), "robots[0].measured", "reports its pose"),
    (_doc('methods=["thesis"]'), "methods", "no methods"),
    (_doc('camera_model="thesis"'), "camera_model", "no methods or camera_model"),
    ({**_doc(), "sampling": {"period_seconds": 0}}, "sampling.period_seconds", "[0.04, 3600]"),
    ({**_doc(), "sampling": {"every": 1}}, "sampling.every", "period_seconds"),
])
def test_a_bad_sampling_file_is_a_precise_error(data: dict, key: str, fragment: str) -> None:
    with pytest.raises(ScenarioFileError) as caught:
        parse_scenario(data, "t.toml")
    assert caught.value.key == key and fragment in str(caught.value)


def test_periodic_sampling_measures_any_pose_reporter_and_ignores_methods_overrides() -> None:
    spec = parse_scenario(_doc(policy="scan_localize"), "t.toml")
    assert spec.periodic and spec.measured == ("home_0",)
    assert with_overrides(spec, methods=("thesis",), samples=3) == spec  # its runs last a match, its robots localize
    assert with_overrides(spec, half_seconds=30).half_seconds == 30.0
    event_spec = load_scenario("1")
    assert not event_spec.periodic and event_spec.sample_period_s is None


def test_a_policy_without_an_estimate_cannot_be_measured() -> None:
    spec = parse_scenario(_doc(), "t.toml")
    with pytest.raises(UnmeasurableRobotError, match="home_0"):
        PeriodicCollector(spec, 0, 10, {"home_0": object(), "away_0": object()})


# --------------------------------------------------------------------------- the report


def _sample(robot: str, index: int, error_m: float, policy: str = "team") -> LocalizationSample:
    return LocalizationSample(0, robot, policy, index, 30.0 + index, 1.0, 0.5, 0.2, 1.0 + error_m, 0.5, 0.2 + 0.1, 0, 0)


def test_the_report_shows_play_beside_the_thesis_scenario_3() -> None:
    spec = load_scenario("3-match")
    errors = (0.1, 0.2, 0.3, 0.6, 1.0)
    samples = tuple(_sample("home_1", i, e) for i, e in enumerate(errors))
    samples += (dataclasses.replace(_sample("away_1", 0, 0.0), est_x=math.nan, est_y=math.nan, est_theta=math.nan),)
    stats = playing_statistics(samples)["team"]
    assert (stats.samples, stats.missing, stats.robots) == (6, 1, 2)
    assert stats.position_mean_cm == pytest.approx(44.0)
    assert stats.position_p95_cm == pytest.approx(np.percentile([10, 20, 30, 60, 100], 95))
    assert stats.lost_percent == pytest.approx(100.0 * 3 / 6)  # two beyond 0.5 m, one without an estimate
    assert stats.orientation_mean_deg == pytest.approx(math.degrees(0.1))
    report = ScenarioReport("3-match", spec, samples, (1, 2), 10.0, 100.0, {})
    text = table_markdown([report])
    row = next(line for line in text.splitlines() if line.startswith("| 3-match | team | 2 | 6 |"))
    assert row.endswith("| 50.0 | 43.1 | 22.9 |")
    assert "Localization while playing" in text and "| 3-match | team | 44.0 |" in text
    summary = scenario_summary(report)
    assert summary["sample_period_s"] == 1.0 and summary["playing"]["team"]["lost_percent"] == pytest.approx(50.0)
    json.dumps(summary, allow_nan=False)
    event_report = dataclasses.replace(report, spec=load_scenario("3"))
    assert "Localization while playing" not in table_markdown([event_report])
    assert "playing" not in scenario_summary(event_report)


# --------------------------------------------------------------------------- a tiny match


@pytest.fixture
def quick_kickoffs(monkeypatch: pytest.MonkeyPatch) -> None:
    """INITIAL, READY and SET shortened (0.4, 2, 0.4 s) so that a tiny match is mostly play."""
    original = scenario_run._refereed_config

    def quick(spec):
        config = original(spec)
        timings = {"initial_seconds": 0.4, "ready_seconds": 2.0, "set_seconds": 0.4}
        return dataclasses.replace(config, referee=dataclasses.replace(config.referee, **timings))

    monkeypatch.setattr(scenario_run, "_refereed_config", quick)


def _ticks(state: np.ndarray, period_steps: int = 25) -> list[int]:
    """Log rows at which a sample is due: every ``period_steps`` steps of PLAYING counted over the whole match.

    Row k of the match log is the state the policies decided on at the next step (the last row
    is after the last step: nothing decided on it).
    """
    ticks, played = [], 0
    for k in range(len(state) - 1):
        if state[k] == int(GameState.PLAYING):
            if played and played % period_steps == 0:
                ticks.append(k)
            played += 1
    return ticks


@pytest.mark.render
def test_a_tiny_match_is_sampled_every_second_of_play_only(quick_kickoffs, tmp_path: Path) -> None:
    spec = with_overrides(load_scenario("3-match"), half_seconds=TINY_HALF_S)
    robots = tuple(dataclasses.replace(r, measured=True) if r.id == "away_1" else r  # two robots measured
                   for r in spec.robots if r.id in TINY_ROBOTS)
    spec = dataclasses.replace(spec, robots=robots, runs=1)
    outcome = simulate_run(RunTask(spec, 0, spec.run_seeds()[0], spec.samples), out_dir=tmp_path)
    assert outcome.complete  # it played the match to its end
    log = np.load(tmp_path / "match_log.npz")
    assert log["state"][-1] == int(GameState.FINISHED)
    agents = list(log["agents"])
    playing_s = float(np.sum(log["state"][:-1] == int(GameState.PLAYING))) * 0.04
    assert playing_s == pytest.approx(2 * TINY_HALF_S, abs=0.1)
    ticks = _ticks(log["state"])
    assert len(ticks) == pytest.approx(playing_s - 1, abs=1)  # about one a second of play
    assert {s.robot for s in outcome.samples} == {"home_1", "away_1"}
    for robot in ("home_1", "away_1"):
        column = agents.index(robot)
        rows = [s for s in outcome.samples if s.robot == robot]
        policy = next(r.policy for r in spec.robots if r.id == robot)
        assert {s.method for s in rows} == {policy} and [s.event for s in rows] == list(range(len(rows)))
        due = [k for k in ticks if not log["fallen"][k, column]]  # in play and up
        assert [s.sim_time_s for s in rows] == [float(log["time_s"][k]) for k in due]
        for s, k in zip(rows, due):
            assert log["state"][k] == int(GameState.PLAYING)
            assert (s.true_x, s.true_y) == pytest.approx(tuple(log["robots"][k, column, :2]), abs=1e-4)
            assert math.isfinite(s.position_error_m) and math.isfinite(s.orientation_error_deg)
            assert s.position_error_m < 3.0


@pytest.mark.render
def test_the_tiny_batch_reports_the_play(quick_kickoffs, tmp_path: Path) -> None:
    spec = with_overrides(load_scenario("3-match"), half_seconds=2.0)
    spec = dataclasses.replace(spec, robots=tuple(r for r in spec.robots if r.id in ("home_0", "home_1", "away_0")),
                               runs=1, samples=2)
    report = run_scenario(spec, "3-match", tmp_path, BatchOptions(workers=1, progress=False))
    assert len(report.samples) == 2  # the cap: the run stopped with its samples, in the second half
    assert list(report.playing) == ["team"] and report.playing["team"].samples == 2
    table = (tmp_path / "table.md").read_text(encoding="utf-8")
    assert "Localization while playing" in table and "| 43.1 | 22.9 |" in table
    assert json.loads((tmp_path / "summary.json").read_text(encoding="utf-8"))["playing"]["team"]["samples"] == 2
