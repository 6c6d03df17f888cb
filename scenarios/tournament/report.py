"""The report of a tournament: results.csv, summary.json and table.md, from the match records.

A match record (the batch's stored JSON of one match, see :func:`match_record`) holds the
schedule's facts (match, pair, seed, home and away policy), the status (``ok`` or
``failed`` with its error), the score, the shoot-out, the winning side and the match
statistics of both teams (:mod:`match.statistics`). Everything here is computed from the
records in match order, so the files do not depend on the worker count or the backend.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from match.statistics import RESTART_SLOW_S, TEAM_KEYS
from scenarios.common.io import json_safe, write_csv, write_json, write_text
from scenarios.common.statistics import mean
from scenarios.tournament.game_flow import GameFlow, game_flow
from scenarios.tournament.settings import TournamentSettings
from scenarios.tournament.statistics import (
    BOOTSTRAP_RESAMPLES,
    Rating,
    Standing,
    fmt,
    games_of,
    ratings,
    verdict,
)

STATISTICS_COLUMNS = tuple(k for k in TEAM_KEYS if k != "goals")  # goals have their own columns
RESULT_COLUMNS = (
    "match", "pair", "seed", "home_policy", "away_policy", "status", "home_goals", "away_goals", "home_shootout",
    "away_shootout", "winner", "sim_seconds",
    *(f"{side}_{key}" for key in STATISTICS_COLUMNS for side in ("home", "away")),
    "error",
)
TABLE_STATISTICS = (  # (key, header, format) of the per-policy means in table.md
    ("goals", "goals", ".2f"), ("own_goals", "own goals", ".2f"), ("shots_on_target", "shots on target", ".2f"),
    ("shots_saved", "shots saved", ".2f"), ("shots_blocked", "shots blocked", ".2f"),
    ("touches", "touches", ".1f"), ("possession", "possession", ".2f"), ("balls_out", "balls out", ".2f"),
    ("falls", "falls", ".2f"), ("robots_replaced", "replaced", ".2f"), ("radio_sent", "radio sent", ".0f"),
    ("radio_dropped", "radio dropped", ".1f"), ("faults", "faults", ".1f"),
    ("position_error_mean_m", "position error mean / p95 (m)", ".3f"),
    ("orientation_error_mean_deg", "orientation error mean / p95 (deg)", ".1f"),
    ("lost_share", "lost share", ".3f"),
    ("field_position_error_mean_m", "field players: position error mean / p95 (m)", ".3f"),
    ("field_orientation_error_mean_deg", "field players: orientation error mean / p95 (deg)", ".1f"),
    ("field_lost_share", "field players: lost share", ".3f"),
    ("longest_still_s", "longest still (s)", ".1f"),
    ("longest_still_field_s", "field player still (s)", ".1f"),
    ("longest_stuck_field_s", "field player stuck (s)", ".1f"),
)


@dataclass(frozen=True)
class HeadToHead:
    first: str
    second: str
    standing: Standing  # the first's
    verdict: str
    flow: GameFlow

    def to_json(self) -> dict:
        return {"first": self.first, "second": self.second, **self.standing.to_json(), "verdict": self.verdict,
                "game_flow": self.flow.to_json()}


@dataclass(frozen=True)
class TournamentReport:
    settings: TournamentSettings
    records: tuple[dict, ...]
    standings: tuple[Standing, ...]
    head_to_head: tuple[HeadToHead, ...]
    ratings: tuple[Rating, ...] | None
    team_means: dict[str, dict]
    wall_seconds: float
    versions: dict = field(default_factory=dict)

    @property
    def failed(self) -> tuple[dict, ...]:
        return tuple(r for r in self.records if r["status"] != "ok")

    @property
    def verdicts(self) -> tuple[str, ...]:
        return tuple(h.verdict for h in self.head_to_head)


def build_report(settings: TournamentSettings, records: Sequence[dict], wall_seconds: float,
                 versions: dict | None = None) -> TournamentReport:
    """Standings, head to head, ratings (three or more policies) and statistics means of the records."""
    entrants = settings.entrants()
    standings = tuple(Standing.of(name, games_of(records, name)) for name in entrants)
    if settings.self_play:
        pairs = [entrants]
    else:
        pairs = list(settings.pairs())
    head = []
    for first, second in pairs:
        standing = Standing.of(first, games_of(records, first, second))
        head.append(HeadToHead(first, second, standing, verdict(first, second, standing),
                               game_flow(records, first, second)))
    rated = tuple(ratings(records, entrants, settings.seed)) if len(settings.policies) >= 3 else None
    return TournamentReport(settings, tuple(records), standings, tuple(head), rated, team_means(records, entrants),
                            wall_seconds, versions or {})


def team_means(records: Sequence[Mapping], entrants: Sequence[str]) -> dict[str, dict]:
    """Per entrant, the mean over its played matches of each team statistic (None when never reported)."""
    means = {}
    for name in entrants:
        teams = [r["statistics"][side] for r in records if r["status"] == "ok"
                 for side in ("home", "away") if r[f"{side}_entrant"] == name]
        row = {}
        for key in TEAM_KEYS:
            values = [t[key] for t in teams if t.get(key) is not None]
            row[key] = round(mean(values), 4) if values else None
        means[name] = row
    return means


# ---- files -----------------------------------------------------------------------------------


def winner_name(record: Mapping) -> str:
    """The winning policy, ``home``/``away`` when both sides play the same policy, empty for a draw or a failure."""
    side = record.get("winner_side")
    if record["status"] != "ok" or side is None:
        return ""
    if record["home_policy"] == record["away_policy"]:
        return side
    return record[f"{side}_policy"]


def result_row(record: Mapping) -> list[object]:
    ok = record["status"] == "ok"
    statistics = record.get("statistics") or {}
    row: dict[str, object] = {key: record.get(key) for key in RESULT_COLUMNS}
    row["winner"] = winner_name(record)
    for side in ("home", "away"):
        for key in STATISTICS_COLUMNS:
            row[f"{side}_{key}"] = statistics.get(side, {}).get(key) if ok else None
    return ["" if row[c] is None else row[c] for c in RESULT_COLUMNS]


def write_results_csv(path: Path, records: Sequence[Mapping]) -> Path:
    """One row per match, in match order (see :data:`RESULT_COLUMNS`); empty cells for what is missing."""
    return write_csv(path, RESULT_COLUMNS, (result_row(r) for r in records))


def write_summary_json(path: Path, report: TournamentReport, fingerprint: str) -> Path:
    records = report.records
    data = {
        "settings": report.settings.to_json(),
        "fingerprint": fingerprint,
        "matches": {"planned": len(records), "played": len(records) - len(report.failed), "failed": len(report.failed)},
        "failures": [{"match": r["match"], "home_policy": r["home_policy"], "away_policy": r["away_policy"],
                      "error": r["error"], "attempts": r["attempts"]} for r in report.failed],
        "verdicts": list(report.verdicts),
        "standings": {s.name: s.to_json() for s in report.standings},
        "head_to_head": [h.to_json() for h in report.head_to_head],
        "ratings": None if report.ratings is None else {r.name: r.to_json() for r in report.ratings},
        "team_statistics_means": report.team_means,
        "definitions": DEFINITIONS,
        "sim_seconds": round(sum(r.get("sim_seconds") or 0.0 for r in records), 3),
        "wall_seconds": round(report.wall_seconds, 3),
        "versions": report.versions,
    }
    return write_json(path, json_safe(data))


DEFINITIONS = {
    "win_rate": "wins + draws / 2 over matches played; 95% interval: Wilson score interval, z = 1.96",
    "goal_difference": "goals scored minus conceded per match (shoot-out goals excluded); 95% interval: Student t",
    "verdict": ("A beats B when A's win-rate interval lies wholly above 0.5 or its goal-difference interval wholly "
                "above 0, and neither lies wholly on B's side; else no significant difference"),
    "rating": (f"Bradley-Terry (MM), a draw half a win, one virtual draw per pair; Elo scale (400 log10), mean 0; "
               f"95% interval: 2.5-97.5 percentiles of {BOOTSTRAP_RESAMPLES} bootstrap resamples of the matches "
               "within each pair"),
    "failed": "matches whose worker failed or died twice count for nothing",
    "game_flow": (f"per pair: matches with a goal in playing time, goals and own goals, and every kick-off's and "
                  f"throw-in's wait to the first touch: how many, how many over {RESTART_SLOW_S:g} s, median, longest"),
}


def table_markdown(report: TournamentReport) -> str:
    """The verdicts and tables of ``table.md`` (also printed by the command)."""
    s = report.settings
    played = len(report.records) - len(report.failed)
    kind = "self-play" if s.self_play else ("round robin" if len(s.policies) > 2 else "head to head")
    lines = [
        f"# Tournament: {', '.join(s.policies)}",
        "",
        f"{kind}, {s.matches} matches per pair ({played} played, {len(report.failed)} failed), {s.players} v "
        f"{s.players}, {s.half_seconds:g} s halves, shoot-out {'on' if s.shootout else 'off'}, seed {s.seed}, "
        f"camera profile {s.camera_profile}.",
        "",
        "## Verdicts",
        "",
        *(f"- {v}" for v in report.verdicts),
        "",
        "## Standings",
        "",
        "| policy | matches | W | D | L | win rate | 95% CI | goals for / match | goals against / match | "
        "goal difference / match | 95% CI |",
        "|---|---:|---:|---:|---:|---:|---|---:|---:|---:|---|",
        *(_standing_row(st.name, st) for st in report.standings),
    ]
    if report.ratings is not None:
        lines += ["", "## Ratings", "", "| policy | rating | 95% CI |", "|---|---:|---|"]
        lines += [f"| {r.name} | {fmt(r.rating, '+.0f')} | [{fmt(r.ci95[0], '+.0f')}, {fmt(r.ci95[1], '+.0f')}] |"
                  for r in report.ratings]
    if len(report.head_to_head) > 1:
        lines += ["", "## Head to head", "", "| pair | matches | W | D | L | win rate | 95% CI | goals for / match | "
                  "goals against / match | goal difference / match | 95% CI |",
                  "|---|---:|---:|---:|---:|---:|---|---:|---:|---:|---|"]
        lines += [_standing_row(f"{h.first} v {h.second}", h.standing) for h in report.head_to_head]
    lines += ["", "## Game flow", "",
              "| pair | matches | with goals | goals | own goals | restarts | over "
              f"{RESTART_SLOW_S:g} s | median wait (s) | longest wait (s) |",
              "|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    lines += [_flow_row(f"{h.first} v {h.second}", h.flow) for h in report.head_to_head]
    lines += ["", "## Match statistics, mean per match", "",
              "| policy | " + " | ".join(header for _, header, _ in TABLE_STATISTICS) + " |",
              "|---|" + "---:|" * len(TABLE_STATISTICS)]
    for name, means in report.team_means.items():
        cells = []
        for key, _, spec in TABLE_STATISTICS:
            cell = fmt(means[key], spec)
            if key.endswith("_mean_m") or key.endswith("_mean_deg"):
                cell += " / " + fmt(means[key.replace("_mean_", "_p95_")], spec)
            cells.append(cell)
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    if report.failed:
        lines += ["", "## Failed matches", ""]
        lines += [f"- match {r['match']} ({r['home_policy']} v {r['away_policy']}): {r['error']}" for r in report.failed]
    lines += ["", "## How to read it", ""]
    lines += [f"- {name.replace('_', ' ')}: {text}." for name, text in DEFINITIONS.items()]
    lines += ["- match statistics: see `match/statistics.py` (possession is a share of playing time; pose errors "
              "only where the policy reports an estimate, while the robot is up)."]
    return "\n".join(lines) + "\n"


def _standing_row(name: str, st: Standing) -> str:
    return (f"| {name} | {st.matches} | {st.wins} | {st.draws} | {st.losses} | {fmt(st.win_rate, '.2f')} | "
            f"[{fmt(st.win_rate_ci95[0], '.2f')}, {fmt(st.win_rate_ci95[1], '.2f')}] | "
            f"{fmt(st.goals_for_per_match, '.2f')} | {fmt(st.goals_against_per_match, '.2f')} | "
            f"{fmt(st.goal_difference, '+.2f')} | [{fmt(st.goal_difference_ci95[0], '+.2f')}, "
            f"{fmt(st.goal_difference_ci95[1], '+.2f')}] |")


def _flow_row(name: str, flow: GameFlow) -> str:
    return (f"| {name} | {flow.matches} | {flow.matches_with_goals} | {flow.goals} | {flow.own_goals} | "
            f"{fmt(flow.restarts, 'd')} | {fmt(flow.restarts_slow, 'd')} | {fmt(flow.restart_median_s, '.1f')} | "
            f"{fmt(flow.restart_max_s, '.1f')} |")


def write_table(path: Path, report: TournamentReport) -> Path:
    return write_text(path, table_markdown(report))


def running_standings(records: Sequence[Mapping], entrants: Sequence[str]) -> str:
    """The progress bar's standings so far: ``name W-D-L`` per entrant, best first."""
    rows = []
    for name in entrants:
        games = games_of(records, name)
        wins = sum(1 for g in games if g.result == 1.0)
        draws = sum(1 for g in games if g.result == 0.5)
        rows.append((wins + draws / 2.0, f"{name} {wins}-{draws}-{len(games) - wins - draws}"))
    failed = sum(1 for r in records if r["status"] != "ok")
    text = ", ".join(t for _, t in sorted(rows, key=lambda row: -row[0]))
    return text + (f", {failed} failed" if failed else "")

