"""A tournament on the batch engine: every match played once, kept as it finishes, resumable, and its report.

The matches run on local worker processes (always in processes of their own, so a policy
that kills its process ends only its match) or as Ray tasks, through
:func:`scenarios.common.batch.execute`. Each finished match writes its outputs to
``DIR/matches/NNN/`` and then its record to ``DIR/runs/match_NNNN.json`` (atomically), so
a tournament interrupted with Ctrl-C or killed keeps what it finished, and ``resume``
plays only the matches without a record (and those that failed); a record that cannot be
read back as its match's (damaged outside the tournament) is refused, naming the file,
before anything is written. The report is built from the records in match order: the same
whatever the worker count or the backend.

With a page writer (the command line gives :func:`scenarios.replay.write_replay`), each
worker writes its match's replay page right after the match, and it is kept in
``DIR/matches/NNN/`` with the logs; a page that fails is a warning, the match is kept.
"""

from __future__ import annotations

import dataclasses
import logging
import math
import shutil
import time
from collections.abc import Mapping, Sequence
from pathlib import Path

from tqdm import tqdm

from agents.policies import policy_factory
from match.protocol.spaces import MAX_SCORE
from match.runner import package_versions
from match.statistics import TEAM_KEYS
from scenarios.common.batch import (
    BatchOptions,
    ResultStore,
    TaskResult,
    check_bounds,
    check_fields,
    execute,
    require_ray,
)
from scenarios.common.io import write_text
from scenarios.tournament.figures import plot_ratings, plot_standings
from scenarios.tournament.play import play_match
from scenarios.tournament.report import (
    TournamentReport,
    build_report,
    running_standings,
    write_results_csv,
    write_summary_json,
    write_table,
)
from scenarios.tournament.settings import MatchTask, PageWriter, TournamentError, TournamentSettings

log = logging.getLogger(__name__)

MARKER_FILE = "tournament.json"
RECORDS_DIR = "runs"
MATCHES_DIR = "matches"
MAX_RECORD_BYTES = 16 << 20  # one match's record: its score and statistics


def check_policies(settings: TournamentSettings) -> None:
    """Every policy name resolves (built in, or an importable ``package.module:ClassName``)."""
    for name in dict.fromkeys(settings.policies):
        try:
            policy_factory(name)
        except ValueError as error:
            raise TournamentError(f"POLICY: {error}") from None


def check_match_index(settings: TournamentSettings, index: int, flag: str) -> int:
    """``index`` when it names a match of ``settings`` (as ``matches/NNN`` does); a :class:`TournamentError`
    naming ``flag``, the value and the range otherwise."""
    count = settings.match_count()
    if not 0 <= index < count:
        raise TournamentError(f"{flag} {index}: expected a match index from 0 to {count - 1} "
                              f"(the tournament plays {count} matches, matches/000 to matches/{count - 1:03d})")
    return index


def match_dir(out_dir: Path, index: int) -> Path:
    return Path(out_dir) / MATCHES_DIR / f"{index:03d}"


