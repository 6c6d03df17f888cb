"""The RLlib example (examples/rllib_teams.py) in its smoke mode: a local Ray instance, an env runner as a Ray
actor, one small PPO iteration through RLlib's PettingZoo adapter, both evaluations, the curve, the JSON and
a checkpoint whose home module plays a robot as a policy."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.render

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "rllib_teams.py"
SMOKE_LIMIT_S = 120


def test_the_smoke_mode_trains_evaluates_and_checkpoints(tmp_path):
    for module in ("ray.rllib", "torch"):
        pytest.importorskip(module, reason="the ray and learn extras: pip install -e '.[ray,learn]'")
    out = tmp_path / "smoke"
    done = subprocess.run([sys.executable, str(EXAMPLE), "--smoke", "--out", str(out)], cwd=ROOT,
                          capture_output=True, text=True, timeout=SMOKE_LIMIT_S)
    assert done.returncode == 0, done.stderr[-3000:]
    results = json.loads((out / "results.json").read_text())
    assert results["env_steps"] >= 128 and results["settings"]["env_runners"] == 1
    for policy in ("random", "learned"):
        assert results[policy]["low"] <= results[policy]["mean"] <= results[policy]["high"]
        assert results[policy]["episodes"] == 2
    assert (out / "learning_curve.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"

    played = subprocess.run(
        [sys.executable, "-c",
         "from rllib_teams import LearnedPolicy\n"
         "from match import parallel_env\n"
         "from match.protocol import parse_action\n"
         "policy = LearnedPolicy()\n"
         "env = parallel_env(1, 1, start='penalty')\n"
         "observations, _ = env.reset(seed=0)\n"
         "policy.reset('home_0', 0)\n"
         "for _ in range(3):\n"
         "    observations, *_ = env.step({'home_0': policy.act(observations['home_0'])})\n"
         "print(parse_action('home_0', policy.act(observations['home_0'])).motion.value)\n"],
        cwd=ROOT, capture_output=True, text=True, timeout=SMOKE_LIMIT_S,
        env={**os.environ, "PYTHONPATH": str(ROOT / "examples"), "RLLIB_TEAMS_CHECKPOINT": str(out / "checkpoint")})
    assert played.returncode == 0, played.stderr[-3000:]
    assert played.stdout.split()[-1] in {"stand", "walk", "kick_left", "kick_right"}
