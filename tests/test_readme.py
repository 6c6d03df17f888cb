"""The README: short, its links lead to pages that exist, and its commands run as written.

A command in a ```sh block is run from a scratch directory, ``.venv/bin/`` standing for this
interpreter's scripts, when it is short: a ``--help``, or a match of halves of at most
:data:`SHORT_HALF_SECONDS`. A longer one is checked to be a valid command without running it:
a make target the Makefile has (``make -n`` plans it), a ``robotstadium`` command whose
subcommand answers ``--help``.
"""

from __future__ import annotations

import json
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
README = (REPO / "README.md").read_text(encoding="utf-8")
SHELL_BLOCK = re.compile(r"^```sh\n(.*?)^```$", re.DOTALL | re.MULTILINE)
COMMANDS = [line for block in SHELL_BLOCK.findall(README) for line in block.splitlines() if line.strip()]
LINK = re.compile(r"\]\(([^)#\s]+)")
MAX_LINES = 200
SHORT_HALF_SECONDS = 5.0
SCRIPTS = Path(sys.executable).parent
TIMEOUT_S = 120


def test_the_readme_is_short_and_leads_to_the_guide() -> None:
    assert len(README.splitlines()) <= MAX_LINES
    targets = LINK.findall(README)
    assert "docs/getting-started.md" in targets and "docs/policy-tutorial.md" in targets
    for target in targets:
        assert (REPO / target).is_file(), target


def test_the_readme_has_the_quick_start() -> None:
    assert {"make install", "make match", "make test"} <= set(COMMANDS)


def _argv(command: str) -> list[str]:
    argv = shlex.split(command)
    if argv[0].startswith(".venv/bin/"):
        argv[0] = str(SCRIPTS / argv[0].removeprefix(".venv/bin/"))
    return argv


def _short(argv: list[str]) -> bool:
    if "--help" in argv:
        return True
    if "--half-seconds" in argv:
        return float(argv[argv.index("--half-seconds") + 1]) <= SHORT_HALF_SECONDS
    return False


@pytest.mark.parametrize("command", COMMANDS)
def test_a_command_runs_as_written_or_is_valid(command: str, tmp_path: Path) -> None:
    argv = _argv(command)
    if argv[0] == "make":
        (target,) = argv[1:]
        assert re.search(rf"^{re.escape(target)}:", (REPO / "Makefile").read_text(encoding="utf-8"), re.MULTILINE)
        planned = subprocess.run(["make", "-n", target], cwd=REPO, capture_output=True, text=True, timeout=TIMEOUT_S)
        assert planned.returncode == 0, planned.stderr
        return
    assert Path(argv[0]).name == "robotstadium", command
    if not _short(argv):
        argv = [argv[0], argv[1], "--help"]
    result = subprocess.run(argv, cwd=tmp_path, capture_output=True, text=True, timeout=TIMEOUT_S)
    assert result.returncode == 0, result.stderr[-2000:]
    if "--out" in argv:
        summary = json.loads((tmp_path / argv[argv.index("--out") + 1] / "summary.json").read_text(encoding="utf-8"))
        assert summary["completed"] is True