def run_tournament(settings: TournamentSettings, out_dir: Path, options: BatchOptions = BatchOptions(),
                   page: PageWriter | None = None) -> TournamentReport:
    """Play every match of ``settings`` not already recorded in ``out_dir``; write and return the report.

    Everything is checked before anything is written: the policies, the backend, and on
    ``options.resume`` that ``out_dir`` holds matches of the same settings. ``page``: writes
    each played match's replay page in its worker (None: no pages); it is not a setting.
    """
    started = time.perf_counter()
    out_dir = Path(out_dir)
    check_policies(settings)
    if options.backend == "ray":
        require_ray()
    tasks = settings.tasks()
    store = ResultStore(out_dir, fingerprint=settings.fingerprint(), settings=settings.to_json(),
                        resume=options.resume, marker=MARKER_FILE, subdir=RECORDS_DIR, prefix="match", key="match",
                        what="matches", read=lambda index, data: stored_record(tasks, index, data),
                        max_bytes=MAX_RECORD_BYTES)
    if not options.resume:
        _clear_matches(out_dir)
    records = {i: r for i, r in store.load().items() if r["status"] == "ok"}  # failed ones are played again
    pending = [dataclasses.replace(t, page=page) for t in tasks if t.index not in records]
    if records:
        log.info("%d of %d matches already in %s", len(records), len(tasks), out_dir)
    entrants = settings.entrants()
    bar = tqdm(total=len(tasks), initial=len(records), unit="match", desc="tournament", disable=not options.progress,
               dynamic_ncols=True)
    bar.set_postfix_str(running_standings(_in_order(records), entrants))
    try:
        for result in execute(pending, play_match, options, isolate=True, label=lambda task: task.label):
            record = _keep(out_dir, store, result)
            records[record["match"]] = record
            bar.update(1)
            bar.set_postfix_str(running_standings(_in_order(records), entrants))
    finally:
        bar.close()
    ordered = [records[t.index] for t in tasks]
    report = build_report(settings, ordered, time.perf_counter() - started, package_versions())
    write_report(out_dir, report)
    return report


def _in_order(records: Mapping[int, dict]) -> list[dict]:
    return [records[i] for i in sorted(records)]


def _clear_matches(out_dir: Path) -> None:
    """A fresh tournament: the match directories of an earlier one go (only ``matches/NNN``)."""
    matches = out_dir / MATCHES_DIR
    if matches.is_dir():
        for old in matches.iterdir():
            if old.is_dir() and old.name.isdigit():
                shutil.rmtree(old)


def _keep(out_dir: Path, store: ResultStore, result: TaskResult) -> dict:
    """The match's files into ``matches/NNN`` (or its error), then its record into the store."""
    task: MatchTask = result.task
    directory = match_dir(out_dir, task.index)
    if directory.exists():
        shutil.rmtree(directory)
    directory.mkdir(parents=True)
    if result.failed:
        write_text(directory / "error.txt", result.error + "\n")
    else:
        for name, data in result.value.files.items():
            (directory / name).write_bytes(data)
        if result.value.page_error is not None:
            log.warning("%s: no replay page (%s); the match is kept", task.label, result.value.page_error)
    record = match_record(task, result)
    store.save(task.index, record)
    return record


def match_record(task: MatchTask, result: TaskResult) -> dict:
    """What the report needs of one match (plain JSON)."""
    record = {
        "match": task.index,
        "pair": task.pair,
        "game": task.game,
        "seed": task.seed,
        "home_policy": task.home,
        "away_policy": task.away,
        "home_entrant": task.entrant("home"),
        "away_entrant": task.entrant("away"),
        "status": "failed" if result.failed else "ok",
        "error": result.error,
        "attempts": result.attempts,
        "home_goals": None,
        "away_goals": None,
        "home_shootout": None,
        "away_shootout": None,
        "winner_side": None,
        "sim_seconds": None,
        "wall_seconds": None,
        "statistics": None,
    }
    if not result.failed:
        summary = result.value.summary
        shootout = summary["shootout"] or {}
        record.update(
            home_goals=summary["score"]["home"],
            away_goals=summary["score"]["away"],
            home_shootout=shootout.get("home"),
            away_shootout=shootout.get("away"),
            winner_side=summary["winner"],
            sim_seconds=summary["sim_seconds"],
            wall_seconds=round(result.value.wall_seconds, 3),
            statistics=summary["statistics"],
        )
    return record


_SCHEDULED = ("pair", "game", "seed", "home_policy", "away_policy", "home_entrant", "away_entrant")
_PLAYED_FIELDS = {"home_goals": int, "away_goals": int, "home_shootout": (int, type(None)),
                  "away_shootout": (int, type(None)), "winner_side": (str, type(None)), "sim_seconds": float,
                  "wall_seconds": float, "statistics": dict}
