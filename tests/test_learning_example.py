"""The learning example (examples/look_at_ball.py) runs end to end for a hundred-odd steps: PPO through
SuperSuit's vector env, both policies evaluated, the curve and the numbers written; and its task rewards
looking at the ball."""

from __future__ import annotations

import importlib.util
import json
import math
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.render

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "look_at_ball.py"


def _example():
    for module in ("stable_baselines3", "torch", "supersuit"):
        pytest.importorskip(module, reason="the learn extra is not installed: pip install -e '.[learn]'")
    spec = importlib.util.spec_from_file_location("look_at_ball", EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclasses look their module up
    spec.loader.exec_module(module)
    return module


def test_the_example_trains_evaluates_and_writes_its_curve(tmp_path):
    example = _example()
    out = tmp_path / "run"
    code = example.main(["--timesteps", "128", "--envs", "2", "--workers", "1", "--episode-steps", "16",
                         "--eval-episodes", "1", "--out", str(out)])
    assert code == 0
    results = json.loads((out / "results.json").read_text())
    for key in ("random_mean_return", "learned_mean_return"):
        assert -16.0 <= results[key] <= 16.0 and math.isfinite(results[key])
    assert results["settings"]["timesteps"] == 128 and results["training_episodes"] >= 2
    assert (out / "learning_curve.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_the_task_rewards_looking_at_the_ball():
    example = _example()
    env = example.task_env(episode_steps=80)
    try:
        env.reset(seed=3)
        look = env
        while not isinstance(look, example.LookAtBall):  # the task wrapper, under the learner's views
            look = look.env
        world = look.unwrapped.match.world
        pose, ball = world.robot_pose(example.LEARNER), world.ball()
        bearing = math.remainder(math.atan2(ball.y - pose.y, ball.x - pose.x) - pose.theta, math.tau)
        best = min(range(len(example.HEAD_YAWS_RAD)), key=lambda i: abs(example.HEAD_YAWS_RAD[i] - bearing))
        worst = max(range(len(example.HEAD_YAWS_RAD)), key=lambda i: abs(example.HEAD_YAWS_RAD[i] - bearing))
        rewards = {}
        for choice in (worst, best):
            for _ in range(25):  # the head turns about 240 degrees a second
                _, reward, *_ = env.step({example.LEARNER: choice})
            rewards[choice] = reward[example.LEARNER]
        assert rewards[best] > 0.9 and rewards[worst] < rewards[best] - 0.3
        observations, *_ = env.step({example.LEARNER: best})
        assert observations[example.LEARNER][2] == 1.0  # the ball is seen (head yaw, pitch, ball seen, ...)
        with pytest.raises(Exception, match="'action'"):
            env.step({example.LEARNER: len(example.HEAD_YAWS_RAD)})
    finally:
        env.close()
