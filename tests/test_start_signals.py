"""A SIGTERM at any point of ``robotstadium match`` ends it with exit 130 and one line that names only what exists.

While loading: "stopped before the command began; nothing was written"; before the match began: nothing was
written either; during the match: the directory named holds a valid summary.json (completed false). Before the
interpreter runs the entry point's first lines (Python's own start) a SIGTERM still has its default action, so
a signal is sent no earlier than the entry point's handler is in place.
"""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

COMMAND = Path(sys.executable).parent / "robotstadium"
HANDLER_WAIT_S = 10.0


def _handles_sigterm(pid: int) -> bool:
    """Whether the process has a handler of its own for SIGTERM (Linux: its caught signals in /proc)."""
    try:
        with open(f"/proc/{pid}/status", encoding="ascii") as status:
            for line in status:
                if line.startswith("SigCgt:"):
                    return bool(int(line.split()[1], 16) >> (signal.SIGTERM - 1) & 1)
    except OSError:
        pass
    return False


@pytest.mark.skipif(not COMMAND.exists(), reason="the robotstadium console script is not installed beside python")
@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="a process's signal handlers are read from /proc")
@pytest.mark.parametrize("after_s", [0.1, 0.3, 1.0, 3.0])
def test_a_sigterm_ends_robotstadium_with_130_and_names_only_what_exists(tmp_path: Path, after_s: float) -> None:
    out = tmp_path / "match"
    started = time.monotonic()
    process = subprocess.Popen([str(COMMAND), "match", "--half-seconds", "5", "--home-players", "1",
                                "--away-players", "1", "--no-progress", "--out", str(out)],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    while not _handles_sigterm(process.pid) and time.monotonic() < started + HANDLER_WAIT_S:
        time.sleep(0.002)
    time.sleep(max(0.0, started + after_s - time.monotonic()))
    process.send_signal(signal.SIGTERM)
    _, stderr = process.communicate(timeout=60)
    assert process.returncode == 130, stderr
    lines = [line for line in stderr.splitlines() if line.startswith("robotstadium")]
    assert len(lines) == 1 and "Traceback" not in stderr, stderr
    if str(out) in lines[0]:  # during the match (completed false) or after it
        summary = json.loads((out / "summary.json").read_text(encoding="utf-8"))
        assert summary["completed"] is ("after the match" in lines[0]), lines[0]
    else:
        assert lines[0].endswith("nothing was written") and not out.exists(), stderr


SWALLOWED_SIGTERM = """
import os, signal, sys
from scenarios import launch
signal.signal(signal.SIGTERM, launch._interrupt)
class Finalised:
    def __del__(self):  # a SIGTERM handled here raises where Python only prints the exception
        os.kill(os.getpid(), signal.SIGTERM)
        sum(range(1000))
item = Finalised()
del item
sys.argv = ["robotstadium", "match", "--half-seconds", "5", "--out", sys.argv[1]]
sys.exit(launch.main())
"""


def test_a_sigterm_whose_interrupt_python_ignored_while_loading_still_stops_the_command(tmp_path: Path) -> None:
    out = tmp_path / "match"
    process = subprocess.run([sys.executable, "-c", SWALLOWED_SIGTERM, str(out)], capture_output=True, text=True,
                             timeout=120)
    assert "Exception ignored" in process.stderr  # the interrupt fell where Python ignores exceptions
    assert process.returncode == 130, process.stderr
    assert process.stderr.rstrip().endswith("stopped before the command began; nothing was written")
    assert not out.exists()
