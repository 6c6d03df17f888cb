"""The ``robotstadium`` command's entry point: stoppable from its first instant.

Loading the command line (the simulator, numpy, OpenCV, numba) takes about a second; a SIGTERM in
that time would otherwise end the process by the default action, with no word. Here a SIGTERM
is a Ctrl-C (``KeyboardInterrupt``) before anything is imported, and one that arrives before a
command began ends with one line and exit 130: nothing was written yet. That exit skips the
interpreter's clean-up (``os._exit``): a signal in the middle of importing a native library leaves
it half initialised, and finalising it can abort the process (a double free) instead of exiting
130. A SIGTERM handled while Python runs a finaliser or a callback of its import machinery raises
where Python only prints the exception and goes on: the handler also records it, and a command
whose loading saw one does not begin. Once a command runs, :func:`scenarios.cli.main` handles both
itself.
"""

from __future__ import annotations

import os
import signal
import sys

EXIT_INTERRUPTED = 130  # as scenarios.common.termination: the shell's code for a Ctrl-C


_received: list[int] = []  # the signals received while the command line loaded


def _interrupt(signum: int, _frame: object) -> None:
    _received.append(signum)
    raise KeyboardInterrupt(f"signal {signal.Signals(signum).name}")


def _load_command_line():
    """The command line's entry point, imported; ``KeyboardInterrupt`` when a SIGTERM arrived meanwhile, even
    one whose exception fell in a callback of the import machinery or a finaliser (where Python prints an
    exception and goes on)."""
    from scenarios.cli import main as run_command_line

    if _received:
        raise KeyboardInterrupt(f"signal {signal.Signals(_received[0]).name}")
    return run_command_line


def main() -> int:
    """Run ``robotstadium`` with the process's arguments; return its exit code (or end the process with
    exit 130 when stopped before the command began)."""
    signal.signal(signal.SIGTERM, _interrupt)
    try:
        return _load_command_line()()
    except KeyboardInterrupt:
        print("robotstadium: stopped before the command began; nothing was written", file=sys.stderr)
        sys.stderr.flush()
        os._exit(EXIT_INTERRUPTED)  # no finalisers of half-imported native libraries