MAX_SIM_SECONDS = 1e7  # two halves of the longest allowed length, their pauses and a shoot-out fit many times
MAX_STATISTIC = 1e12  # a count, a share, metres or seconds of a match
_PLAYED_BOUNDS = {"home_goals": (0, MAX_SCORE), "away_goals": (0, MAX_SCORE), "home_shootout": (0, MAX_SCORE),
                  "away_shootout": (0, MAX_SCORE), "sim_seconds": (0.0, MAX_SIM_SECONDS),
                  "wall_seconds": (0.0, MAX_SIM_SECONDS)}


def stored_record(tasks: Sequence[MatchTask], index: int, data: dict) -> dict:
    """A stored record of match ``index`` as the report reads it; ``ValueError`` when it is not that match's
    (the schedule's fields differ) or a played match's record lacks a key or has one of another type."""
    if index >= len(tasks):
        raise ValueError(f"match {index} is not one of the tournament's {len(tasks)} matches")
    expected = match_record(tasks[index], TaskResult(tasks[index], error=""))
    check_fields(data, {key: type(expected[key]) for key in _SCHEDULED} | {"status": str})
    for key in _SCHEDULED:
        if data[key] != expected[key]:
            raise ValueError(f"{key} = {repr(data[key])[:60]}; match {index} of this tournament has "
                             f"{expected[key]!r}")
    if data["status"] not in ("ok", "failed"):
        raise ValueError(f"status = {data['status'][:40]!r}; expected 'ok' or 'failed'")
    if data["status"] == "ok":
        check_fields(data, _PLAYED_FIELDS)
        check_bounds(data, _PLAYED_BOUNDS)
        _check_result(data)
        for side in ("home", "away"):
            team = data["statistics"].get(side)
            if not isinstance(team, dict):
                raise ValueError(f"statistics.{side} is not an object")
            present = [key for key in TEAM_KEYS if key in team]
            check_fields(team, {key: (float, type(None)) for key in present}, f"statistics.{side}.")
            for key in present:  # NaN stands for a figure without samples
                value = team[key]
                if value is not None and not (isinstance(value, float) and math.isnan(value)
                                              or abs(value) <= MAX_STATISTIC):
                    raise ValueError(f"statistics.{side}.{key} = {value!r:.40}; expected a number of at most "
                                     f"{MAX_STATISTIC:g}")
    return data


def _check_result(data: dict) -> None:
    """The score, the shoot-out and the winner of a played match's record agree: a shoot-out only after a
    draw, both its counts or neither, and the winner the side with more goals (of the shoot-out after a draw)."""
    home, away = data["home_goals"], data["away_goals"]
    shootout = (data["home_shootout"], data["away_shootout"])
    if (shootout[0] is None) != (shootout[1] is None):
        raise ValueError(f"home_shootout = {shootout[0]}, away_shootout = {shootout[1]}; expected both or neither")
    if shootout[0] is not None and home != away:
        raise ValueError(f"a shoot-out after {home}-{away}; expected one only after a draw")
    decider = (home, away) if home != away or shootout[0] is None else shootout
    winner = None if decider[0] == decider[1] else ("home" if decider[0] > decider[1] else "away")
    if data["winner_side"] != winner:
        score = f"{home}-{away}" + (f" ({shootout[0]}-{shootout[1]} in the shoot-out)" if shootout[0] is not None else "")
        raise ValueError(f"winner_side = {data['winner_side']!r:.40} after {score}; expected {winner!r}")


def write_report(out_dir: Path, report: TournamentReport) -> list[Path]:
    """results.csv, summary.json, table.md, standings.png and (three or more policies) ratings.png."""
    out = Path(out_dir)
    paths = [
        write_results_csv(out / "results.csv", report.records),
        write_summary_json(out / "summary.json", report, report.settings.fingerprint()),
        write_table(out / "table.md", report),
        plot_standings(out / "standings.png", report),
    ]
    if report.ratings is not None:
        paths.append(plot_ratings(out / "ratings.png", report.ratings))
    return paths

