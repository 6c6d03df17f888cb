"""The chapter 6 report (scenarios.localization statistics, tables, figures) on synthetic samples: statistics, CSV, JSON, tables, plots."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import pytest
from scipy import stats

from scenarios.localization.batch import write_combined_report, write_scenario_report
from scenarios.localization.figures import plot_errors, plot_traces
from scenarios.localization.samples import LocalizationSample
from scenarios.localization.spec import RobotEntry, ScenarioSpec, ThesisReference
from scenarios.localization.statistics import ScenarioReport, method_statistics
from scenarios.localization.tables import RESULT_COLUMNS, played_by, table_markdown, write_results_csv

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
THESIS_1 = ThesisReference(12.39, 2.83, 3.53, 2.86)
NAN = math.nan


def sample(
    method: str = "particle",
    dx: float = 0.0,
    dy: float = 0.0,
    *,
    event: int = 0,
    run: int = 0,
    robot: str = "home_1",
    true: tuple[float, float, float] = (0.5, -0.25, 0.3),
    est_theta: float | None = None,
    missing: bool = False,
) -> LocalizationSample:
    """A sample whose estimate is the true pose moved by (dx, dy) m; ``missing``: no estimate."""
    tx, ty, tt = true
    if missing:
        ex = ey = et = NAN
    else:
        ex, ey, et = tx + dx, ty + dy, tt if est_theta is None else est_theta
    return LocalizationSample(run, robot, method, event, 1.5 + event, tx, ty, tt, ex, ey, et, 0 if missing else 3, 5,
                              2.0)


def spec(name: str = "scenario 1", thesis: ThesisReference | None = THESIS_1) -> ScenarioSpec:
    return ScenarioSpec(
        name=name, description="one robot alone", samples=4, runs=1, seed=0, methods=("thesis", "particle"),
        camera_model="exact", referee=False, robots=(RobotEntry("home_1", "scan_localize", True, None),),
        thesis=thesis,
    )


def report(key: str = "1", samples: tuple[LocalizationSample, ...] | None = None, **spec_args) -> ScenarioReport:
    if samples is None:
        samples = mixed_samples()
    return ScenarioReport(key, spec(**spec_args), samples, (123, 456), 3.25, 80.0, {"numpy": "1.0"})


def mixed_samples() -> tuple[LocalizationSample, ...]:
    """Two runs, two methods, four events each; one missing estimate; headings across the wrap."""
    out = []
    for run in (0, 1):
        for event in range(4):
            true = (-1.0 + 0.5 * event, 0.3 * event - 0.5, 0.8 * event - 1.0 + run)
            out.append(sample("thesis", 0.05 * event, -0.02, event=event, run=run, true=true, est_theta=true[2] + 0.1))
            out.append(sample("particle", -0.1, 0.03 * event, event=event, run=run, true=true,
                              missing=(run == 1 and event == 2)))
    return tuple(out)


# --------------------------------------------------------------------------- statistics


def test_ci95_matches_the_hand_computation() -> None:
    st = method_statistics([sample(dx=d, event=i) for i, d in enumerate((0.1, 0.2, 0.3))])["particle"]
    assert st.samples == 3 and st.missing == 0
    assert st.position_mean_cm == pytest.approx(20.0)
    assert st.position_median_cm == pytest.approx(20.0)
    assert st.position_ci95_cm == pytest.approx(stats.t.ppf(0.975, 2) * 10.0 / math.sqrt(3))
    assert st.orientation_mean_deg == pytest.approx(0.0)
    assert st.orientation_ci95_deg == pytest.approx(0.0)


def test_missing_estimates_are_counted_and_excluded() -> None:
    rows = [sample(dx=0.1), sample(dy=0.3, event=1), sample(missing=True, event=2)]
    st = method_statistics(rows)["particle"]
    assert (st.samples, st.missing) == (2, 1)
    assert st.position_mean_cm == pytest.approx(20.0)
    assert st.position_ci95_cm == pytest.approx(stats.t.ppf(0.975, 1) * math.sqrt(200.0) / math.sqrt(2))


def test_one_sample_has_no_interval_and_null_in_json() -> None:
    st = method_statistics([sample(dx=0.1)])["particle"]
    assert math.isnan(st.position_ci95_cm) and math.isnan(st.orientation_ci95_deg)
    data = st.to_json()
    assert data["position_ci95_cm"] is None and data["orientation_ci95_deg"] is None
    assert data["position_mean_cm"] == pytest.approx(10.0)
    json.dumps(data, allow_nan=False)


def test_only_missing_estimates_give_no_values() -> None:
    st = method_statistics([sample(missing=True), sample(missing=True, event=1)])["particle"]
    assert (st.samples, st.missing) == (0, 2)
    assert all(v is None for k, v in st.to_json().items() if k not in ("samples", "missing", "localize_ms_median"))


def test_orientation_error_wraps() -> None:
    row = sample(true=(0.0, 0.0, math.radians(179.0)), est_theta=math.radians(-179.0))
    assert row.orientation_error_deg == pytest.approx(2.0)
    assert method_statistics([row])["particle"].orientation_mean_deg == pytest.approx(2.0)


def test_methods_keep_first_appearance_order() -> None:
    rows = [sample("zeta"), sample("alpha"), sample("zeta", event=1)]
    assert list(method_statistics(rows)) == ["zeta", "alpha"]


def test_to_json_has_the_required_keys() -> None:
    data = method_statistics([sample(dx=0.1), sample(dx=0.2, event=1)])["particle"].to_json()
    assert set(data) == {
        "position_mean_cm", "position_ci95_cm", "orientation_mean_deg", "orientation_ci95_deg", "samples",
        "missing", "position_median_cm", "orientation_median_deg", "localize_ms_median",
    }


# --------------------------------------------------------------------------- CSV and JSON


def test_results_csv_round_trips(tmp_path: Path) -> None:
    rep = report()
    path = write_results_csv(tmp_path / "results.csv", rep)
    with path.open(newline="", encoding="utf-8") as f:
        header = next(csv.reader(f))
    assert tuple(header) == RESULT_COLUMNS
    with path.open(newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == len(rep.samples)
    fields = {
        "sim_time": "sim_time_s", "true_x": "true_x", "true_y": "true_y", "true_theta": "true_theta",
        "est_x": "est_x", "est_y": "est_y", "est_theta": "est_theta",
        "position_error_m": "position_error_m", "orientation_error_deg": "orientation_error_deg",
    }
    for row, s in zip(rows, rep.samples):
        assert row["scenario"] == "scenario 1"
        assert (int(row["run"]), row["robot"], row["method"], int(row["event"])) == (s.run, s.robot, s.method, s.event)
        assert (int(row["landmarks_used"]), int(row["percepts"])) == (s.landmarks_used, s.percepts)
        for column, attribute in fields.items():
            expected = getattr(s, attribute)
            if math.isnan(expected):
                assert row[column] == "nan" and math.isnan(float(row[column]))
            else:
                assert float(row[column]) == pytest.approx(expected, abs=1e-6)
    assert sum(row["est_x"] == "nan" for row in rows) == 1


def test_summary_json(tmp_path: Path) -> None:
    write_scenario_report(tmp_path, report())
    data = json.loads((tmp_path / "summary.json").read_text(encoding="utf-8"))
    assert data["scenario"] == "scenario 1" and data["key"] == "1"
    assert list(data["methods"]) == ["thesis", "particle"]
    for stats_json in data["methods"].values():
        assert {"position_mean_cm", "position_ci95_cm", "orientation_mean_deg", "orientation_ci95_deg",
                "samples"} <= set(stats_json)
    assert data["methods"]["particle"]["samples"] == 7 and data["methods"]["particle"]["missing"] == 1
    assert data["thesis"] == {"position_mean_cm": 12.39, "position_ci95_cm": 2.83, "orientation_mean_deg": 3.53,
                              "orientation_ci95_deg": 2.86}
    assert (data["samples_requested"], data["runs"], data["seed"]) == (4, 1, 0)
    assert data["run_seeds"] == [123, 456] and data["measured"] == ["home_1"]
    assert data["played_by"]["home_1"] == "scan_localize"  # who played: every robot's policy
    assert data["camera_model"] == "exact" and data["versions"] == {"numpy": "1.0"}
    assert (data["wall_seconds"], data["sim_seconds"]) == (3.25, 80.0)


def test_summary_json_without_thesis_row(tmp_path: Path) -> None:
    write_scenario_report(tmp_path, report(thesis=None))
    assert json.loads((tmp_path / "summary.json").read_text(encoding="utf-8"))["thesis"] is None


# --------------------------------------------------------------------------- tables


def test_table_shows_the_thesis_row() -> None:
    text = table_markdown([report()])
    assert "Table 6.1" in text and "Table 6.2" in text
    position, orientation = text.split("Orientation error (degrees)")
    assert "12.4" in position and "2.8" in position
    assert "3.5" in orientation and "2.9" in orientation
    particle_rows = [line for line in text.splitlines() if line.startswith("| 1 | particle |")]
    assert len(particle_rows) == 2 and all("| 12.4 | 2.8 |" in line or "| 3.5 | 2.9 |" in line
                                           for line in particle_rows)


def test_table_without_thesis_row_uses_dashes() -> None:
    text = table_markdown([report(thesis=None)])
    rows = [line for line in text.splitlines() if line.startswith("| 1 |")]
    assert len(rows) == 4 and all(line.endswith("| – | – |") for line in rows)


def test_scenario_table_md(tmp_path: Path) -> None:
    write_scenario_report(tmp_path, report())
    text = (tmp_path / "table.md").read_text(encoding="utf-8")
    assert text.splitlines()[0] == "# scenario 1"
    assert f"- 1: {played_by(report())}" in text and "scan_localize (home_1 measured)" in text  # who played
    assert "seed: 0" in text and "wall time" in text and "12.4" in text


# --------------------------------------------------------------------------- plots and whole reports


def assert_png(path: Path) -> None:
    assert path.exists()
    assert path.read_bytes()[:8] == PNG_MAGIC
    assert path.stat().st_size > 5_000


def test_scenario_report_files(tmp_path: Path) -> None:
    paths = write_scenario_report(tmp_path / "s1", report())
    assert [p.name for p in paths] == ["results.csv", "summary.json", "table.md", "errors.png", "traces.png"]
    assert all(p.exists() for p in paths)
    assert_png(tmp_path / "s1" / "errors.png")
    assert_png(tmp_path / "s1" / "traces.png")


def test_plots_cope_with_single_samples_and_no_samples(tmp_path: Path) -> None:
    assert_png(plot_errors(tmp_path / "one.png", [report(samples=(sample(dx=0.1),))]))
    assert_png(plot_traces(tmp_path / "none.png", report(samples=())))
    many = tuple(sample(dx=0.1, run=run) for run in range(8))
    assert_png(plot_traces(tmp_path / "many.png", report(samples=many), max_panels=6))


def test_combined_report(tmp_path: Path) -> None:
    first = report("1")
    second = report("2", samples=tuple(s for s in mixed_samples() if s.method == "particle"), name="scenario 2",
                    thesis=None)
    paths = write_combined_report(tmp_path, [first, second])
    assert [p.name for p in paths] == ["table.md", "errors.png", "summary.json"]
    data = json.loads((tmp_path / "summary.json").read_text(encoding="utf-8"))
    assert list(data["scenarios"]) == ["1", "2"]
    assert data["scenarios"]["2"]["scenario"] == "scenario 2" and data["scenarios"]["2"]["thesis"] is None
    assert list(data["scenarios"]["2"]["methods"]) == ["particle"]
    text = (tmp_path / "table.md").read_text(encoding="utf-8")
    assert sum(line.startswith("| 1 |") for line in text.splitlines()) == 4
    assert sum(line.startswith("| 2 |") for line in text.splitlines()) == 2
    assert_png(tmp_path / "errors.png")


def test_combined_report_rejects_duplicate_keys(tmp_path: Path) -> None:
    with pytest.raises(ValueError):
        write_combined_report(tmp_path, [report("1"), report("1")])
