"""The batch engine of the scenarios and the tournaments: independent tasks on local processes
or Ray, every result kept as it arrives, resumable.

- :func:`execute` runs tasks with a module-level function ``work(task, tick)`` (``tick()``,
  when not None, counts one unit of progress from inside a task) in this process, in a pool
  of fresh (spawned) processes, or as Ray tasks, and yields a :class:`TaskResult` per task
  as it finishes, in whatever order. A task that raises is a failure with its error. A task
  whose worker process dies (``os._exit``, a crash in native code, the OOM killer) breaks
  the pool: every task that was running in it is retried once, alone in a fresh process,
  and the rest go on in a fresh pool; a task that kills its process again is a failure
  with the exit code. On Ray, Ray retries a task whose worker died once.
- :class:`ResultStore` keeps one JSON file per finished task in ``DIR/<subdir>/`` (written
  atomically) with a fingerprint of the settings; a marker file in ``DIR`` names the
  settings. A fresh batch clears the old files; a resumed one keeps those of the same
  fingerprint and refuses a directory of other settings, naming both. Since every file is
  written atomically, a file that cannot be read back (truncated, not JSON, not an object,
  a key missing or of another type, another task's record under this task's name) was
  damaged outside the batch: a resumed batch refuses it, naming the file, before anything
  is written, rather than overwrite it. The files are read as untrusted
  (:mod:`scenarios.common.untrusted`: regular files of a bounded size, JSON of a bounded
  depth); :func:`check_fields` checks a record's keys and :func:`check_bounds` its numbers.

A Ctrl-C (``KeyboardInterrupt``; under the command line a SIGTERM too) stops the batch: tasks
not finished are cancelled, the worker processes are stopped (:mod:`scenarios.common.termination`)
and the results already yielded (and stored by the caller) are kept for ``--resume``. A
worker process ends with the process that started it, even one killed by SIGKILL.
"""

from __future__ import annotations

import collections
import concurrent.futures
import dataclasses
import importlib.util
import json
import logging
import math
import multiprocessing
import os
import queue
import sys
from collections.abc import Callable, Iterator, Mapping, Sequence
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path
from typing import Any

from scenarios.common.io import write_text, write_text_atomic
from scenarios.common.untrusted import LongNumber, SmallFileError, load_json, read_small_file
from scenarios.common.termination import (
    end_interrupted,
    parent_alive,
    prepare_worker,
    stop_processes,
)

log = logging.getLogger(__name__)

BACKENDS = ("local", "ray")
RETRIES = 1  # a task whose worker process died runs once more
MAX_MARKER_BYTES = 1 << 20  # the settings of a batch
MAX_RECORD_BYTES = 256 << 20  # a task's record: a scenario run of 100,000 samples of 4 methods fits
_POLL_S = 0.2

Work = Callable[[Any, Callable[..., None] | None], Any]
Progress = Callable[..., None]  # progress(n=1): n more units done


class BatchError(ValueError):
    """A batch that cannot start: bad options, a missing extra, a directory of other settings or a damaged file."""


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
            raise BatchError(f"workers = {self.workers!r}; expected an integer >= 1")
        if self.backend not in BACKENDS:
            raise BatchError(f"backend = {self.backend!r}; expected one of {', '.join(BACKENDS)}")


def default_workers() -> int:
    """All cores of this machine."""
    return max(1, os.cpu_count() or 1)


def require_ray() -> None:
    """:class:`BatchError` when Ray is not installed (check before writing anything)."""
    if importlib.util.find_spec("ray") is None:
        raise BatchError("backend 'ray' needs Ray: pip install 'robotstadium[ray]'")


@dataclasses.dataclass(frozen=True)
class TaskResult:
    """What became of one task: its ``value``, or its ``error`` (one line); ``attempts`` it took."""

    task: Any
    value: Any = None
    error: str | None = None
    attempts: int = 1

    @property
    def failed(self) -> bool:
        return self.error is not None


def describe_error(error: BaseException) -> str:
    """One line: the exception's type and message."""
    text = " ".join(str(error).split())
    return f"{type(error).__name__}: {text}" if text else type(error).__name__


