"""Two teams on Ray RLlib: PPO learns the home team's penalty kick through RLlib's PettingZoo adapter.

The task: a 1 v 1 match (``--players`` per team) that starts with the ball on the away team's
penalty mark, the home attacker behind it and the away keeper on its goal line (the env's
``start="penalty"``), for ``--episode-steps`` steps (40 ms each). Each team has its policy:
the home team's is learned (RLlib module ``home``); the away team plays ``--opponent``, a
built-in policy (``stand`` or ``scripted``, driven in the env's process) or ``self``, a second
learned module (``away``). A learner sees its percepts (:class:`agents.learning.PerceptObservations`:
landmarks and the ball its camera shows, no pixels) and picks one of the motions of
:data:`ACTIONS` (stand, walk ahead, turn, curve, kick) with its head at a fixed target. Its
reward is the env's shaped reward (:mod:`match.rewards`): the metres the ball moved toward the
goal its team attacks, plus 1 per goal scored (minus 1 per goal let in).

Env runners are Ray actors (``--env-runners``) on a local Ray instance, or on a cluster with
``--address``. Each runner builds its envs on their own seed streams (:func:`env_creator`).
It writes into ``--out``: ``learning_curve.png`` (the training episodes' mean return per
iteration against the env steps, with the evaluations), ``results.json`` (the curve, the
evaluation of the learned and of a random policy on the same seeds with 95% intervals, the
settings) and ``checkpoint/`` (the algorithm; :class:`LearnedPolicy` plays its home module
in a match or a tournament).

    python examples/rllib_teams.py --iterations 30 --out out/rllib_teams
    python examples/rllib_teams.py --smoke --out out/rllib_smoke   # one small iteration

Needs the ``ray`` extra (RLlib) and the ``learn`` extra (the CPU build of torch):
``pip install -e '.[ray,learn]'``. ``tests/test_rllib_example.py`` runs the smoke mode.
"""

from __future__ import annotations

import argparse
import itertools
import json
import logging
import math
import os
import sys
import time
from collections.abc import Callable, Mapping
from dataclasses import asdict, dataclass, replace
from pathlib import Path

import numpy as np
from pettingzoo.utils.wrappers import BaseParallelWrapper

from agents.learning import PerceptObservations, percept_vector
from agents.vision.camera_models import DEFAULT_CAMERA_MODEL
from agents.vision.pipeline import VisionPipeline
from agents.policies import make_policy
from match import parallel_env
from match.protocol import CameraChoice, Motion
from match.rewards import BallProgress, Goals, Weighted
from match.wrappers import ActionSet, DiscreteActions

log = logging.getLogger("rllib_teams")

STILL = (0.0, 0.0, 0.0)
ACTIONS = ActionSet(
    motions=(
        (Motion.STAND, STILL),
        (Motion.WALK, (0.2, 0.0, 0.0)),  # ahead, m/s
        (Motion.WALK, (0.0, 0.0, 0.6)),  # turn left, rad/s
        (Motion.WALK, (0.0, 0.0, -0.6)),
        (Motion.WALK, (0.15, 0.0, 0.4)),  # curve left
        (Motion.WALK, (0.15, 0.0, -0.4)),
        (Motion.KICK_LEFT, STILL),
        (Motion.KICK_RIGHT, STILL),
    ),
    heads=((0.0, math.radians(29.0)),),  # straight ahead, looking down: the ball in front of the feet
    cameras=(CameraChoice.TOP,),
)
OPPONENTS = ("stand", "scripted", "self")
EVAL_SEED = 50_000  # evaluation episodes use seeds from here on
Z_95 = 1.96


@dataclass(frozen=True)
class Settings:
    """One run: ``iterations`` PPO iterations of ``batch`` env steps each (every learner's steps) from
    ``env_runners`` Ray actors; episodes of ``episode_steps`` steps; ``eval_episodes`` per policy."""

    iterations: int = 30
    batch: int = 2000
    env_runners: int = 2
    players: int = 1
    opponent: str = "stand"
    episode_steps: int = 100
    eval_episodes: int = 40
    seed: int = 0
    address: str | None = None


SMOKE = Settings(iterations=1, batch=128, env_runners=1, episode_steps=32, eval_episodes=2)


# ---- the task --------------------------------------------------------------------------------


