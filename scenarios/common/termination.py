"""How a batch ends when it is told to: a SIGTERM is a Ctrl-C, and worker processes end with their parent.

- :func:`terminate_as_interrupt` (the command line's main process): while it is active a
  SIGTERM raises ``KeyboardInterrupt``, so ``kill PID`` stops a tournament or a scenario batch
  the way Ctrl-C does (finished tasks kept for ``--resume``, the workers stopped).
- :func:`prepare_worker` (every worker process, first thing): the first SIGTERM raises
  ``KeyboardInterrupt`` there too (later ones are ignored), so a stopped worker closes its
  match's controller and render processes on its way out; and it sends itself that SIGTERM
  when the process that started it dies, even by SIGKILL, and then ends
  (:func:`end_interrupted`): no worker plays on for a parent that is gone.
- :func:`stop_processes`: SIGTERM to each live process, SIGKILL to those still alive after
  :data:`GRACE_S`.
"""

from __future__ import annotations

import contextlib
import logging
import os
import signal
import sys
import threading
import time
from collections.abc import Iterable, Iterator
from typing import NoReturn

log = logging.getLogger(__name__)

EXIT_INTERRUPTED = 130  # as a shell reports a Ctrl-C
GRACE_S = 5.0  # s a stopped worker has to close its match before it is killed
PARENT_CHECK_S = 0.25  # s between a worker's checks that its parent lives


def _raise_interrupt(signum: int, _frame: object) -> None:
    raise KeyboardInterrupt(f"signal {signal.Signals(signum).name}")


@contextlib.contextmanager
def terminate_as_interrupt() -> Iterator[None]:
    """Within the block a SIGTERM raises ``KeyboardInterrupt`` (in the main thread only; elsewhere nothing
    changes); the previous handler is back afterwards."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGTERM, _raise_interrupt)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


def _raise_interrupt_once(signum: int, frame: object) -> None:
    signal.signal(signal.SIGTERM, signal.SIG_IGN)  # the cleanup the first one started runs to its end
    _raise_interrupt(signum, frame)


def prepare_worker(parent_pid: int) -> None:
    """In a worker process started by ``parent_pid``: the first SIGTERM raises ``KeyboardInterrupt``, and a
    watcher thread sends this process that SIGTERM once ``parent_pid`` is no longer its parent (it died and the
    worker was handed to another), within :data:`PARENT_CHECK_S`."""
    signal.signal(signal.SIGTERM, _raise_interrupt_once)
    threading.Thread(target=_watch_parent, args=(parent_pid,), name="parent watcher", daemon=True).start()


def parent_alive(parent_pid: int) -> bool:
    """Whether ``parent_pid`` is still this process's parent."""
    return os.getppid() == parent_pid


def _watch_parent(parent_pid: int) -> None:
    while parent_alive(parent_pid):
        time.sleep(PARENT_CHECK_S)
    os.kill(os.getpid(), signal.SIGTERM)


def end_interrupted() -> NoReturn:
    """End a worker whose task was interrupted (its cleanup done) at once, exit code 130: nobody waits for
    more from it, and a pool worker would otherwise wait for its next task from a parent that may be gone."""
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(Exception):
            stream.flush()
    os._exit(EXIT_INTERRUPTED)


def stop_processes(processes: Iterable, grace_s: float = GRACE_S) -> None:
    """SIGTERM to every live ``multiprocessing`` process of ``processes``, SIGKILL to any still alive
    ``grace_s`` seconds later; returns when all have ended."""
    alive = [process for process in processes if process.is_alive()]
    for process in alive:
        process.terminate()
    deadline = time.monotonic() + grace_s
    for process in alive:
        process.join(max(0.0, deadline - time.monotonic()))
    for process in alive:
        if process.is_alive():
            log.warning("worker %d did not end within %g s of a SIGTERM: killed", process.pid, grace_s)
            process.kill()
            process.join()
