"""The files of a chapter 6 scenario's numbers: results.csv, summary.json and table.md.

Thesis chapter 6: Tables 6.1 (position error, cm) and 6.2 (orientation error, degrees), and
for scenarios sampled while the robots play (``3-match``) a third table beside them: 95th
percentiles and the share of samples lost, with the thesis' scenario figures for comparison.
Units: the CSV keeps the samples' SI units (metres, radians, seconds) plus
``orientation_error_deg``; the JSON and the tables use the statistics' centimetres and
degrees (:mod:`scenarios.localization.statistics`).
"""

from __future__ import annotations

import dataclasses
import logging
import math
from collections.abc import Sequence
from pathlib import Path

from scenarios.common.io import json_safe, write_csv, write_json, write_text
from scenarios.localization.samples import LocalizationSample
from scenarios.localization.statistics import LOST_M, ORIENTATION, POSITION, Quantity, ScenarioReport

log = logging.getLogger(__name__)

RESULT_COLUMNS = (
    "scenario",
    "run",
    "robot",
    "method",
    "sim_time",
    "true_x",
    "true_y",
    "true_theta",
    "est_x",
    "est_y",
    "est_theta",
    "position_error_m",
    "orientation_error_deg",
    "landmarks_used",
    "event",
    "percepts",
)

NO_VALUE = "–"  # table cell without a value


# --------------------------------------------------------------------------- CSV and JSON


def _float_cell(value: float) -> str:
    """6 decimals (µm, µrad); NaN as ``nan`` so the cell round-trips through ``float()``."""
    return "nan" if math.isnan(value) else format(value, ".6f")


def _result_row(scenario: str, s: LocalizationSample) -> list[str | int]:
    floats = (s.sim_time_s, s.true_x, s.true_y, s.true_theta, s.est_x, s.est_y, s.est_theta,
              s.position_error_m, s.orientation_error_deg)
    return [scenario, s.run, s.robot, s.method, *(_float_cell(v) for v in floats), s.landmarks_used, s.event,
            s.percepts]


def write_results_csv(path: Path, report: ScenarioReport) -> Path:
    """One row per sample, in the report's order, columns :data:`RESULT_COLUMNS`."""
    path = write_csv(path, RESULT_COLUMNS, (_result_row(report.spec.name, s) for s in report.samples))
    log.info("wrote %s (%d samples)", path, len(report.samples))
    return path


def scenario_summary(report: ScenarioReport) -> dict:
    """The JSON summary of one scenario (the body of summary.json, one entry of the combined one)."""
    spec = report.spec
    summary = {
        "scenario": spec.name,
        "key": report.key,
        "description": spec.description,
        "methods": {name: st.to_json() for name, st in report.statistics.items()},
        "thesis": dataclasses.asdict(spec.thesis) if spec.thesis is not None else None,
        "samples_requested": spec.samples,
        "runs": spec.runs,
        "seed": spec.seed,
        "run_seeds": [int(s) for s in report.run_seeds],
        "measured": list(spec.measured),
        "played_by": {robot.id: robot.policy for robot in spec.robots},
        "camera_model": spec.camera_model,
        "camera_profile": spec.camera_profile,
        "wall_seconds": float(report.wall_seconds),
        "sim_seconds": float(report.sim_seconds),
        "versions": dict(report.versions),
    }
    if spec.periodic:  # only then: the summaries of event-sampled scenarios stay as they were
        summary["sample_period_s"] = spec.sample_period_s
        summary["half_seconds"] = spec.half_seconds
        summary["playing"] = {name: st.to_json() for name, st in report.playing.items()}
    return json_safe(summary)


def _write_json(path: Path, data: dict) -> Path:
    path = write_json(path, data)
    log.info("wrote %s", path)
    return path


def write_summary_json(path: Path, report: ScenarioReport) -> Path:
    """summary.json of one scenario: :func:`scenario_summary`, indented."""
    return _write_json(path, scenario_summary(report))


def write_combined_summary_json(path: Path, reports: Sequence[ScenarioReport]) -> Path:
    """summary.json of several scenarios: ``{"scenarios": {key: summary}}``."""
    return _write_json(path, {"scenarios": {r.key: scenario_summary(r) for r in reports}})


# --------------------------------------------------------------------------- tables


