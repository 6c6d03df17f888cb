"""Figures of one match: ``traces.png`` and ``localization.png``.

- :func:`plot_traces`: the true and estimated paths of each robot that reported pose
  estimates, on the field drawing, one panel per robot (as the thesis' figures 6.11-6.14);
  the true paths of all robots in one panel when none did.
- :func:`plot_localization`: each such robot's position (cm) and orientation (degrees) error
  over time, with its falls, its placements by the referee and the kick-offs as vertical lines.

Both return the figure; :func:`scenarios.common.plotting.save_figure` writes it.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from matplotlib.collections import LineCollection

from match.protocol.game_control import GameState
from scenarios.common.plotting import draw_field, plt
from scenarios.replay.record import MatchRecord

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

DPI = 110
JUMP_M = 0.5  # a robot that moved more in one step was placed: its path is broken there
MAX_MARKERS = 300  # localizations drawn per panel (evenly thinned beyond)
MAX_CURVE_POINTS = 8000  # points of an error curve over time (a full match: every 4th step)
TEAM_COLORS = {"home": ("#0b3d91", "#1f5fe0", "#4f8cf7", "#8fb6ff"), "away": ("#8b0000", "#e0282e", "#ff6b6b", "#ffa3a3")}
EVENT_LINES = {  # event kinds drawn on the error plots: colour, label
    "kickoff": ("tab:green", "kick-off"),
    "fall": ("tab:red", "fall"),
    "robot_placed": ("tab:orange", "placed by the referee"),
    "robot_replaced": ("tab:orange", "placed by the referee"),
}


def estimated_robots(record: MatchRecord) -> list[int]:
    """Indices of the robots that reported a pose estimate at least once."""
    return [i for i in range(len(record.agents)) if record.has_estimates(i)]


def _path(xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """x and y with NaN where the robot jumped (a placement), so the line breaks there."""
    x, y = xy[:, 0].copy(), xy[:, 1].copy()
    jumps = np.flatnonzero(np.hypot(np.diff(x), np.diff(y)) > JUMP_M) + 1
    return np.insert(x, jumps, np.nan), np.insert(y, jumps, np.nan)


def localization_steps(record: MatchRecord, robot: int) -> np.ndarray:
    """Steps at which the robot's estimate changed (its localizations), first estimate included."""
    est = record.estimates[:, robot, :]
    finite = np.isfinite(est[:, :2]).all(axis=1)
    changed = np.ones(len(est), dtype=bool)
    changed[1:] = ~np.isclose(est[1:], est[:-1], atol=1e-6, equal_nan=True).all(axis=1)
    return np.flatnonzero(finite & changed)


def errors(record: MatchRecord, robot: int) -> tuple[np.ndarray, np.ndarray]:
    """Position error (cm) and orientation error (degrees) every step, NaN without an estimate."""
    est, truth = record.estimates[:, robot, :], record.robots[:, robot, :]
    position = np.hypot(est[:, 0] - truth[:, 0], est[:, 1] - truth[:, 1]) * 100.0
    turn = np.angle(np.exp(1j * (est[:, 2] - truth[:, 2])))
    return position, np.degrees(np.abs(turn))


def _trace_panel(ax: Axes, record: MatchRecord, robot: int) -> None:
    truth = record.robots[:, robot, :2]
    x, y = _path(truth)
    ax.plot(x, y, color="black", linewidth=0.8, alpha=0.75, label="true path", zorder=3)
    steps = localization_steps(record, robot)
    if len(steps) > MAX_MARKERS:
        steps = steps[np.linspace(0, len(steps) - 1, MAX_MARKERS).round().astype(int)]
    est = record.estimates[steps, robot, :2]
    at = truth[steps]
    ax.add_collection(LineCollection(np.stack([at, est], axis=1), colors="tab:red", linewidths=0.6, alpha=0.8,
                                     zorder=4))
    ax.plot(at[:, 0], at[:, 1], "o", color="black", markersize=2.5, zorder=5, label="true pose at a localization")
    ex, ey = _path(est)
    ax.plot(ex, ey, "--", color="tab:red", linewidth=0.6, alpha=0.6, zorder=4)
    ax.plot(est[:, 0], est[:, 1], "x", color="tab:red", markersize=5, mew=1.2, zorder=6, label="estimate")
    position, _ = errors(record, robot)
    mean = np.nanmean(position[steps]) if len(steps) else math.nan
    ax.set_title(f"{record.agents[robot]}: {len(localization_steps(record, robot))} estimates, mean error {mean:.0f} cm",
                 fontsize=9)


