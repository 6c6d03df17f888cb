"""Whole matches with hostile policies in controller processes: each costs only its own robot.

The attackers stand as the clean line-up's robot does (or stand for a fault), so the world plays the
same match: what the other team saw is compared frame by frame with the clean match (the victims
report a checksum of every frame as their pose estimate), the match completes in about the clean
match's time, and no process of a policy outlives it (none below this process, which plays the
simulator, outside its own session; none of those LeavesChildren starts anywhere). The attackers read
and write the other team's image memory, raise KeyboardInterrupt, forge Actions, end or kill their
process, hang in Python and in C, hoard memory, leave processes behind, return 200 MiB packets, and
write to the simulator through their pipe: 200 MiB, code to run, part of a message.
"""

from __future__ import annotations

import json
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pytest

from match.controllers import ControllerLimits
from scenarios.matches.play import Lineup, run_lineup_match
from tests.user_policies import CODE_RAN, left_behind
from world.process_memory import stat_fields

pytestmark = [pytest.mark.render,
              pytest.mark.skipif(not sys.platform.startswith("linux"), reason="processes are found in /proc")]

STEPS = 120
QUICK = {"initial_seconds": 0.2, "ready_seconds": 0.4, "set_seconds": 0.2}
VICTIM = "tests.user_policies:ImageProbe"  # stands, camera on; reports a checksum of each frame
RAN = os.path.join(tempfile.gettempdir(), CODE_RAN)
LIMITS = ControllerLimits(step_budget_s=0.25, hang_s=0.5, memory_mb=400.0, group="robot")
ATTACKERS = {  # what it does: (its policy, a fault it must be recorded for; "" for none)
    "reads and zeroes image memory": ("SnoopsImages", ""),
    "raises KeyboardInterrupt": ("InterruptsItself", "KeyboardInterrupt"),
    "forges actions": ("Forges", "InvalidActionError"),
    "exits the process": ("ExitsOften", "ControllerDied"),
    "hangs": ("Sleeps", "ControllerTimeout"),
    "hoards memory": ("Hoards", "ControllerMemory"),
    "kills its process": ("KillsItself", "ControllerDied"),
    "hangs in C": ("SpinsInC", "ControllerHung"),
    "leaves processes behind": ("LeavesChildren", ""),
    "returns 200 MiB packets": ("SendsHugePackets", "RadioPacketError"),
    "sends 200 MiB through its pipe": ("FloodsItsPipe", "ControllerRefused: an answer of 209715200 bytes"),
    "sends code through its pipe": ("SendsCode", "ControllerRefused: an answer that names posix.mkdir"),
    "sends part of a message": ("SendsPartOfAnAnswer", "ControllerHung"),
}


def _play(out: Path, attacker: str) -> tuple[dict, float]:
    started = time.perf_counter()
    run_lineup_match(out, Lineup(VICTIM, VICTIM, {"home_0": attacker}), home=2, away=2, half_seconds=60.0, seed=9,
                     progress=False, max_steps=STEPS, referee=QUICK, shootout=False, controllers=LIMITS)
    return json.loads((out / "summary.json").read_text(encoding="utf-8")), time.perf_counter() - started


def _policy_processes() -> list[int]:
    """Processes of a policy still running: below this process (the simulator) but outside its session
    (each controller leads one), or started by LeavesChildren wherever they went. Zombies have ended."""
    parents: dict[int, int] = {}
    for entry in filter(str.isdigit, os.listdir("/proc")):
        fields = stat_fields(int(entry))
        if fields is not None and len(fields) > 1 and fields[0] != b"Z":  # Z: ended, not yet waited for
            parents[int(entry)] = int(fields[1])
    below, frontier = set(), {os.getpid()}
    while frontier:
        frontier = {pid for pid, parent in parents.items() if parent in frontier} - below
        below |= frontier
    left = set(left_behind())
    for pid in below:
        try:
            if os.getsid(pid) != os.getsid(0):
                left.add(pid)
        except OSError:  # ended meanwhile
            continue
    return sorted(left)


def _command(pid: int) -> str:
    try:
        with open(f"/proc/{pid}/cmdline", "rb") as cmdline:
            return f"{pid}: " + cmdline.read().replace(b"\0", b" ").decode(errors="replace")[:200]
    except OSError:
        return f"{pid}: ended"


def _victims_frames(out: Path) -> np.ndarray:
    """The away robots' frame checksums, step by step."""
    with np.load(out / "match_log.npz") as log:
        agents = list(log["agents"])
        return log["estimates"][:, [agents.index("away_0"), agents.index("away_1")], :]


@pytest.fixture(scope="module")
def clean(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, float]:
    out = tmp_path_factory.mktemp("clean")
    if os.path.isdir(RAN):
        os.rmdir(RAN)
    summary, wall = _play(out, VICTIM)
    assert summary["completed"] and summary["faults"]["total"] == 0
    return out, wall


@pytest.mark.parametrize(("attacker", "fault"), list(ATTACKERS.values()), ids=list(ATTACKERS))
def test_a_hostile_policy_costs_only_its_own_robot(tmp_path: Path, clean: tuple[Path, float], attacker: str,
                                                  fault: str) -> None:
    clean_out, clean_wall = clean
    summary, wall = _play(tmp_path, f"tests.user_policies:{attacker}")
    assert summary["completed"] and summary["steps"] == STEPS
    assert set(summary["faults"]["by_agent"]) <= {"home_0"}
    assert not fault or any(fault in d["error"] for d in summary["faults"]["details"]), summary["faults"]
    frames = _victims_frames(tmp_path)
    assert np.isfinite(frames).all()  # the victims saw a frame and reported its checksum at every step
    assert np.array_equal(frames, _victims_frames(clean_out))  # what the other team saw is untouched
    assert wall < 1.5 * clean_wall + 10.0, (wall, clean_wall)
    left = _policy_processes()
    assert left == [], [_command(pid) for pid in left]
    assert not os.path.exists(RAN)  # nothing a controller sent ran in the simulator
