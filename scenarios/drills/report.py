"""The report of a drill batch: ``results.csv`` (a row per trial), ``summary.json`` and ``table.md``.

Everything is computed from the trial records in trial order, so the files do not depend on the
worker count or the backend. Failed trials (their worker raised, or died twice) are listed and
count for nothing in the summary. ``summary.json`` also says who played (the policies as named,
with the file and hash of a user's module or parameter file), the command line, the trial seeds,
the versions of the packages and the machine, as a match's summary does.
"""

from __future__ import annotations

import sys
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

from match.runner import machine_description, package_versions
from scenarios.common.io import json_safe, write_csv, write_json, write_text
from scenarios.common.statistics import wilson_interval
from scenarios.drills.records import TrialRecord, header
from scenarios.drills.settings import DrillSettings
from scenarios.drills.summaries import counts, interval, percent
from scenarios.matches.provenance import lineup_record


@dataclass(frozen=True)
class DrillReport:
    """A batch's settings, its trial records in trial order, the drill's summary of the played ones, and
    the batch's wall time (s)."""

    settings: DrillSettings
    records: tuple[TrialRecord, ...]
    summary: dict
    wall_seconds: float
    versions: dict = field(default_factory=package_versions)

    @property
    def played(self) -> tuple[TrialRecord, ...]:
        return tuple(r for r in self.records if r.ok)

    @property
    def failed(self) -> tuple[TrialRecord, ...]:
        return tuple(r for r in self.records if not r.ok)


def build_report(settings: DrillSettings, records: tuple[TrialRecord, ...], wall_seconds: float) -> DrillReport:
    played = [r for r in records if r.ok]
    return DrillReport(settings, records, settings.drill.summarize(played), wall_seconds)


def played_by(settings: DrillSettings) -> dict:
    """Who played: every robot's policy (as a match's summary records it), its role, and where it ran."""
    roles = settings.drill.trial_setup(settings.seed).roles
    names = settings.policy_names()
    return {**lineup_record({robot: names[role] for robot, role in roles.items()}, None), "roles": dict(roles)}


def write_report(out_dir: Path, report: DrillReport) -> list[Path]:
    """results.csv, summary.json and table.md into ``out_dir``."""
    out = Path(out_dir)
    columns = header(report.settings.drill)
    rows = ([record.to_json()[c] for c in columns] for record in report.records)
    return [write_csv(out / "results.csv", columns, rows),
            write_json(out / "summary.json", json_safe(summary_json(report))),
            write_text(out / "table.md", table_markdown(report) + "\n")]


def summary_json(report: DrillReport) -> dict:
    settings = report.settings
    seeds = settings.seeds()
    return {
        "drill": settings.drill.NAME,
        "settings": settings.to_json(),
        "fingerprint": settings.fingerprint(),
        "trials": {"planned": len(report.records), "played": len(report.played), "failed": len(report.failed)},
        "seeds": {"first": seeds[0], "last": seeds[-1], "rule": "trial k has the seed first + k"},
        "failures": [{"trial": r.trial, "seed": r.seed, "error": r.error, "attempts": r.attempts}
                     for r in report.failed],
        "summary": report.summary,
        "headline": settings.drill.headline(report.summary),
        "played_by": played_by(settings),
        "sim_seconds": round(sum(r.sim_seconds or 0.0 for r in report.records), 3),
        "wall_seconds": round(report.wall_seconds, 3),
        "command_line": list(sys.argv),
        "versions": report.versions,
        "machine": machine_description(),
    }


def table_markdown(report: DrillReport) -> str:
    """The outcomes of the played trials with 95% intervals and the drill's headline (``table.md``)."""
    settings = report.settings
    drill = settings.drill
    played = report.played
    lines = [f"# {drill.NAME} drill", "",
             f"{_policies(settings.policy_names())}; {_parameters(drill.to_json())}; {len(played)} of "
             f"{len(report.records)} trials played, seeds {settings.seeds()[0]}-{settings.seeds()[-1]}"
             + (f", {len(report.failed)} failed" if report.failed else "") + ".", "",
             "| outcome | trials | share | 95% interval |", "| --- | ---: | ---: | --- |"]
    for outcome, count in counts(played, drill.OUTCOMES).items():
        share = count / len(played) if played else None
        lines.append(f"| {outcome} | {count} | {percent(share)} | {interval(wilson_interval(count, len(played)))} |")
    lines += ["", drill.headline(report.summary)]
    return "\n".join(lines)


def _policies(names: Mapping[str, str]) -> str:
    return ", ".join(f"{role} `{name}`" for role, name in names.items())


def _parameters(values: Mapping[str, float]) -> str:
    return ", ".join(f"{name} {value:g}" for name, value in values.items())