class Opponents(BaseParallelWrapper):
    """The away team played by a built-in policy (``agents.policies``) in this process; only the home team's
    agents are the env's agents. Wraps the raw env: the policies read their robots' observation dicts."""

    def __init__(self, env, policy: str):
        super().__init__(env)
        self.policy = policy
        self._policies: dict[str, object] = {}
        self._observations: dict[str, Mapping] = {}

    def __getstate__(self) -> dict:
        return {"env": self.env, "policy": self.policy}

    def __setstate__(self, state: dict) -> None:
        self.__init__(state["env"], state["policy"])

    @property
    def possible_agents(self) -> list[str]:
        return [a for a in self.env.possible_agents if a.startswith("home")]

    @property
    def agents(self) -> list[str]:
        return [a for a in self.env.agents if a.startswith("home")]

    def reset(self, seed: int | None = None, options: dict | None = None):
        observations, infos = self.env.reset(seed=seed, options=options)
        away = [a for a in self.env.possible_agents if a not in self.possible_agents]
        self._policies = {a: make_policy(self.policy) for a in away}
        for i, (agent, policy) in enumerate(self._policies.items()):
            policy.reset(agent, (self.env.unwrapped.episode_seed + i) % 2**32)
        self._observations = {a: observations[a] for a in away}
        return self._own(observations), self._own(infos)

    def step(self, actions: dict):
        full = {a: policy.act(self._observations[a]) for a, policy in self._policies.items()}
        full.update(actions)
        observations, *rest = self.env.step(full)
        self._observations = {a: observations[a] for a in self._policies if a in observations}
        return (self._own(observations), *(self._own(part) for part in rest))

    def _own(self, values: dict) -> dict:
        return {a: v for a, v in values.items() if a.startswith("home")}


def task_env(players: int = 1, opponent: str = "stand", episode_steps: int = 100, stream: tuple[int, ...] = ()):
    """The learners' view of the task (a PettingZoo parallel env): percepts in, a choice of :data:`ACTIONS` out."""
    reward = Weighted((1.0, BallProgress()), (1.0, Goals()))
    env = parallel_env(players, players, preset="learning", start="penalty", max_cycles=episode_steps,
                       reward_fn=reward, stream=stream)
    if opponent != "self":
        env = Opponents(env, opponent)
    return DiscreteActions(PerceptObservations(env), ACTIONS, flat=True)


_made = itertools.count()  # envs this process built: a runner's sub-envs each get their own stream


def env_creator(context: Mapping) -> object:
    """RLlib's env creator: the task through RLlib's PettingZoo adapter, on the stream (runner, n-th env)."""
    from ray.rllib.env.wrappers.pettingzoo_env import ParallelPettingZooEnv

    worker = int(getattr(context, "worker_index", 0))
    return ParallelPettingZooEnv(task_env(context.get("players", 1), context.get("opponent", "stand"),
                                          context.get("episode_steps", 100), stream=(worker, next(_made))))


def module_of(agent_id: str, *args, **kwargs) -> str:
    """The RLlib module (the team's policy) an agent plays: ``home`` or ``away``."""
    return agent_id.split("_")[0]


# ---- training --------------------------------------------------------------------------------


def build_algo(settings: Settings):
    """PPO on the task, env runners as Ray actors; one module per learning team."""
    import ray
    from ray.rllib.algorithms.ppo import PPOConfig
    from ray.rllib.core.rl_module.default_model_config import DefaultModelConfig
    from ray.rllib.core.rl_module.multi_rl_module import MultiRLModuleSpec
    from ray.rllib.core.rl_module.rl_module import RLModuleSpec
    from ray.tune.registry import register_env

    if not ray.is_initialized():
        ray.init(address=settings.address, num_cpus=None if settings.address else max(2, settings.env_runners + 1),
                 include_dashboard=False, log_to_driver=False, configure_logging=False)
    register_env("robotstadium_teams", env_creator)
    modules = ("home", "away") if settings.opponent == "self" else ("home",)
    config = (
        PPOConfig()
        .environment("robotstadium_teams", env_config={"players": settings.players, "opponent": settings.opponent,
                                                       "episode_steps": settings.episode_steps},
                     disable_env_checking=True)
        .env_runners(num_env_runners=settings.env_runners, num_envs_per_env_runner=1, num_cpus_per_env_runner=1,
                     rollout_fragment_length="auto", sample_timeout_s=600.0)
        .multi_agent(policies=set(modules), policy_mapping_fn=module_of, policies_to_train=list(modules))
        .rl_module(rl_module_spec=MultiRLModuleSpec(rl_module_specs={m: RLModuleSpec() for m in modules}),
                   model_config=DefaultModelConfig(fcnet_hiddens=[64, 64], vf_share_layers=False))
        .training(train_batch_size_per_learner=settings.batch, minibatch_size=min(256, settings.batch),
                  num_epochs=8, lr=1e-3, gamma=0.97, entropy_coeff=0.01)
        .learners(num_learners=0)
        .debugging(seed=settings.seed, log_level="ERROR")
        .reporting(metrics_num_episodes_for_smoothing=20)
    )
    return config.build_algo()


