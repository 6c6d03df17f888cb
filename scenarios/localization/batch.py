"""The batch of a scenario: its runs on local processes or Ray tasks, resumable, and its report.

The runs go through the batch engine (:mod:`scenarios.common.batch`), those of several scenarios
in one pool, the longest first. Every finished run is
written at once to ``DIR/runs/run_NNNN.json`` (atomically), so a batch interrupted with
Ctrl-C or killed keeps what it finished, and ``resume=True`` continues without recomputing
those runs. The report is built from the run files in run order, so it is the same whatever
the number of workers or the backend. A run that fails (its error, or its process died
twice) is not kept: the others finish, then the batch stops with the failures named, and
``--resume`` runs the failed ones again. A run file that cannot be read back as this
scenario's run (damaged outside the batch) is refused, naming it, before anything runs.
"""

from __future__ import annotations

import dataclasses
import logging
import time
from collections.abc import Sequence
from pathlib import Path

from tqdm import tqdm

from match.runner import package_versions
from scenarios.common.batch import (
    BACKENDS,
    BatchError,
    BatchOptions,
    ResultStore,
    check_bounds,
    check_fields,
    default_workers,
    execute,
    require_ray,
)
from scenarios.localization.figures import plot_errors, plot_traces
from scenarios.localization.file import NAMED_SCENARIOS, load_scenario
from scenarios.localization.run import RunOutcome, RunTask, run_tasks, simulate_run
from scenarios.localization.samples import LocalizationSample
from scenarios.localization.spec import ScenarioSpec
from scenarios.localization.statistics import ScenarioReport
from world.camera_profiles import camera_profile as world_camera_profile
from scenarios.localization.tables import (
    write_combined_summary_json,
    write_combined_table,
    write_results_csv,
    write_scenario_table,
    write_summary_json,
)

__all__ = ["BACKENDS", "BatchOptions", "RunStore", "ScenarioBatchError", "default_workers", "run_named", "run_scenario",
           "run_scenarios"]

log = logging.getLogger(__name__)

RUNS_DIR = "runs"
SCENARIO_FILE = "scenario.json"

ScenarioBatchError = BatchError  # a batch that cannot start (bad options, a directory of another scenario)


def run_scenario(spec: ScenarioSpec, key: str, out_dir: Path, options: BatchOptions = BatchOptions()) -> ScenarioReport:
    """Run every run of ``spec`` not already in ``out_dir``, then write and return the report."""
    return run_scenarios([(spec, key, Path(out_dir))], options)[0]


@dataclasses.dataclass
class _Pending:
    """One scenario of a batch: its runs, those already done, its store, when its last run finished."""

    spec: ScenarioSpec
    key: str
    store: RunStore
    tasks: tuple[RunTask, ...]
    done: dict[int, RunOutcome]
    finished_s: float = 0.0


def run_scenarios(scenarios: Sequence[tuple[ScenarioSpec, str, Path]], options: BatchOptions = BatchOptions()
                  ) -> list[ScenarioReport]:
    """Run the runs of several scenarios ((spec, key, directory) each) not already in their directories, all
    in one pool of workers, the longest first (:func:`_longest_first`), then write and return each
    scenario's report, in the order given. A report's ``wall_seconds`` is the time from the batch's
    start to the end of that scenario's last run."""
    started = time.perf_counter()
    batches = []
    for spec, key, out_dir in scenarios:
        store = RunStore(Path(out_dir), spec, resume=options.resume)
        done = store.load()
        tasks = run_tasks(spec)
        if done:
            log.info("%s: %d of %d runs already in %s", spec.name, len(done), len(tasks), out_dir)
        batches.append(_Pending(spec, key, store, tasks, done))
    of_task = {id(t): b for b in batches for t in b.tasks if t.run not in b.done}
    pending = sorted((t for b in batches for t in b.tasks if t.run not in b.done), key=_longest_first)
    name = batches[0].spec.name if len(batches) == 1 else f"{len(batches)} scenarios"
    bar = tqdm(total=sum(b.spec.expected_samples() for b in batches),
               initial=sum(o.events for b in batches for o in b.done.values()),
               unit="sample", desc=name, disable=not options.progress, dynamic_ncols=True)
    failures = []
    try:
        for result in execute(pending, simulate_run, options, lambda n=1: bar.update(n),
                              units=lambda outcome: outcome.events,
                              label=lambda task: f"{task.spec.name} run {task.run}"):
            batch = of_task[id(result.task)]
            if result.failed:
                failures.append(f"{batch.spec.name} run {result.task.run}: {result.error}")
                continue
            batch.store.save(result.value)
            batch.done[result.value.run] = result.value
            batch.finished_s = time.perf_counter() - started
    finally:
        bar.close()
    if failures:
        kept = ", ".join(str(b.store.runs_dir) for b in batches)
        raise ScenarioBatchError(f"{len(failures)} run(s) failed ({'; '.join(failures)}); the finished runs are kept "
                                 f"in {kept}: run again with --resume to retry the failed ones")
    reports = []
    for batch, (_, _, out_dir) in zip(batches, scenarios):
        outcomes = [batch.done[t.run] for t in batch.tasks]
        report = ScenarioReport(
            key=batch.key,
            spec=batch.spec,
            samples=tuple(s for o in outcomes for s in o.samples),
            run_seeds=batch.spec.run_seeds(),
            wall_seconds=batch.finished_s,
            sim_seconds=sum(o.sim_seconds for o in outcomes),
            versions=package_versions(),
        )
        write_scenario_report(Path(out_dir), report)
        reports.append(report)
    return reports


