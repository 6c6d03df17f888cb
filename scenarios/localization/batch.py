"""The batch of a scenario: its runs on local processes or Ray tasks, resumable, and its report.

Every finished run is written at once to ``DIR/runs/run_NNNN.json`` (atomically), so a
batch interrupted with Ctrl-C or killed keeps what it finished, and ``resume=True``
continues without recomputing those runs. The report is built from the run files in run
order, so it is the same whatever the number of workers or the backend.
"""

from __future__ import annotations

import concurrent.futures
import dataclasses
import json
import logging
import multiprocessing
import os
import queue
import time
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path

from tqdm import tqdm

from match.runner import package_versions
from scenarios.common.io import write_text, write_text_atomic
from scenarios.localization.figures import plot_errors, plot_traces
from scenarios.localization.file import BUILTIN_SCENARIOS, load_scenario
from scenarios.localization.run import RunOutcome, RunTask, run_tasks, simulate_run
from scenarios.localization.samples import LocalizationSample
from scenarios.localization.spec import ScenarioSpec
from scenarios.localization.statistics import ScenarioReport
from scenarios.localization.tables import (
    write_combined_summary_json,
    write_combined_table,
    write_results_csv,
    write_scenario_table,
    write_summary_json,
)

log = logging.getLogger(__name__)

BACKENDS = ("local", "ray")
RUNS_DIR = "runs"
SCENARIO_FILE = "scenario.json"
_POLL_S = 0.2


class ScenarioBatchError(ValueError):
    """A batch that cannot start: a bad backend, a missing extra, a directory of another scenario."""


@dataclasses.dataclass(frozen=True)
class BatchOptions:
    """How to run: ``workers`` processes (or Ray CPUs), the backend, resuming, a progress bar."""

    workers: int = 1
    backend: str = "local"
    ray_address: str | None = None
    resume: bool = False
    progress: bool = True

    def __post_init__(self) -> None:
        if not isinstance(self.workers, int) or self.workers < 1:
            raise ScenarioBatchError(f"workers = {self.workers!r}; expected an integer >= 1")
        if self.backend not in BACKENDS:
            raise ScenarioBatchError(f"backend = {self.backend!r}; expected one of {', '.join(BACKENDS)}")


def default_workers() -> int:
    """All cores of this machine."""
    return max(1, os.cpu_count() or 1)


def run_scenario(spec: ScenarioSpec, key: str, out_dir: Path, options: BatchOptions = BatchOptions()) -> ScenarioReport:
    """Run every run of ``spec`` not already in ``out_dir``, then write and return the report."""
    started = time.perf_counter()
    out_dir = Path(out_dir)
    store = RunStore(out_dir, spec, resume=options.resume)
    tasks = run_tasks(spec)
    done = store.load()
    pending = [t for t in tasks if t.run not in done]
    if done:
        log.info("%s: %d of %d runs already in %s", spec.name, len(done), len(tasks), out_dir)
    bar = tqdm(total=spec.samples, initial=sum(o.events for o in done.values()),
               unit="sample", desc=spec.name, disable=not options.progress, dynamic_ncols=True)
    try:
        execute = _execute_ray if options.backend == "ray" else _execute_local
        for outcome in execute(pending, options, lambda n=1: bar.update(n)):
            store.save(outcome)
            done[outcome.run] = outcome
    finally:
        bar.close()
    outcomes = [done[t.run] for t in tasks]
    samples = tuple(s for o in outcomes for s in o.samples)
    report = ScenarioReport(
        key=key,
        spec=spec,
        samples=samples,
        run_seeds=spec.run_seeds(),
        wall_seconds=time.perf_counter() - started,
        sim_seconds=sum(o.sim_seconds for o in outcomes),
        versions=package_versions(),
    )
    write_scenario_report(out_dir, report)
    return report


# ---- where finished runs are kept -----------------------------------------------------------


class RunStore:
    """The run files of one scenario in ``out_dir``; a fresh batch clears them, a resumed one checks them."""

    def __init__(self, out_dir: Path, spec: ScenarioSpec, resume: bool):
        self.runs_dir = out_dir / RUNS_DIR
        self.fingerprint = spec.fingerprint()
        marker = out_dir / SCENARIO_FILE
        if resume and marker.exists():
            stored = json.loads(marker.read_text(encoding="utf-8")).get("fingerprint")
            if stored != self.fingerprint:
                raise ScenarioBatchError(
                    f"{out_dir} holds runs of another scenario or settings (fingerprint {stored}); expected "
                    f"{self.fingerprint} for {spec.name!r}: run without --resume to start over, or use another --out"
                )
        self.runs_dir.mkdir(parents=True, exist_ok=True)
        if not resume:
            for old in self.runs_dir.glob("run_*.json"):
                old.unlink()
        write_text(marker, json.dumps({"scenario": spec.name, "fingerprint": self.fingerprint}) + "\n")

    def load(self) -> dict[int, RunOutcome]:
        done = {}
        for path in sorted(self.runs_dir.glob("run_*.json")):
            data = json.loads(path.read_text(encoding="utf-8"))
            if data.get("fingerprint") != self.fingerprint:
                log.warning("ignoring %s: written for another scenario", path)
                continue
            outcome = RunOutcome(
                data["run"], data["seed"], tuple(LocalizationSample(**row) for row in data["samples"]),
                data["sim_seconds"], data["wall_seconds"], data["complete"],
            )
            done[outcome.run] = outcome
        return done

    def save(self, outcome: RunOutcome) -> None:
        data = {
            "fingerprint": self.fingerprint,
            "run": outcome.run,
            "seed": outcome.seed,
            "sim_seconds": outcome.sim_seconds,
            "wall_seconds": outcome.wall_seconds,
            "complete": outcome.complete,
            "samples": [dataclasses.asdict(s) for s in outcome.samples],
        }
        # NaN kept as NaN: Python's JSON reads it
        write_text_atomic(self.runs_dir / f"run_{outcome.run:04d}.json", json.dumps(data) + "\n")


