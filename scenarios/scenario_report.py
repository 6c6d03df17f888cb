"""Outputs of a chapter 6 scenario: results.csv, summary.json, table.md, errors.png, traces.png.

Thesis chapter 6: Tables 6.1 (position error, cm) and 6.2 (orientation error, degrees),
Figure 6.15 (the errors of every scenario side by side) and Figures 6.1-6.14 (true and
estimated poses on the field). Units: the CSV keeps the samples' SI units (metres,
radians, seconds) plus ``orientation_error_deg``; the statistics, JSON, tables and the
error plot use centimetres and degrees.
"""

from __future__ import annotations

import csv
import dataclasses
import json
import logging
import math
from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # after choosing the backend
import numpy as np
from matplotlib.patches import Circle, Rectangle
from scipy import stats

from scenarios.scenario_spec import ScenarioSpec
from world.field import FIELD

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from scenarios.localization_run import LocalizationSample

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

DPI = 120
NO_VALUE = "–"  # table cell without a value
THESIS_LABEL = "thesis, reported"  # the thesis' own numbers (not the method named "thesis")
# Method colours, in method order: readable on the green field, none of them green.
METHOD_COLORS = ("tab:red", "tab:blue", "tab:orange", "tab:purple", "tab:cyan", "tab:pink", "tab:brown", "gold")
FIELD_GREEN = "#4c9a4c"
ARROW_M = 0.25  # length of a heading arrow on the traces, metres


# --------------------------------------------------------------------------- statistics


@dataclass(frozen=True)
class MethodStatistics:
    """One method's errors over a scenario: position in cm, orientation in degrees.

    ``samples``: samples with an estimate (the n of the means and intervals);
    ``missing``: samples of the method without an estimate, left out of everything else.
    ``*_ci95_*``: half-width of the Student t 95% interval of the mean, NaN when n < 2.
    ``localize_ms_median``: median wall time of the method's ``localize`` per scan (ms), a
    figure of the machine that ran it, not of the scenario.
    """

    samples: int
    missing: int
    position_mean_cm: float
    position_ci95_cm: float
    position_median_cm: float
    orientation_mean_deg: float
    orientation_ci95_deg: float
    orientation_median_deg: float
    localize_ms_median: float = math.nan

    def to_json(self) -> dict[str, float | int | None]:
        """The statistics as a JSON-ready dict, NaN as ``None``."""
        keys = (
            "position_mean_cm",
            "position_ci95_cm",
            "orientation_mean_deg",
            "orientation_ci95_deg",
            "samples",
            "missing",
            "position_median_cm",
            "orientation_median_deg",
            "localize_ms_median",
        )
        return {key: _json_number(getattr(self, key)) for key in keys}


def ci95_half_width(values: Sequence[float] | np.ndarray) -> float:
    """Half-width of the Student t 95% interval of the mean of ``values`` (same unit); NaN when n < 2."""
    data = np.asarray(values, dtype=float)
    n = data.size
    if n < 2:
        return math.nan
    return float(stats.t.ppf(0.975, n - 1) * np.std(data, ddof=1) / math.sqrt(n))


def _mean(data: np.ndarray) -> float:
    return float(np.mean(data)) if data.size else math.nan


def _median(data: np.ndarray) -> float:
    return float(np.median(data)) if data.size else math.nan


def _statistics(rows: Sequence[LocalizationSample]) -> MethodStatistics:
    position_cm = np.array([s.position_error_m for s in rows], dtype=float) * 100.0
    orientation_deg = np.array([s.orientation_error_deg for s in rows], dtype=float)
    ok = np.isfinite(position_cm) & np.isfinite(orientation_deg)
    pos, ori = position_cm[ok], orientation_deg[ok]
    return MethodStatistics(
        samples=int(ok.sum()),
        missing=int((~ok).sum()),
        position_mean_cm=_mean(pos),
        position_ci95_cm=ci95_half_width(pos),
        position_median_cm=_median(pos),
        orientation_mean_deg=_mean(ori),
        orientation_ci95_deg=ci95_half_width(ori),
        orientation_median_deg=_median(ori),
        localize_ms_median=_median(np.array([s.compute_ms for s in rows if math.isfinite(s.compute_ms)])),
    )


def method_order(samples: Sequence[LocalizationSample]) -> tuple[str, ...]:
    """The methods of ``samples`` in order of first appearance."""
    return tuple(dict.fromkeys(s.method for s in samples))


