"""A SIGTERM while ``robotstadium`` is still loading ends it with one line and exit 130, nothing written."""

from __future__ import annotations

import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

COMMAND = Path(sys.executable).parent / "robotstadium"


@pytest.mark.skipif(not COMMAND.exists(), reason="the robotstadium console script is not installed beside python")
@pytest.mark.parametrize("after_s", [0.25, 0.5])
def test_a_sigterm_while_starting_ends_with_one_line_and_nothing_written(tmp_path: Path, after_s: float) -> None:
    out = tmp_path / "match"
    process = subprocess.Popen([str(COMMAND), "match", "--half-seconds", "5", "--no-progress", "--out", str(out)],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    time.sleep(after_s)
    process.send_signal(signal.SIGTERM)
    _, stderr = process.communicate(timeout=60)
    assert process.returncode == 130
    lines = [line for line in stderr.splitlines() if not line.startswith("pybullet build time")]
    assert lines == ["robotstadium: stopped before the command began; nothing was written"]
    assert not out.exists()
