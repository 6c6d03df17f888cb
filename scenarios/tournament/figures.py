"""The figures of a tournament: standings.png (goal difference per match, cumulative standings)
and ratings.png (the Bradley-Terry ratings with their 95% intervals, three or more policies)."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from scenarios.common.plotting import plt, save_figure
from scenarios.tournament.report import TournamentReport
from scenarios.tournament.statistics import Rating

DPI = 110
COLORS = ("tab:blue", "tab:red", "tab:green", "tab:orange", "tab:purple", "tab:brown", "tab:pink", "tab:gray")


def plot_standings(path: Path, report: TournamentReport) -> Path:
    """Left: each played match's goal difference (bars; crosses: a shoot-out's), from its pair's first
    policy's side, a colour per pair.
    Right: every policy's cumulative score (a win 1, a draw 1/2) over the tournament's matches."""
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2))
    pairs = [(h.first, h.second) for h in report.head_to_head]
    for p, (first, second) in enumerate(pairs):
        xs, ys, shootouts = [], [], []
        for record in report.records:
            if record["status"] != "ok" or {record["home_entrant"], record["away_entrant"]} != {first, second}:
                continue
            side = "home" if record["home_entrant"] == first else "away"
            other = "away" if side == "home" else "home"
            xs.append(record["match"])
            ys.append(record[f"{side}_goals"] - record[f"{other}_goals"])
            if record[f"{side}_shootout"] is not None:
                shootouts.append((record["match"], record[f"{side}_shootout"] - record[f"{other}_shootout"]))
        color = COLORS[p % len(COLORS)]
        left.bar(xs, ys, color=color, label=f"{first} - {second}")
        if shootouts:
            left.scatter(*zip(*shootouts), marker="x", color=color, label=f"{first} - {second}, shoot-out")
    left.axhline(0.0, color="black", linewidth=0.8)
    left.set_xlabel("match")
    left.set_ylabel("goal difference")
    left.set_title("goal difference per match")
    left.legend(fontsize=8)
    for e, name in enumerate(s.name for s in report.standings):
        xs, ys = _cumulative(report.records, name)
        right.step(xs, ys, where="post", color=COLORS[e % len(COLORS)], label=name)
    right.set_xlabel("match")
    right.set_ylabel("score (win 1, draw 1/2)")
    right.set_title("cumulative standings")
    right.legend(fontsize=8)
    fig.tight_layout()
    return save_figure(fig, path, DPI)


def _cumulative(records: Sequence[Mapping], name: str) -> tuple[list[int], list[float]]:
    xs, ys, total = [0], [0.0], 0.0
    for record in records:
        if record["status"] != "ok":
            continue
        for side in ("home", "away"):
            if record[f"{side}_entrant"] == name:
                winner = record["winner_side"]
                total += 0.5 if winner is None else float(winner == side)
                xs.append(record["match"] + 1)
                ys.append(total)
    return xs, ys


def plot_ratings(path: Path, ratings: Sequence[Rating]) -> Path:
    """The ratings, best on top, with their bootstrap 95% intervals."""
    fig, ax = plt.subplots(figsize=(6.5, 0.5 * len(ratings) + 1.5))
    order = list(reversed(ratings))
    ys = np.arange(len(order))
    values = np.array([r.rating for r in order])
    low = np.array([r.rating - r.ci95[0] if math.isfinite(r.ci95[0]) else 0.0 for r in order])
    high = np.array([r.ci95[1] - r.rating if math.isfinite(r.ci95[1]) else 0.0 for r in order])
    ax.errorbar(values, ys, xerr=[low, high], fmt="o", color="tab:blue", capsize=4)
    ax.set_yticks(ys, [r.name for r in order])
    ax.axvline(0.0, color="gray", linewidth=0.8)
    ax.set_xlabel("Bradley-Terry rating, Elo scale (mean 0), 95% bootstrap interval")
    ax.set_title("ratings")
    fig.tight_layout()
    return save_figure(fig, path, DPI)