def train(settings: Settings, out: Path) -> tuple[object, list[dict], float]:
    """The trained algorithm, one curve point per iteration and the wall seconds."""
    algo = build_algo(settings)
    curve = []
    start = time.perf_counter()
    for iteration in range(1, settings.iterations + 1):
        result = algo.train()
        runners = result.get("env_runners", {})
        returns = runners.get("module_episode_returns_mean", {})
        point = {"iteration": iteration,
                 "env_steps": int(result.get("num_env_steps_sampled_lifetime", 0)),
                 "episode_return_mean": _number(returns.get("home", runners.get("episode_return_mean"))),
                 "wall_seconds": time.perf_counter() - start}
        curve.append(point)
        log.info("iteration %d: %d env steps, mean return of home %.3f", iteration, point["env_steps"],
                 point["episode_return_mean"] if point["episode_return_mean"] is not None else float("nan"))
    return algo, curve, time.perf_counter() - start


def _number(value: object) -> float | None:
    try:
        number = float(value)
    except (TypeError, ValueError):
        return None
    return number if math.isfinite(number) else None


# ---- evaluation ------------------------------------------------------------------------------


def greedy(module) -> Callable[[np.ndarray], int]:
    """The module's most likely choice for a percept vector."""
    import torch

    def act(observation: np.ndarray) -> int:
        with torch.no_grad():
            out = module.forward_inference({"obs": torch.as_tensor(observation[None], dtype=torch.float32)})
        return int(torch.argmax(out["action_dist_inputs"][0]))

    return act


def evaluate(policy: Callable[[np.ndarray], int], settings: Settings) -> list[float]:
    """The home team's return in each of ``eval_episodes`` episodes (seeds from :data:`EVAL_SEED`), every home
    robot playing ``policy`` and the away team ``opponent`` (``self``: it stands)."""
    opponent = "stand" if settings.opponent == "self" else settings.opponent
    env = task_env(settings.players, opponent, settings.episode_steps)
    returns = []
    try:
        for episode in range(settings.eval_episodes):
            observations, _ = env.reset(seed=EVAL_SEED + episode)
            total = 0.0
            while env.agents:
                observations, rewards, *_ = env.step({a: policy(o) for a, o in observations.items()})
                total += float(np.mean(list(rewards.values())))
            returns.append(total)
    finally:
        env.close()
    return returns


def interval(values: list[float]) -> dict:
    """Mean and its 95% interval (normal approximation)."""
    mean = float(np.mean(values))
    half = Z_95 * float(np.std(values, ddof=1)) / math.sqrt(len(values)) if len(values) > 1 else float("inf")
    return {"mean": mean, "low": mean - half, "high": mean + half, "episodes": len(values)}


# ---- the figure and the run ------------------------------------------------------------------