# ---- backends ----------------------------------------------------------------------------------

Progress = Callable[..., None]


def _execute_local(tasks: Sequence[RunTask], options: BatchOptions, progress: Progress) -> Iterator[RunOutcome]:
    """Runs in this process (one worker) or in a pool of fresh processes; outcomes as they finish."""
    if not tasks:
        return
    if options.workers == 1 or len(tasks) == 1:
        for task in tasks:
            yield simulate_run(task, lambda run: progress())
        return
    context = multiprocessing.get_context("spawn")  # fresh interpreters: no state shared with this one
    samples_done = context.Queue()
    with concurrent.futures.ProcessPoolExecutor(
        max_workers=min(options.workers, len(tasks)), mp_context=context, initializer=_init_worker,
        initargs=(samples_done,),
    ) as pool:
        futures = {pool.submit(_simulate_in_worker, task) for task in tasks}
        try:
            while futures:
                finished, futures = concurrent.futures.wait(futures, timeout=_POLL_S,
                                                            return_when=concurrent.futures.FIRST_COMPLETED)
                _drain(samples_done, progress)
                for future in finished:
                    yield future.result()
        except BaseException:
            for future in futures:
                future.cancel()
            raise
        finally:
            _drain(samples_done, progress)


_worker_queue = None


def _init_worker(samples_done) -> None:
    global _worker_queue
    _worker_queue = samples_done


def _simulate_in_worker(task: RunTask) -> RunOutcome:
    return simulate_run(task, _worker_queue.put if _worker_queue is not None else None)


def _drain(samples_done, progress: Progress) -> None:
    while True:
        try:
            samples_done.get_nowait()
        except queue.Empty:
            return
        progress()


def _execute_ray(tasks: Sequence[RunTask], options: BatchOptions, progress: Progress) -> Iterator[RunOutcome]:
    """The same runs as Ray tasks on the cluster at ``ray_address``, or on a local Ray instance."""
    try:
        import ray
    except ImportError:
        raise ScenarioBatchError("backend 'ray' needs Ray: pip install 'robotstadium[ray]'") from None
    if not tasks:
        return
    started_here = not ray.is_initialized()
    if started_here:
        if options.ray_address is None:
            ray.init(num_cpus=options.workers, include_dashboard=False, log_to_driver=False)
        else:
            ray.init(address=options.ray_address, log_to_driver=False)
    try:
        remote = ray.remote(num_cpus=1)(simulate_run)
        pending = [remote.remote(task) for task in tasks]
        while pending:
            finished, pending = ray.wait(pending, num_returns=1)
            outcome = ray.get(finished[0])
            progress(outcome.events)
            yield outcome
    finally:
        if started_here:
            ray.shutdown()


# ---- several scenarios, as the command line names them --------------------------------------

ALL = "all"


def scenario_key(name_or_path: str) -> str:
    """The short name of a scenario in tables and directory names: "1" for a built-in, else the file stem."""
    return name_or_path if name_or_path in BUILTIN_SCENARIOS else Path(name_or_path).stem


def with_overrides(spec: ScenarioSpec, samples: int | None = None, seed: int | None = None,
                   methods: Sequence[str] | None = None) -> ScenarioSpec:
    """``spec`` with the command line's samples, seed and methods where given (runs capped at samples)."""
    changes: dict = {}
    if samples is not None:
        changes.update(samples=samples, runs=min(spec.runs, samples))
    if seed is not None:
        changes["seed"] = seed
    if methods is not None:
        changes["methods"] = tuple(methods)
    return dataclasses.replace(spec, **changes)


def run_named(names: Sequence[str], out_dir: Path, options: BatchOptions, **overrides) -> list[ScenarioReport]:
    """Run the scenarios named (built-in names, paths, or "all"); every file is checked before any runs.

    One scenario writes into ``out_dir``; several write into ``out_dir/scenario_<key>`` each,
    and the combined table and figure into ``out_dir``.
    """
    expanded = [n for name in names for n in (BUILTIN_SCENARIOS if name == ALL else (name,))]
    specs = [(scenario_key(n), with_overrides(load_scenario(n), **overrides)) for n in expanded]
    keys = [k for k, _ in specs]
    if len(set(keys)) != len(keys):
        raise ScenarioBatchError(f"scenarios {keys}: expected distinct names")
    if len(specs) == 1:
        return [run_scenario(specs[0][1], specs[0][0], out_dir, options)]
    reports = [run_scenario(spec, key, Path(out_dir) / f"scenario_{key}", options) for key, spec in specs]
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