# ---- running tasks ---------------------------------------------------------------------------


def execute(
    tasks: Sequence[Any],
    work: Work,
    options: BatchOptions,
    progress: Progress | None = None,
    *,
    units: Callable[[Any], int] | None = None,
    isolate: bool = False,
    label: Callable[[Any], str] = repr,
) -> Iterator[TaskResult]:
    """Run ``work(task, tick)`` for every task; yield each :class:`TaskResult` as it finishes.

    One worker runs the tasks in this process unless ``isolate`` (then always in worker
    processes, so a task that kills its process does not end the batch). ``units(value)``:
    the progress a finished task counts on Ray, where ticks from inside tasks do not reach
    ``progress``. ``label(task)`` names a task in log messages.
    """
    if not tasks:
        return
    progress = progress or (lambda n=1: None)
    if options.backend == "ray":
        yield from _execute_ray(tasks, work, options, progress, units, label)
    elif not isolate and (options.workers == 1 or len(tasks) == 1):
        yield from _execute_here(tasks, work, progress, label)
    else:
        yield from _execute_pool(tasks, work, options.workers, progress, label)


def _execute_here(tasks: Sequence[Any], work: Work, progress: Progress,
                  label: Callable[[Any], str]) -> Iterator[TaskResult]:
    for task in tasks:
        try:
            value = work(task, lambda *_: progress())
        except Exception as error:  # a failing task must not end the batch
            log.warning("%s failed", label(task), exc_info=True)
            yield TaskResult(task, error=describe_error(error))
        else:
            yield TaskResult(task, value)


def _execute_pool(tasks: Sequence[Any], work: Work, workers: int, progress: Progress,
                  label: Callable[[Any], str]) -> Iterator[TaskResult]:
    """A pool of spawned processes; after a worker died, its tasks alone, then a fresh pool for the rest."""
    context = multiprocessing.get_context("spawn")  # fresh interpreters: no state shared with this one
    ticks = context.Queue()
    waiting = collections.deque(tasks)
    while waiting:
        crashed: list[Any] = []
        yield from _run_pool(context, ticks, waiting, work, min(workers, len(waiting)), progress, crashed, label)
        for task in crashed:
            yield _run_alone(context, ticks, work, task, progress, label)