def plot_traces(record: MatchRecord) -> Figure:
    """True and estimated paths (one panel per robot with estimates), or every robot's true path."""
    robots = estimated_robots(record)
    panels = max(1, len(robots))
    cols = min(2, panels)
    rows = math.ceil(panels / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(6.4 * cols, 4.6 * rows), squeeze=False, layout="constrained")
    for ax in axes.flat:
        ax.set_visible(False)
    for ax, robot in zip(axes.flat, robots):
        ax.set_visible(True)
        draw_field(ax)
        _trace_panel(ax, record, robot)
    if robots:
        axes.flat[0].legend(loc="upper left", fontsize=7, framealpha=0.85)
        fig.suptitle(f"{record.directory.resolve().name}: true and estimated paths (the teams swap sides at half-time)")
    else:
        ax = axes.flat[0]
        ax.set_visible(True)
        draw_field(ax)
        for i, agent in enumerate(record.agents):
            side, _, player = agent.partition("_")
            x, y = _path(record.robots[:, i, :2])
            ax.plot(x, y, linewidth=0.9, color=TEAM_COLORS.get(side, TEAM_COLORS["home"])[int(player) % 4], label=agent)
        ax.legend(loc="upper left", fontsize=7, framealpha=0.85, ncol=2)
        ax.set_title("true paths (no robot reported a pose estimate)", fontsize=9)
        fig.suptitle(f"{record.directory.resolve().name}: true paths (the teams swap sides at half-time)")
    for ax in axes.flat:
        if ax.get_visible():
            ax.set_xlabel("x (m)")
            ax.set_ylabel("y (m)")
    return fig


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """(first, last) step of every run of True in ``mask``."""
    edges = np.diff(np.concatenate(([0], mask.astype(np.int8), [0])))
    return list(zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1))


def _shade_periods(ax: Axes, record: MatchRecord, drawn: set[str]) -> None:
    """Grey where the game was not PLAYING (robots walk to or are put at their places), gold in a shoot-out."""
    shootout_from = next((e["time_s"] for e in record.events if e["kind"] == "state"
                          and e.get("secondary") == "PENALTY_SHOOTOUT"), math.inf)
    in_shootout = record.time_s >= shootout_from
    for mask, color, label in ((record.state != GameState.PLAYING, "0.85", "not playing"),
                               (in_shootout, "#f6e7a8", "shoot-out")):
        for first, last in _runs(mask):
            ax.axvspan(record.time_s[first], record.time_s[last], color=color, alpha=0.6, linewidth=0, zorder=0,
                       label=None if label in drawn else label)
            drawn.add(label)


def _event_lines(ax: Axes, record: MatchRecord, robot: int, drawn: set[str]) -> None:
    agent = record.agents[robot]
    for event in record.events:
        kind = event["kind"]
        if kind not in EVENT_LINES or (kind != "kickoff" and event.get("robot") != agent):
            continue
        color, label = EVENT_LINES[kind]
        ax.axvline(event["time_s"], color=color, linewidth=0.9, alpha=0.8, zorder=1,
                   label=None if label in drawn else label)
        drawn.add(label)


def plot_localization(record: MatchRecord) -> Figure:
    """Position and orientation errors over time for each robot with estimates; events as vertical lines."""
    robots = estimated_robots(record)
    if not robots:
        fig, ax = plt.subplots(figsize=(8, 2.5), layout="constrained")
        ax.text(0.5, 0.5, "no robot reported a pose estimate", ha="center", va="center", transform=ax.transAxes)
        ax.set_axis_off()
        return fig
    height = 2.6 * len(robots) + 0.9
    fig, axes = plt.subplots(len(robots), 2, figsize=(13, height), squeeze=False, sharex=True)
    fig.subplots_adjust(left=0.06, right=0.99, top=1 - 0.75 / height, bottom=0.45 / height, hspace=0.35, wspace=0.13)
    every = max(1, math.ceil(record.steps / MAX_CURVE_POINTS))  # a curve point per step, up to this many
    for row, robot in enumerate(robots):
        position, orientation = (values[::every] for values in errors(record, robot))
        for ax, values, unit, label in ((axes[row, 0], position, "cm", "position error"),
                                        (axes[row, 1], orientation, "deg", "orientation error")):
            drawn: set[str] = set()
            _shade_periods(ax, record, drawn)
            _event_lines(ax, record, robot, drawn)
            ax.plot(record.time_s[::every], values, color="black", linewidth=0.8, zorder=3)
            ax.set_ylabel(f"{label} ({unit})")
            ax.set_title(f"{record.agents[robot]}: {label}, median {np.nanmedian(values):.1f} {unit}", fontsize=9)
            ax.set_ylim(bottom=0)
            ax.grid(alpha=0.3)
        if row == 0:
            axes[0, 0].legend(loc="upper left", fontsize=7, framealpha=0.85)
    for ax in axes[-1]:
        ax.set_xlabel("simulated time (s)")
    fig.suptitle(f"{record.directory.resolve().name}: localization errors against the true pose", y=1 - 0.12 / height)
    return fig