def method_statistics(samples: Sequence[LocalizationSample]) -> dict[str, MethodStatistics]:
    """Per method (first-appearance order): its :class:`MethodStatistics`."""
    return {m: _statistics([s for s in samples if s.method == m]) for m in method_order(samples)}


# --------------------------------------------------------------------------- report


@dataclass(frozen=True)
class ScenarioReport:
    """Everything one scenario produced.

    ``key``: short name for file names and table rows (``"1"``, a file stem);
    ``samples``: sorted by run, robot, event, then method; ``run_seeds``: one per run;
    ``wall_seconds`` / ``sim_seconds``: real and simulated time over all runs, seconds;
    ``versions``: package name -> version.
    """

    key: str
    spec: ScenarioSpec
    samples: tuple[LocalizationSample, ...]
    run_seeds: tuple[int, ...]
    wall_seconds: float
    sim_seconds: float
    versions: dict

    @cached_property
    def statistics(self) -> dict[str, MethodStatistics]:
        return method_statistics(self.samples)


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
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="", encoding="utf-8") as f:
        writer = csv.writer(f)
        writer.writerow(RESULT_COLUMNS)
        for sample in report.samples:
            writer.writerow(_result_row(report.spec.name, sample))
    log.info("wrote %s (%d samples)", path, len(report.samples))
    return path


def _json_number(value: float) -> float | None:
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def _json_safe(value: object) -> object:
    """``value`` with every non-finite float replaced by ``None``, tuples as lists."""
    if isinstance(value, float):
        return _json_number(value)
    if isinstance(value, dict):
        return {k: _json_safe(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_json_safe(v) for v in value]
    return value


def scenario_summary(report: ScenarioReport) -> dict:
    """The JSON summary of one scenario (the body of summary.json, one entry of the combined one)."""
    spec = report.spec
    return _json_safe({
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
        "camera_model": spec.camera_model,
        "wall_seconds": float(report.wall_seconds),
        "sim_seconds": float(report.sim_seconds),
        "versions": dict(report.versions),
    })


def _write_json(path: Path, data: dict) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(data, indent=2, allow_nan=False) + "\n", encoding="utf-8")
    log.info("wrote %s", path)
    return path


def write_summary_json(path: Path, report: ScenarioReport) -> Path:
    """summary.json of one scenario: :func:`scenario_summary`, indented."""
    return _write_json(path, scenario_summary(report))


# --------------------------------------------------------------------------- tables


@dataclass(frozen=True)
class _Quantity:
    """One of the two tables: which statistics and which thesis fields, and their unit."""

    title: str
    thesis_table: str
    mean: str
    ci95: str
    median: str
    unit: str


POSITION = _Quantity("Position error (cm)", "6.1", "position_mean_cm", "position_ci95_cm", "position_median_cm", "cm")
ORIENTATION = _Quantity(
    "Orientation error (degrees)", "6.2", "orientation_mean_deg", "orientation_ci95_deg", "orientation_median_deg", "deg"
)


def _cell(value: float | None) -> str:
    return NO_VALUE if value is None or not math.isfinite(value) else f"{value:.1f}"


def _table(reports: Sequence[ScenarioReport], q: _Quantity) -> list[str]:
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


def table_markdown(reports: Sequence[ScenarioReport]) -> str:
    """Tables 6.1 (position, cm) and 6.2 (orientation, degrees) of ``reports``, Markdown, one decimal."""
    lines = _table(reports, POSITION) + [""] + _table(reports, ORIENTATION)
    return "\n".join(lines) + "\n"


def _write_text(path: Path, text: str) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    log.info("wrote %s", path)
    return path


def _scenario_table(report: ScenarioReport) -> str:
    spec = report.spec
    header = (
        f"# {spec.name}\n\n"
        f"samples requested: {spec.samples}, runs: {spec.runs}, seed: {spec.seed}, "
        f"wall time: {report.wall_seconds:.1f} s, simulated time: {report.sim_seconds:.1f} s\n\n"
    )
    return header + table_markdown([report])


# --------------------------------------------------------------------------- plots


def _method_colors(methods: Sequence[str]) -> dict[str, str]:
    return {m: METHOD_COLORS[i % len(METHOD_COLORS)] for i, m in enumerate(methods)}