def _longest_first(task: RunTask) -> tuple[int, int]:
    """Sort key putting the longest runs first: a periodic run plays a whole match; others by their samples."""
    return (0 if task.spec.periodic else 1, -task.samples)


# ---- where finished runs are kept -----------------------------------------------------------


class RunStore:
    """The run files of one scenario in ``out_dir``; a fresh batch clears them, a resumed one checks them
    (``write=False``: only checks them)."""

    def __init__(self, out_dir: Path, spec: ScenarioSpec, resume: bool, write: bool = True):
        self.runs_dir = Path(out_dir) / RUNS_DIR
        seeds = spec.run_seeds()
        self._store = ResultStore(out_dir, fingerprint=spec.fingerprint(), settings={"scenario": spec.name},
                                  resume=resume, marker=SCENARIO_FILE, subdir=RUNS_DIR, prefix="run", key="run",
                                  what="runs", read=lambda run, data: _outcome(run, data, seeds), write=write)

    def load(self) -> dict[int, RunOutcome]:
        return self._store.load()

    def save(self, outcome: RunOutcome) -> None:
        self._store.save(outcome.run, {
            "run": outcome.run,
            "seed": outcome.seed,
            "sim_seconds": outcome.sim_seconds,
            "wall_seconds": outcome.wall_seconds,
            "complete": outcome.complete,
            "samples": [dataclasses.asdict(s) for s in outcome.samples],
        })


_RUN_FIELDS = {"run": int, "seed": int, "sim_seconds": float, "wall_seconds": float, "complete": bool, "samples": list}
_SAMPLE_TYPES = {"int": int, "float": float, "str": str}
_SAMPLE_FIELDS = {f.name: _SAMPLE_TYPES[f.type] for f in dataclasses.fields(LocalizationSample)}
_SAMPLE_REQUIRED = {f.name: _SAMPLE_FIELDS[f.name] for f in dataclasses.fields(LocalizationSample)
                    if f.default is dataclasses.MISSING}
MAX_SECONDS = 1e7  # a run's simulated or wall time
MAX_FIELD_M = 100.0  # a true position (the field and its surroundings are a few metres)
MAX_ESTIMATE = 1e6  # an estimate (m or rad) may be far off, never unbounded
MAX_COUNT = 10**9
MAX_NAME_CHARS = 200
_RUN_BOUNDS = {"sim_seconds": (0.0, MAX_SECONDS), "wall_seconds": (0.0, MAX_SECONDS)}
_SAMPLE_BOUNDS = {
    "run": (0, MAX_COUNT), "event": (0, MAX_COUNT), "sim_time_s": (0.0, MAX_SECONDS),
    "true_x": (-MAX_FIELD_M, MAX_FIELD_M), "true_y": (-MAX_FIELD_M, MAX_FIELD_M), "true_theta": (-MAX_ESTIMATE, MAX_ESTIMATE),
    "est_x": (-MAX_ESTIMATE, MAX_ESTIMATE), "est_y": (-MAX_ESTIMATE, MAX_ESTIMATE),
    "est_theta": (-MAX_ESTIMATE, MAX_ESTIMATE), "landmarks_used": (0, MAX_COUNT), "percepts": (0, MAX_COUNT),
    "compute_ms": (0.0, MAX_SECONDS * 1000.0),
}
_NAN_SAMPLE_FIELDS = ("est_x", "est_y", "est_theta", "compute_ms")  # no estimate, no time measured


