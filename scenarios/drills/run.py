"""A drill batch on the batch engine: every trial played once, kept as it finishes, resumable, and its report.

The trials run on local worker processes (in this process with one worker) or as Ray tasks,
through :func:`scenarios.common.batch.execute`. Each finished trial writes its record to
``DIR/runs/trial_NNNN.json`` (atomically), so a batch interrupted with Ctrl-C or killed keeps
what it finished, and ``resume`` plays only the trials without a record (and those that
failed); a record that cannot be read back as its trial's is refused, naming the file, before
anything is written. Then ``results.csv``, ``summary.json`` and ``table.md`` are written from
the records in trial order.
"""

from __future__ import annotations

import dataclasses
import logging
import time
from collections.abc import Mapping
from pathlib import Path

from tqdm import tqdm

from agents.policies import policy_factory
from scenarios.common.batch import BatchOptions, ResultStore, TaskResult, execute, require_ray
from scenarios.drills.base import DrillError, flag_of
from scenarios.drills.records import TrialRecord, stored_record
from scenarios.drills.report import DrillReport, build_report, write_report
from scenarios.drills.settings import DrillSettings, TrialTask
from scenarios.drills.trial import play_trial

log = logging.getLogger(__name__)

MARKER_FILE = "drill.json"
RECORDS_DIR = "runs"
MAX_RECORD_BYTES = 1 << 20  # one trial's record: a few figures


def check_policies(settings: DrillSettings) -> None:
    """Every policy name resolves (built in, or an importable ``package.module:ClassName``); a
    :class:`DrillError` naming the role's flag otherwise."""
    for role, name in settings.policies:
        try:
            policy_factory(name)
        except ValueError as error:
            raise DrillError(f"--{flag_of(role)}: {error}") from None


def run_drill(settings: DrillSettings, out_dir: Path, options: BatchOptions = BatchOptions()) -> DrillReport:
    """Play every trial of ``settings`` not already recorded in ``out_dir``; write and return the report.

    Everything is checked before anything is written: the policies, the backend, and on
    ``options.resume`` that ``out_dir`` holds trials of the same settings, each record sound.
    """
    started = time.perf_counter()
    out_dir = Path(out_dir)
    check_policies(settings)
    if options.backend == "ray":
        require_ray()
    tasks = settings.tasks()
    store = ResultStore(out_dir, fingerprint=settings.fingerprint(), settings=settings.to_json(),
                        resume=options.resume, marker=MARKER_FILE, subdir=RECORDS_DIR, prefix="trial", key="trial",
                        what="trials", read=lambda index, data: stored_record(tasks, index, data),
                        max_bytes=MAX_RECORD_BYTES)
    records = {i: r for i, r in store.load().items() if r.ok}  # failed ones are played again
    pending = [t for t in tasks if t.index not in records]
    if records:
        log.info("%d of %d trials already in %s", len(records), len(tasks), out_dir)
    drill = settings.drill
    bar = tqdm(total=len(tasks), initial=len(records), unit="trial", desc=f"drill {drill.NAME}",
               disable=not options.progress, dynamic_ncols=True)
    bar.set_postfix_str(_tally(records))
    try:
        for result in execute(pending, play_trial, options, label=lambda task: task.label):
            record = _record(result)
            store.save(record.trial, record.to_json())
            records[record.trial] = record
            bar.update(1)
            bar.set_postfix_str(_tally(records))
    finally:
        bar.close()
    report = build_report(settings, tuple(records[t.index] for t in tasks), time.perf_counter() - started)
    write_report(out_dir, report)
    return report


def _record(result: TaskResult) -> TrialRecord:
    task: TrialTask = result.task
    if result.failed:
        return TrialRecord.failure(task, result.error, result.attempts)
    return dataclasses.replace(result.value, attempts=result.attempts)


def _tally(records: Mapping[int, TrialRecord]) -> str:
    """The outcomes so far, for the progress bar: ``home 3, away 2, failed 1``."""
    found: dict[str, int] = {}
    for record in records.values():
        key = record.outcome if record.ok else "failed"
        found[key] = found.get(key, 0) + 1
    return ", ".join(f"{name} {count}" for name, count in sorted(found.items()))
