"""The figures of chapter 6 scenarios: errors.png and traces.png.

Thesis Figure 6.15 (the errors of every scenario side by side, :func:`plot_errors`) and
Figures 6.1-6.14 (true and estimated poses on the field, :func:`plot_traces`). Errors in
centimetres and degrees (:mod:`scenarios.localization.statistics`), poses in metres.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from scenarios.common.plotting import draw_field, plt, save_figure
from scenarios.localization.samples import LocalizationSample
from scenarios.localization.statistics import ORIENTATION, POSITION, Quantity, ScenarioReport, method_order

if TYPE_CHECKING:
    from matplotlib.axes import Axes

log = logging.getLogger(__name__)

DPI = 120
THESIS_LABEL = "thesis, reported"  # the thesis' own numbers (not the method named "thesis")
# Method colours, in method order: readable on the green field, none of them green.
METHOD_COLORS = ("tab:red", "tab:blue", "tab:orange", "tab:purple", "tab:cyan", "tab:pink", "tab:brown", "gold")
ARROW_M = 0.25  # length of a heading arrow on the traces, metres


def _method_colors(methods: Sequence[str]) -> dict[str, str]:
    return {m: METHOD_COLORS[i % len(METHOD_COLORS)] for i, m in enumerate(methods)}


def _all_methods(reports: Sequence[ScenarioReport]) -> tuple[str, ...]:
    return tuple(dict.fromkeys(m for r in reports for m in r.statistics))


# --------------------------------------------------------------------------- errors


def _error_panel(ax: Axes, reports: Sequence[ScenarioReport], q: Quantity, methods: Sequence[str]) -> None:
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
    methods = _all_methods(reports)
    width = max(10.0, 2.0 + 1.6 * len(reports) * (len(methods) + 1) / 2)
    fig, axes = plt.subplots(1, 2, figsize=(width, 4.8), layout="constrained")
    for ax, q in zip(axes, (POSITION, ORIENTATION)):
        _error_panel(ax, reports, q, methods)
    handles, labels = axes[0].get_legend_handles_labels()
    if handles:  # below the panels, clear of the bars and error bars
        fig.legend(handles, labels, loc="outside lower center", ncol=len(handles), fontsize=9)
    path = save_figure(fig, path, DPI)
    log.info("wrote %s", path)
    return path


# --------------------------------------------------------------------------- traces


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
    path = save_figure(fig, path, DPI)
    log.info("wrote %s (%d panels)", path, len(panels))
    return path