def _all_methods(reports: Sequence[ScenarioReport]) -> tuple[str, ...]:
    return tuple(dict.fromkeys(m for r in reports for m in r.statistics))


def _error_panel(ax: Axes, reports: Sequence[ScenarioReport], q: _Quantity, methods: Sequence[str]) -> None:
    """Grouped bars of one quantity: x groups = scenarios, a bar per method, then the thesis' bar."""
    colors = _method_colors(methods)
    has_thesis = any(r.spec.thesis is not None for r in reports)
    slots = len(methods) + int(has_thesis)
    width = 0.8 / max(slots, 1)
    centres = np.arange(len(reports), dtype=float)
    for i, method in enumerate(methods):
        xs, ys, errs = [], [], []
        for x, report in zip(centres, reports):
            st = report.statistics.get(method)
            if st is None or not math.isfinite(getattr(st, q.mean)):
                continue
            xs.append(x + (i - (slots - 1) / 2) * width)
            ys.append(getattr(st, q.mean))
            errs.append(getattr(st, q.ci95))
        _bars(ax, xs, ys, errs, width, label=method, color=colors[method])
    if has_thesis:
        pairs = [(x, r.spec.thesis) for x, r in zip(centres, reports) if r.spec.thesis is not None]
        xs = [x + (slots - 1) / 2 * width for x, _ in pairs]
        _bars(ax, xs, [getattr(t, q.mean) for _, t in pairs], [getattr(t, q.ci95) for _, t in pairs], width,
              label=THESIS_LABEL, color="lightgrey", hatch="//", edgecolor="dimgrey")
    ax.set_xticks(centres, [r.spec.name for r in reports])
    ax.set_ylabel(f"mean {q.title.lower()}")
    ax.set_title(f"{q.title.split(' (')[0]} (cf. thesis Table {q.thesis_table})")
    ax.set_ylim(bottom=0)
    ax.grid(axis="y", alpha=0.3)


def _bars(ax: Axes, xs: list, ys: list, errs: list, width: float, label: str, **style) -> None:
    """Bars at ``xs``; error bars where the half-width is finite."""
    if not xs:
        return
    ax.bar(xs, ys, width, label=label, **style)
    finite = [(x, y, e) for x, y, e in zip(xs, ys, errs) if e is not None and math.isfinite(e)]
    if finite:
        fx, fy, fe = zip(*finite)
        ax.errorbar(fx, fy, yerr=fe, fmt="none", ecolor="black", elinewidth=1, capsize=3)


def plot_errors(path: Path, reports: Sequence[ScenarioReport]) -> Path:
    """Thesis Figure 6.15: mean position (cm) and orientation (deg) errors per scenario, 95% CI bars."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    methods = _all_methods(reports)
    width = max(10.0, 2.0 + 1.6 * len(reports) * (len(methods) + 1) / 2)
    fig, axes = plt.subplots(1, 2, figsize=(width, 4.8), layout="constrained")
    for ax, q in zip(axes, (POSITION, ORIENTATION)):
        _error_panel(ax, reports, q, methods)
    handles, labels = axes[0].get_legend_handles_labels()
    if handles:  # below the panels, clear of the bars and error bars
        fig.legend(handles, labels, loc="outside lower center", ncol=len(handles), fontsize=9)
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    log.info("wrote %s", path)
    return path


def draw_field(ax: Axes) -> None:
    """The field in ``ax``: green carpet, white lines, blue (x < 0) and yellow (x > 0) goals, metres."""
    hl, hw = FIELD.half_length, FIELD.half_width
    line = {"color": "white", "linewidth": 1.5, "zorder": 1}
    ax.set_facecolor(FIELD_GREEN)
    ax.add_patch(Rectangle((-hl, -hw), 2 * hl, 2 * hw, fill=False, **line))
    ax.plot([0.0, 0.0], [-hw, hw], **line)
    ax.add_patch(Circle((0.0, 0.0), FIELD.center_circle_radius, fill=False, **line))
    for sign in (-1.0, 1.0):
        x0 = min(sign * hl, sign * FIELD.goal_area_x)
        ax.add_patch(Rectangle((x0, -FIELD.goal_area_half_width), FIELD.goal_area_depth, FIELD.goal_area_width,
                               fill=False, **line))
    for sign, color in ((-1.0, "blue"), (1.0, "gold")):
        ax.plot([sign * hl, sign * hl], [-FIELD.goal_post_y, FIELD.goal_post_y], color=color, linewidth=6,
                solid_capstyle="butt", zorder=2)
    ax.set_xlim(-hl - 0.4, hl + 0.4)
    ax.set_ylim(-hw - 0.4, hw + 0.4)
    ax.set_aspect("equal")


def _trace_panel(ax: Axes, rows: Sequence[LocalizationSample], colors: dict[str, str]) -> None:
    """True poses (black line, dots, heading arrows) and each method's estimates joined to the truth."""
    first: dict[int, LocalizationSample] = {}
    for s in rows:
        first.setdefault(s.event, s)  # the true pose is the same for every method of an event
    truth = sorted(first.values(), key=lambda s: s.event)
    tx = np.array([s.true_x for s in truth])
    ty = np.array([s.true_y for s in truth])
    tt = np.array([s.true_theta for s in truth])
    ax.plot(tx, ty, "-o", color="black", linewidth=1.2, markersize=3, label="true pose", zorder=4)
    ax.quiver(tx, ty, ARROW_M * np.cos(tt), ARROW_M * np.sin(tt), angles="xy", scale_units="xy", scale=1,
              width=0.004, color="black", zorder=4)
    for method, color in colors.items():
        est = [s for s in rows if s.method == method and math.isfinite(s.est_x) and math.isfinite(s.est_y)]
        if not est:
            continue
        for s in est:
            ax.plot([s.true_x, s.est_x], [s.true_y, s.est_y], color=color, linewidth=0.7, zorder=3)
        ax.plot([s.est_x for s in est], [s.est_y for s in est], "x", color=color, markersize=6, mew=1.5,
                label=method, zorder=5, linestyle="none")