def _run_pool(context, ticks, waiting: collections.deque, work: Work, workers: int, progress: Progress,
              crashed: list, label: Callable[[Any], str]) -> Iterator[TaskResult]:
    """Tasks from ``waiting``, at most ``workers`` at once, until done or the pool broke (then ``crashed``)."""
    broken = False
    try:
        threads = max(1, (os.cpu_count() or 1) // workers)  # each worker's share of the cores for compiled code
        with concurrent.futures.ProcessPoolExecutor(max_workers=workers, mp_context=context, initializer=_init_worker,
                                                    initargs=(ticks, os.getpid(), threads)) as pool:
            running: dict[concurrent.futures.Future, Any] = {}
            try:
                while running or (waiting and not broken):
                    while waiting and not broken and len(running) < workers:
                        task = waiting.popleft()
                        running[pool.submit(_work_in_worker, work, task)] = task
                    finished, _ = concurrent.futures.wait(running, timeout=_POLL_S,
                                                          return_when=concurrent.futures.FIRST_COMPLETED)
                    _drain(ticks, progress)
                    for future in finished:
                        task = running.pop(future)
                        try:
                            value = future.result()
                        except BrokenProcessPool as error:
                            broken = True
                            crashed.append(task)
                            log.warning("%s: a worker process died (%s); it runs again alone in a fresh process",
                                        label(task), describe_error(error))
                        except Exception as error:
                            log.warning("%s failed: %s", label(task), describe_error(error))
                            yield TaskResult(task, error=describe_error(error))
                        else:
                            yield TaskResult(task, value)
            except BaseException:  # a Ctrl-C or a SIGTERM (see termination): no task goes on
                for future in running:
                    future.cancel()
                workers_now = list((getattr(pool, "_processes", None) or {}).values())
                pool.shutdown(wait=False, cancel_futures=True)  # each worker ends after its task
                stop_processes(workers_now)  # which a SIGTERM interrupts
                raise
    finally:
        _drain(ticks, progress)  # the workers have exited: their last ticks are in the queue


def _run_alone(context, ticks, work: Work, task: Any, progress: Progress, label: Callable[[Any], str]) -> TaskResult:
    """One task in a fresh process of its own: its result, its error, or how the process died."""
    receive, send = context.Pipe(duplex=False)
    # not daemonic: its match may start controller processes
    process = context.Process(target=_work_alone, args=(work, task, ticks, send, os.getpid()))
    process.start()
    send.close()  # the child holds the only sending end: its death reads as end of file
    message = None
    try:
        while message is None:
            _drain(ticks, progress)
            if receive.poll(_POLL_S):
                try:
                    message = receive.recv()
                except EOFError:
                    break
        process.join()
    except BaseException:
        stop_processes([process])
        raise
    finally:
        receive.close()
        _drain(ticks, progress)
    attempts = 1 + RETRIES
    if message is None:
        error = f"the worker process died ({_exit_text(process.exitcode)}), again when run alone"
        log.warning("%s failed: %s", label(task), error)
        return TaskResult(task, error=error, attempts=attempts)
    kind, payload = message
    if kind == "error":
        log.warning("%s failed: %s", label(task), payload)
        return TaskResult(task, error=payload, attempts=attempts)
    return TaskResult(task, payload, attempts=attempts)


def _exit_text(code: int | None) -> str:
    if code is not None and code < 0:
        return f"killed by signal {-code}"
    return f"exit code {code}"


_worker_queue = None
_worker_parent = None


def _init_worker(ticks, parent_pid: int, threads: int = 1) -> None:
    """A pool worker's start: ``threads`` threads for numba's parallel code (the renderer's cameras), so that
    the workers together use the cores once. Set before numba is loaded, so that numba starts no more
    and, with one, none (its threading layer is chosen where its parallel code first runs)."""
    global _worker_queue, _worker_parent
    prepare_worker(parent_pid)
    if "numba" in sys.modules:  # loaded already: its thread count is fixed, use fewer of them
        import numba

        numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
    else:
        os.environ["NUMBA_NUM_THREADS"] = str(threads)
    _worker_queue, _worker_parent = ticks, parent_pid


def _tick(*_: object) -> None:
    """A worker's progress: one unit to the parent (whatever the task passes)."""
    if _worker_queue is not None:
        _worker_queue.put(1)


def _work_in_worker(work: Work, task: Any) -> Any:
    try:
        return work(task, _tick)
    except KeyboardInterrupt:  # stopped: the task has cleaned up on its way here
        if parent_alive(_worker_parent):
            raise  # to the parent, which shuts the pool down
        end_interrupted()  # the parent is gone: no pool to wait for


def _work_alone(work: Work, task: Any, ticks, send, parent_pid: int) -> None:
    _init_worker(ticks, parent_pid, os.cpu_count() or 1)  # alone: all the cores
    try:
        value = work(task, _tick)
    except Exception as error:
        send.send(("error", describe_error(error)))
    except KeyboardInterrupt:
        send.close()
        end_interrupted()
    else:
        send.send(("ok", value))
    finally:
        send.close()


def _drain(ticks, progress: Progress) -> None:
    while True:
        try:
            ticks.get_nowait()
        except queue.Empty:
            return
        progress()


def _execute_ray(tasks: Sequence[Any], work: Work, options: BatchOptions, progress: Progress,
                 units: Callable[[Any], int] | None, label: Callable[[Any], str]) -> Iterator[TaskResult]:
    """The same tasks as Ray tasks on the cluster at ``ray_address``, or on a local Ray instance."""
    require_ray()
    import ray

    started_here = not ray.is_initialized()
    if started_here:
        if options.ray_address is None:
            ray.init(num_cpus=options.workers, include_dashboard=False, log_to_driver=False)
        else:
            ray.init(address=options.ray_address, log_to_driver=False)
    try:
        remote = ray.remote(num_cpus=1, max_retries=RETRIES)(work)
        by_ref = {remote.remote(task, None): task for task in tasks}
        pending = list(by_ref)
        while pending:
            finished, pending = ray.wait(pending, num_returns=1)
            task = by_ref[finished[0]]
            try:
                value = ray.get(finished[0])
            except ray.exceptions.RayTaskError as error:  # the task raised
                cause = getattr(error, "cause", None) or error
                log.warning("%s failed: %s", label(task), describe_error(cause))
                yield TaskResult(task, error=describe_error(cause))
            except ray.exceptions.RayError as error:  # its worker died, twice
                message = f"the worker process died ({type(error).__name__}), again when retried"
                log.warning("%s failed: %s", label(task), message)
                yield TaskResult(task, error=message, attempts=1 + RETRIES)
            else:
                if units is not None:
                    progress(units(value))
                yield TaskResult(task, value)
    finally:
        if started_here:
            ray.shutdown()


# ---- where finished tasks are kept ----------------------------------------------------------


class ResultStore:
    """One JSON file per finished task, ``DIR/<subdir>/<prefix>_NNNN.json``, and the marker ``DIR/<marker>``.

    ``settings``: what the marker records besides the ``fingerprint`` (plain JSON values),
    named in the message when a resumed batch finds other settings; ``key``: the field of a
    stored task that holds its index; ``what``: how the message names the stored tasks.
    ``read(index, data)``: the caller's value of a stored task, raising ``ValueError`` for
    one it cannot use (the store refuses the file, naming it). A resumed store reads and
    checks every file when it is made, before it writes anything; ``write=False`` only reads
    and checks (a batch checks all its directories before it runs any). ``max_bytes``: the
    largest task file read.
    """

    def __init__(self, out_dir: Path, *, fingerprint: str, settings: Mapping[str, object], resume: bool,
                 marker: str, subdir: str = "runs", prefix: str = "run", key: str = "run", what: str = "runs",
                 read: Callable[[int, dict], Any] = lambda index, data: data, write: bool = True,
                 max_bytes: int = MAX_RECORD_BYTES):
        out_dir = Path(out_dir)
        self.dir = out_dir / subdir
        self.fingerprint = fingerprint
        self.prefix = prefix
        self.key = key
        self.max_bytes = max_bytes
        marker_path = out_dir / marker
        self._stored: dict[int, Any] = {}
        if resume:
            if os.path.lexists(marker_path):
                stored = _read_object(marker_path, MAX_MARKER_BYTES, task=False)
                if stored.get("fingerprint") != fingerprint:
                    raise BatchError(_mismatch(out_dir, what, stored, dict(settings), fingerprint))
            self._stored = self._read_all(read)
        if not write:
            return
        self.dir.mkdir(parents=True, exist_ok=True)
        if not resume:
            for old in self.dir.glob(f"{prefix}_*.json"):
                old.unlink()
        write_text(marker_path, json.dumps({**settings, "fingerprint": fingerprint}) + "\n")

    def path(self, index: int) -> Path:
        return self.dir / f"{self.prefix}_{index:04d}.json"

    def load(self) -> dict[int, Any]:
        """The stored tasks of this fingerprint, by index, as ``read`` made them (files of another are ignored)."""
        return dict(self._stored)

    def _read_all(self, read: Callable[[int, dict], Any]) -> dict[int, Any]:
        done = {}
        for path in sorted(self.dir.glob(f"{self.prefix}_*.json")):
            data = _read_object(path, self.max_bytes)
            if not isinstance(data.get("fingerprint"), str):
                raise BatchError(_damaged(path, "no settings fingerprint"))
            if data["fingerprint"] != self.fingerprint:
                log.warning("ignoring %s: written with other settings", path)
                continue
            index = data.get(self.key)
            if not _is_int(index) or index < 0 or self.path(index).name != path.name:
                raise BatchError(_damaged(path, f"{self.key} = {_short(index)}, which is not the file's name"))
            try:
                done[index] = read(index, data)
            except ValueError as error:
                raise BatchError(_damaged(path, str(error))) from None
        return done

    def save(self, index: int, data: Mapping[str, object]) -> Path:
        """``data`` (plain JSON; NaN kept as NaN, which Python's JSON reads) as task ``index``, atomically."""
        return write_text_atomic(self.path(index), json.dumps({"fingerprint": self.fingerprint, **data}) + "\n")


def check_fields(data: Mapping, fields: Mapping[str, type | tuple[type, ...]], where: str = "") -> None:
    """Every key of ``fields`` is in ``data`` with a value of its type(s): a ``float`` field also takes
    an integer, no number field takes a bool. A ``ValueError`` naming the first key that is not."""
    for key, kinds in fields.items():
        kinds = kinds if isinstance(kinds, tuple) else (kinds,)
        value = data.get(key, _ABSENT)
        if value is _ABSENT:
            raise ValueError(f"{where}{key} is missing")
        if not any(_is_kind(value, kind) for kind in kinds):
            names = " or ".join(_KIND_NAMES.get(kind, kind.__name__) for kind in kinds)
            raise ValueError(f"{where}{key} = {_short(value)}; expected {names}")


_ABSENT = object()
_JSON_NAMES = {list: "array", str: "string", int: "number", float: "number", bool: "boolean", type(None): "null"}
_KIND_NAMES = {int: "an integer", float: "a number", str: "a string", bool: "true or false", list: "an array",
               dict: "an object", type(None): "null"}


def _is_kind(value: object, kind: type) -> bool:
    if kind is float:
        return isinstance(value, (int, float)) and not isinstance(value, bool)
    if kind is int:
        return _is_int(value)
    return isinstance(value, kind)


def _is_int(value: object) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def check_bounds(data: Mapping, bounds: Mapping[str, tuple[float, float]], where: str = "",
                 nan: Sequence[str] = ()) -> None:
    """Every number of ``data`` under a key of ``bounds`` (its type already checked) is finite and within its
    (low, high); None passes, and NaN for the keys of ``nan`` (a figure that has none). A ``ValueError``
    naming the first key that is not."""
    for key, (low, high) in bounds.items():
        value = data.get(key)
        if value is None or (key in nan and isinstance(value, float) and math.isnan(value)):
            continue
        finite = isinstance(value, int) or math.isfinite(value)  # an int past float's range is finite
        if not (finite and low <= value <= high):
            raise ValueError(f"{where}{key} = {_short(value)}; expected a finite number from {low:g} to {high:g}")


def _short(value: object) -> str:
    if isinstance(value, LongNumber):
        return repr(value)
    text = json.dumps(value) if isinstance(value, (str, int, float, bool, type(None))) else type(value).__name__
    return text if len(text) <= 40 else text[:37] + "..."


def _read_object(path: Path, max_bytes: int, task: bool = True) -> dict:
    """A JSON object from ``path`` (a task's file, or the marker), read as untrusted; a :class:`BatchError`
    naming the file when it is not one (not a regular file of at most ``max_bytes``, not UTF-8 JSON, nested
    too deep, not an object)."""
    try:
        data = load_json(read_small_file(path, max_bytes))
    except SmallFileError as error:
        raise BatchError(_damaged(path, error.reason, task)) from None
    if not isinstance(data, dict):
        raise BatchError(_damaged(path, f"a JSON {_JSON_NAMES.get(type(data), 'value')}, not an object", task))
    return data


def _damaged(path: Path, problem: str, task: bool = True) -> str:
    """The refusal to resume from a damaged file."""
    advice = "delete it to run its task again, or run" if task else "run"
    return f"{path}: damaged, cannot resume from it ({problem}): {advice} without --resume to start over"


def _mismatch(out_dir: Path, what: str, stored: dict, settings: dict, fingerprint: str) -> str:
    """The refusal to resume: the settings that differ, as stored and as asked, and both fingerprints."""
    keys = [k for k in dict.fromkeys([*settings, *stored]) if k != "fingerprint" and stored.get(k) != settings.get(k)]

    def shown(values: dict) -> str:
        return ", ".join(f"{k}={json.dumps(values.get(k))}" for k in keys) or "other settings"

    return (f"{out_dir} holds {what} of {shown(stored)} (fingerprint {stored.get('fingerprint')}); this command asks "
            f"for {shown(settings)} (fingerprint {fingerprint}): run without --resume to start over, or use another --out")