def _outcome(run: int, data: dict, seeds: Sequence[int]) -> RunOutcome:
    """The outcome a run file holds; ``ValueError`` when it is not one of this scenario's runs."""
    check_fields(data, _RUN_FIELDS)
    check_bounds(data, _RUN_BOUNDS)
    if run >= len(seeds) or data["seed"] != seeds[run]:
        raise ValueError(f"run {run} with seed {data['seed']} is not a run of this scenario")
    samples = []
    for i, row in enumerate(data["samples"]):
        if not isinstance(row, dict):
            raise ValueError(f"samples[{i}] is not an object")
        check_fields(row, _SAMPLE_REQUIRED, f"samples[{i}].")
        check_fields(row, {key: kind for key, kind in _SAMPLE_FIELDS.items() if key in row}, f"samples[{i}].")
        unknown = sorted(set(row) - set(_SAMPLE_FIELDS))
        if unknown:
            raise ValueError(f"samples[{i}] has unknown keys {unknown}")
        check_bounds(row, _SAMPLE_BOUNDS, f"samples[{i}].", nan=_NAN_SAMPLE_FIELDS)
        if row["run"] != run:
            raise ValueError(f"samples[{i}].run = {row['run']}; expected {run}, the run of the file")
        for key in ("robot", "method"):
            if not 0 < len(row[key]) <= MAX_NAME_CHARS:
                raise ValueError(f"samples[{i}].{key}: {len(row[key])} characters; expected 1 to {MAX_NAME_CHARS}")
        samples.append(LocalizationSample(**row))
    return RunOutcome(run, data["seed"], tuple(samples), data["sim_seconds"], data["wall_seconds"], data["complete"])


# ---- several scenarios, as the command line names them --------------------------------------

ALL = "all"


def scenario_key(name_or_path: str) -> str:
    """The short name of a scenario in tables and directory names: "1" for a built-in, else the file stem."""
    return name_or_path if name_or_path in NAMED_SCENARIOS else Path(name_or_path).stem


def with_overrides(spec: ScenarioSpec, samples: int | None = None, seed: int | None = None,
                   methods: Sequence[str] | None = None, half_seconds: float | None = None,
                   camera_profile: str | None = None) -> ScenarioSpec:
    """``spec`` with the command line's samples, seed, methods, half length (s) and camera profile where given (runs
    capped at samples). A scenario with periodic sampling keeps its samples and methods: its runs
    last a match (``half_seconds`` sets its length) and its robots localize their own way."""
    changes: dict = {}
    if samples is not None and spec.periodic:
        log.warning("%s: its runs last a match (set its length with half_seconds); samples = %d not used",
                    spec.name, samples)
    elif samples is not None:
        changes.update(samples=samples, runs=min(spec.runs, samples))
    if seed is not None:
        changes["seed"] = seed
    if methods is not None and spec.periodic:
        log.warning("%s: its measured robots localize with their own policies; methods %s not used",
                    spec.name, ", ".join(methods))
    elif methods is not None:
        changes["methods"] = tuple(methods)
    if half_seconds is not None:
        changes["half_seconds"] = float(half_seconds)
    if camera_profile is not None:
        changes["camera_profile"] = world_camera_profile(camera_profile).name  # refused here if unknown
    return dataclasses.replace(spec, **changes)


def run_named(names: Sequence[str], out_dir: Path, options: BatchOptions, **overrides) -> list[ScenarioReport]:
    """Run the scenarios named (built-in names, paths, or "all": 1, 2, 3 and 3-match); every file, the
    backend and, resuming, every directory's run files are checked before any runs or anything is written.

    One scenario writes into ``out_dir``; several write into ``out_dir/scenario_<key>`` each,
    and the combined table and figure into ``out_dir``.
    """
    expanded = [n for name in names for n in (NAMED_SCENARIOS if name == ALL else (name,))]
    specs = [(scenario_key(n), with_overrides(load_scenario(n), **overrides)) for n in expanded]
    keys = [k for k, _ in specs]
    if len(set(keys)) != len(keys):
        raise ScenarioBatchError(f"scenarios {keys}: expected distinct names")
    if options.backend == "ray":
        require_ray()
    dirs = [Path(out_dir)] if len(specs) == 1 else [Path(out_dir) / f"scenario_{key}" for key, _ in specs]
    for directory, (_, spec) in zip(dirs, specs):
        RunStore(directory, spec, resume=options.resume, write=False)
    reports = run_scenarios([(spec, key, directory) for directory, (key, spec) in zip(dirs, specs)], options)
    if len(specs) > 1:
        write_combined_report(out_dir, reports)
    return reports


# ---- the report's files ------------------------------------------------------------------------


def write_scenario_report(out_dir: Path, report: ScenarioReport) -> list[Path]:
    """results.csv, summary.json, table.md, errors.png and traces.png of one scenario in ``out_dir``."""
    out = Path(out_dir)
    return [
        write_results_csv(out / "results.csv", report),
        write_summary_json(out / "summary.json", report),
        write_scenario_table(out / "table.md", report),
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
        write_combined_table(out / "table.md", reports),
        plot_errors(out / "errors.png", reports),
        write_combined_summary_json(out / "summary.json", reports),
    ]
