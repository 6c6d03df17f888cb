"""Whole matches with hostile policies in controller processes: each costs only its own robot.

The attackers stand as the clean line-up's robot does (or stand for a fault), so the world plays the
same match: what the other team saw is compared frame by frame with the clean match (the victims
report a checksum of every frame as their pose estimate), and the match completes in about the clean
match's time. Processes a policy starts are ended with its match (tests/test_controllers.py).
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np
import pytest

from match.controllers import ControllerLimits
from scenarios.matches.play import Lineup, run_lineup_match

pytestmark = pytest.mark.render

STEPS = 120
QUICK = {"initial_seconds": 0.2, "ready_seconds": 0.4, "set_seconds": 0.2}
VICTIM = "tests.user_policies:ImageProbe"  # stands, camera on; reports a checksum of each frame
LIMITS = ControllerLimits(step_budget_s=0.25, hang_s=0.5, memory_mb=400.0, group="robot")
ATTACKERS = {
    "reads and zeroes image memory": "tests.user_policies:SnoopsImages",
    "raises KeyboardInterrupt": "tests.user_policies:InterruptsItself",
    "forges actions": "tests.user_policies:Forges",
    "exits the process": "tests.user_policies:ExitsOften",
    "hangs": "tests.user_policies:Sleeps",
    "hoards memory": "tests.user_policies:Hoards",
}


def _play(out: Path, attacker: str) -> tuple[dict, float]:
    started = time.perf_counter()
    run_lineup_match(out, Lineup(VICTIM, VICTIM, {"home_0": attacker}), home=2, away=2, half_seconds=60.0, seed=9,
                     progress=False, max_steps=STEPS, referee=QUICK, shootout=False, controllers=LIMITS)
    return json.loads((out / "summary.json").read_text(encoding="utf-8")), time.perf_counter() - started


def _victims_frames(out: Path) -> np.ndarray:
    """The away robots' frame checksums, step by step."""
    with np.load(out / "match_log.npz") as log:
        agents = list(log["agents"])
        return log["estimates"][:, [agents.index("away_0"), agents.index("away_1")], :]


@pytest.fixture(scope="module")
def clean(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, float]:
    out = tmp_path_factory.mktemp("clean")
    summary, wall = _play(out, VICTIM)
    assert summary["completed"] and summary["faults"]["total"] == 0
    return out, wall


@pytest.mark.parametrize("attacker", list(ATTACKERS.values()), ids=list(ATTACKERS))
def test_a_hostile_policy_costs_only_its_own_robot(tmp_path: Path, clean: tuple[Path, float], attacker: str) -> None:
    clean_out, clean_wall = clean
    summary, wall = _play(tmp_path, attacker)
    assert summary["completed"] and summary["steps"] == STEPS
    assert set(summary["faults"]["by_agent"]) <= {"home_0"}
    frames = _victims_frames(tmp_path)
    assert np.isfinite(frames).all()  # the victims saw a frame and reported its checksum at every step
    assert np.array_equal(frames, _victims_frames(clean_out))  # what the other team saw is untouched
    assert wall < 1.5 * clean_wall + 10.0, (wall, clean_wall)