def _cell(value: float | None) -> str:
    return NO_VALUE if value is None or not math.isfinite(value) else f"{value:.1f}"


def _table(reports: Sequence[ScenarioReport], q: Quantity) -> list[str]:
    lines = [
        f"**{q.title}**, as thesis Table {q.thesis_table}:",
        "",
        "| scenario | method | mean | 95% CI ± | median | samples | thesis mean | thesis 95% CI ± |",
        "|---|---|---:|---:|---:|---:|---:|---:|",
    ]
    for report in reports:
        thesis = report.spec.thesis
        t_mean = _cell(getattr(thesis, q.mean) if thesis else None)
        t_ci = _cell(getattr(thesis, q.ci95) if thesis else None)
        for method, st in report.statistics.items():
            lines.append(
                f"| {report.key} | {method} | {_cell(getattr(st, q.mean))} | {_cell(getattr(st, q.ci95))} | "
                f"{_cell(getattr(st, q.median))} | {st.samples} | {t_mean} | {t_ci} |"
            )
    return lines


def _playing_table(reports: Sequence[ScenarioReport]) -> list[str]:
    """The statistics of the scenarios sampled while playing, with the thesis' means beside them."""
    lines = [
        f"**Localization while playing** (a sample every period of PLAYING time of each measured robot "
        f"that is up; lost: position error over {LOST_M * 100:.0f} cm or no estimate):",
        "",
        "| scenario | policy | robots | samples | position mean cm | position p95 cm | orientation mean deg | "
        "orientation p95 deg | lost % | thesis mean cm | thesis mean deg |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for report in reports:
        thesis = report.spec.thesis
        t_pos = _cell(thesis.position_mean_cm if thesis else None)
        t_ori = _cell(thesis.orientation_mean_deg if thesis else None)
        for policy, st in report.playing.items():
            lines.append(
                f"| {report.key} | {policy} | {st.robots} | {st.samples} | {_cell(st.position_mean_cm)} | "
                f"{_cell(st.position_p95_cm)} | {_cell(st.orientation_mean_deg)} | {_cell(st.orientation_p95_deg)} | "
                f"{_cell(st.lost_percent)} | {t_pos} | {t_ori} |"
            )
    return lines


def played_by(report: ScenarioReport) -> str:
    """Who played a scenario: each policy and its robots, measured ones marked, e.g.
    ``scan_localize (home_0 measured), stand (away_0, away_1)``."""
    robots: dict[str, list[str]] = {}
    for robot in report.spec.robots:
        robots.setdefault(robot.policy, []).append(robot.id + (" measured" if robot.measured else ""))
    return ", ".join(f"{policy} ({', '.join(ids)})" for policy, ids in robots.items())


def table_markdown(reports: Sequence[ScenarioReport]) -> str:
    """Tables 6.1 (position, cm) and 6.2 (orientation, degrees) of ``reports``, Markdown, one decimal;
    then, when a scenario was sampled while playing, its table of play; then who played each scenario."""
    lines = _table(reports, POSITION) + [""] + _table(reports, ORIENTATION)
    playing = [r for r in reports if r.spec.periodic]
    if playing:
        lines += [""] + _playing_table(playing)
    lines += ["", "**Played by**:", ""] + [f"- {report.key}: {played_by(report)}" for report in reports]
    return "\n".join(lines) + "\n"


def _write_markdown(path: Path, text: str) -> Path:
    path = write_text(path, text)
    log.info("wrote %s", path)
    return path


def write_scenario_table(path: Path, report: ScenarioReport) -> Path:
    """table.md of one scenario: a header with its settings and times, then :func:`table_markdown`."""
    spec = report.spec
    header = (
        f"# {spec.name}\n\n"
        f"samples requested: {spec.samples}, runs: {spec.runs}, seed: {spec.seed}, "
        f"wall time: {report.wall_seconds:.1f} s, simulated time: {report.sim_seconds:.1f} s\n\n"
    )
    if spec.periodic:
        header += (f"sampled every {spec.sample_period_s:g} s of PLAYING time, halves of {spec.half_seconds:g} s; "
                   "samples requested is a cap\n\n")
    return _write_markdown(path, header + table_markdown([report]))


def write_combined_table(path: Path, reports: Sequence[ScenarioReport]) -> Path:
    """table.md of several scenarios: :func:`table_markdown`."""
    return _write_markdown(path, table_markdown(reports))
