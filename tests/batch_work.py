"""Work functions for the batch engine's tests, importable by spawned worker processes."""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

from scenarios.common.batch import BatchOptions, execute
from scenarios.common.termination import terminate_as_interrupt


def square(task: int, tick=None) -> int:
    if tick is not None:
        tick()
    return task * task


def dies_on_three(task: int, tick=None) -> int:
    """Kills its process on task 3 (after its neighbours started), squares the others."""
    if task == 3:
        time.sleep(0.3)
        os._exit(3)
    time.sleep(0.6)
    return task * task


def raises_on_two(task: int, tick=None) -> int:
    if task == 2:
        raise RuntimeError("task two fails")
    return task * task


def waits_long(task: tuple[str, int], tick=None) -> int:
    """Writes its process id to ``DIR/worker<N>.pid`` and sleeps a minute: a task a stop must cut short.

    With ``DIR/die-first`` present, the first run of task 0 removes it and kills its process, so that the task
    runs again alone in a fresh process."""
    directory, index = task
    first = Path(directory, "die-first")
    if index == 0 and first.exists():
        first.unlink()
        os._exit(3)
    Path(directory, f"worker{index}.pid").write_text(str(os.getpid()))
    time.sleep(60)
    return index


def run_until_stopped(directory: str, tasks: int) -> None:
    """A main process as the command line runs one: ``tasks`` long tasks on two worker processes, a SIGTERM
    as a Ctrl-C, exit code 130 when interrupted."""
    with terminate_as_interrupt():
        try:
            list(execute([(directory, index) for index in range(tasks)], waits_long, BatchOptions(workers=2),
                         isolate=True))
        except KeyboardInterrupt:
            sys.exit(130)