def plot(path: Path, curve: list[dict], random: dict, learned: dict, settings: Settings) -> Path:
    from scenarios.common.plotting import plt, save_figure

    fig, ax = plt.subplots(figsize=(7, 4))
    points = [(p["env_steps"], p["episode_return_mean"]) for p in curve if p["episode_return_mean"] is not None]
    if points:
        ax.plot(*zip(*points), "o-", color="tab:blue", label="training episodes (mean of the last 20)")
    for name, stats, color in (("random policy", random, "tab:red"), ("learned, greedy", learned, "tab:green")):
        ax.axhline(stats["mean"], color=color, linestyle="--" if name.startswith("random") else "-",
                   label=f"{name}: {stats['mean']:.2f} [{stats['low']:.2f}, {stats['high']:.2f}]")
        ax.axhspan(stats["low"], stats["high"], color=color, alpha=0.15)
    ax.set_xlabel("env steps (40 ms each)")
    ax.set_ylabel("home team's episode return")
    ax.set_title(f"RLlib PPO, {settings.players} v {settings.players} penalty against {settings.opponent}")
    ax.legend(loc="lower right", fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return save_figure(fig, path, dpi=120)


def run(settings: Settings, out: Path) -> dict:
    """Evaluate a random policy, train, evaluate the learned one on the same seeds; write the figure, the JSON
    and the checkpoint; return the results."""
    import ray
    from scenarios.common.io import write_json

    out.mkdir(parents=True, exist_ok=True)
    choices = np.random.default_rng(settings.seed)
    random_returns = evaluate(lambda observation: int(choices.integers(len(ACTIONS.motions))), settings)
    random = interval(random_returns)
    log.info("random policy: mean return %.3f [%.3f, %.3f]", random["mean"], random["low"], random["high"])
    algo, curve, wall_s = train(settings, out)
    try:
        learned_returns = evaluate(greedy(algo.get_module("home")), settings)
        checkpoint = Path(algo.save(str((out / "checkpoint").resolve())).checkpoint.path)
    finally:
        algo.stop()
        ray.shutdown()
    learned = interval(learned_returns)
    results = {
        "task": f"{settings.players} v {settings.players} penalty start against {settings.opponent}: home's return is "
                "the ball's progress toward the goal it attacks (m) plus goals scored minus goals let in",
        "random": random,
        "learned": learned,
        "intervals_apart": learned["low"] > random["high"],
        "eval_seeds": [EVAL_SEED, EVAL_SEED + settings.eval_episodes - 1],
        "curve": curve,
        "training_wall_seconds": wall_s,
        "env_steps": curve[-1]["env_steps"] if curve else 0,
        "checkpoint": checkpoint.name,
        "settings": asdict(settings),
    }
    write_json(out / "results.json", results)
    plot(out / "learning_curve.png", curve, random, learned, settings)
    log.info("learned: %.3f [%.3f, %.3f]; random %.3f [%.3f, %.3f]; %d env steps in %.0f s", learned["mean"],
             learned["low"], learned["high"], random["mean"], random["low"], random["high"], results["env_steps"],
             wall_s)
    return results


class LearnedPolicy:
    """The home module of a checkpoint as a robot's policy (``reset``/``act``), for ``robotstadium match`` or
    ``tournament``: ``rllib_teams:LearnedPolicy`` with ``examples/`` on ``PYTHONPATH``. The checkpoint is
    the directory ``RLLIB_TEAMS_CHECKPOINT`` names (default ``out/rllib_teams/checkpoint``)."""

    def __init__(self, checkpoint: str | None = None):
        from ray.rllib.core.rl_module.rl_module import RLModule

        path = Path(checkpoint or os.environ.get("RLLIB_TEAMS_CHECKPOINT", "out/rllib_teams/checkpoint")).resolve()
        module_path = path / "learner_group" / "learner" / "rl_module" / "home"
        self._act = greedy(RLModule.from_checkpoint(str(module_path)))
        self._pipeline = VisionPipeline(DEFAULT_CAMERA_MODEL)

    def reset(self, agent_id: str, seed: int) -> None:
        pass

    def act(self, observation: Mapping) -> dict:
        return ACTIONS.action((self._act(percept_vector(self._pipeline, observation)), 0, 0))


def main(argv: list[str] | None = None) -> int:
    from scenarios.cli.arguments import int_in

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    defaults = Settings()
    parser.add_argument("--iterations", type=int_in(1, 10_000), default=defaults.iterations,
                        help=f"PPO iterations, 1-10000 (default {defaults.iterations})")
    parser.add_argument("--batch", type=int_in(32, 1_000_000), default=defaults.batch,
                        help=f"env steps per iteration, 32-1000000 (default {defaults.batch})")
    parser.add_argument("--env-runners", type=int_in(1, 256), default=defaults.env_runners,
                        help=f"env runners (Ray actors), 1-256 (default {defaults.env_runners})")
    parser.add_argument("--players", type=int_in(1, 4), default=defaults.players, help="robots per team, 1-4")
    parser.add_argument("--opponent", choices=OPPONENTS, default=defaults.opponent,
                        help="the away team: a built-in policy, or self (a second learned module)")
    parser.add_argument("--episode-steps", type=int_in(8, 100_000), default=defaults.episode_steps,
                        help=f"steps an episode, 8-100000 (default {defaults.episode_steps})")
    parser.add_argument("--eval-episodes", type=int_in(2, 10_000), default=defaults.eval_episodes,
                        help=f"evaluation episodes per policy, 2-10000 (default {defaults.eval_episodes})")
    parser.add_argument("--seed", type=int_in(0, 2**31 - 1), default=defaults.seed, help="seed, 0-2147483647")
    parser.add_argument("--address", default=None, help="a Ray cluster's address (default: a local Ray instance)")
    parser.add_argument("--smoke", action="store_true", help="one small iteration: checks that everything runs")
    parser.add_argument("--out", type=Path, default=Path("out/rllib_teams"), help="output directory")
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.INFO, format="%(asctime)s %(name)s: %(message)s")
    if args.smoke:
        settings = replace(SMOKE, opponent=args.opponent, players=args.players, seed=args.seed, address=args.address)
    else:
        settings = Settings(args.iterations, args.batch, args.env_runners, args.players, args.opponent,
                            args.episode_steps, args.eval_episodes, args.seed, args.address)
    results = run(settings, args.out)
    print(json.dumps({key: results[key] for key in ("random", "learned", "intervals_apart", "env_steps")}))
    print(args.out / "learning_curve.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