def _panels(samples: Sequence[LocalizationSample]) -> list[tuple[int, str]]:
    """(run, robot) pairs, by run and then robot id."""
    return sorted({(s.run, s.robot) for s in samples})


def plot_traces(path: Path, report: ScenarioReport, max_panels: int = 6) -> Path:
    """Thesis Figures 6.1-6.14: per measured robot of each run, true and estimated poses on the field."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    panels = _panels(report.samples)[:max(max_panels, 1)]
    cols = min(3, max(len(panels), 1))
    rows = max(1, math.ceil(len(panels) / cols))
    fig, axes = plt.subplots(rows, cols, figsize=(5.2 * cols, 3.9 * rows), squeeze=False, layout="constrained")
    colors = _method_colors(method_order(report.samples))
    for ax in axes.flat:
        ax.set_visible(False)
    for ax, (run, robot) in zip(axes.flat, panels):
        ax.set_visible(True)
        draw_field(ax)
        _trace_panel(ax, [s for s in report.samples if s.run == run and s.robot == robot], colors)
        ax.set_title(f"run {run} robot {robot}")
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
    if panels:
        axes.flat[0].legend(loc="upper left", fontsize=7, framealpha=0.85)
    else:
        axes.flat[0].set_visible(True)
        axes.flat[0].text(0.5, 0.5, "no samples", ha="center", va="center", transform=axes.flat[0].transAxes)
        axes.flat[0].set_axis_off()
    fig.suptitle(report.spec.name)
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    log.info("wrote %s (%d panels)", path, len(panels))
    return path


# --------------------------------------------------------------------------- whole reports


def write_scenario_report(out_dir: Path, report: ScenarioReport) -> list[Path]:
    """results.csv, summary.json, table.md, errors.png and traces.png of one scenario in ``out_dir``."""
    out = Path(out_dir)
    return [
        write_results_csv(out / "results.csv", report),
        write_summary_json(out / "summary.json", report),
        _write_text(out / "table.md", _scenario_table(report)),
        plot_errors(out / "errors.png", [report]),
        plot_traces(out / "traces.png", report),
    ]


def write_combined_report(out_dir: Path, reports: Sequence[ScenarioReport]) -> list[Path]:
    """table.md, errors.png and summary.json (``{"scenarios": {key: summary}}``) of several scenarios."""
    keys = [r.key for r in reports]
    if len(set(keys)) != len(keys):
        raise ValueError(f"scenario keys are not unique: {keys}")
    out = Path(out_dir)
    return [
        _write_text(out / "table.md", table_markdown(reports)),
        plot_errors(out / "errors.png", reports),
        _write_json(out / "summary.json", {"scenarios": {r.key: scenario_summary(r) for r in reports}}),
    ]
