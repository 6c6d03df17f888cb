"""Train a small policy to look at the ball: PPO (Stable-Baselines3) through SuperSuit's vector env.

The task: one robot (``home_0``) stands on the field with the ball to its left (a seeded random
spot 1.0-2.8 m away, 30-100 degrees left of its heading: out of view while it looks ahead) and
must turn its head to find it and keep looking at it; the other robot (``away_0``) stands with
its camera off. The side is fixed: a policy without memory cannot search both sides (it would
turn back and forth). The learner sees the head and ball entries of its percepts
(:class:`agents.learning.PerceptObservations`: its head angles, and the ball's bearing and
distance when its camera shows it) and picks one of 7 head yaws, -90 to 90 degrees in steps of
30, at 15 degrees pitch, top camera (:class:`match.wrappers.DiscreteActions`). Each 40 ms step
it is rewarded with the cosine of the angle between its camera's optical axis and the direction
to the ball (1 when the ball is in the middle of its image), from the ground truth; an episode
is 60 steps (2.4 s), so a return is at most 60.

It writes into ``--out``: ``learning_curve.png`` (the training episodes' returns against the
timesteps, with the random policy's and the trained policy's mean returns) and ``results.json``
(both means over the same evaluation seeds, the curve, the settings, the wall time).

    python examples/look_at_ball.py --timesteps 40000 --out out/look_at_ball

Needs the ``learn`` extra (Stable-Baselines3, the CPU build of torch, SuperSuit):
``pip install -e '.[learn]'``. ``tests/test_learning_example.py`` runs it for 128 steps.
"""

from __future__ import annotations

import argparse
import json
import logging
import math
import sys
import time
import warnings
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
from gymnasium import spaces
from pettingzoo.utils.wrappers import BaseParallelWrapper

from agents.learning import PERCEPT_LABELS, PerceptObservations
from match import parallel_env
from match.free_play import FreePlay
from match.game import MatchConfig
from match.protocol import CameraChoice, Motion, make_action
from match.wrappers import ActionSet, DiscreteActions
from scenarios.cli.arguments import int_in
from scenarios.common.io import write_json
from scenarios.common.plotting import plt, save_figure
from world.field import Pose2D

log = logging.getLogger("look_at_ball")

LEARNER = "home_0"
STANDER = "away_0"
STARTS = ((LEARNER, Pose2D(-1.0, 0.0, 0.0)), (STANDER, Pose2D(1.5, 1.2, math.pi)))
HEAD_PITCH_RAD = math.radians(15.0)
HEAD_YAWS_RAD = tuple(math.radians(yaw) for yaw in range(-90, 91, 30))  # 7 targets; the image spans 46 degrees
BALL_DISTANCE_M = (1.0, 2.8)
BALL_BEARING_RAD = (math.radians(30.0), math.radians(100.0))  # to the left (CCW): out of view straight ahead
BALL_AREA_M = (3.4, 2.4)  # the ball is placed within |x|, |y| below these (the carpet)
STAND_STILL = make_action(Motion.STAND, camera=CameraChoice.OFF)
PLACEMENT_SALT = 0x4C4F4F4B  # mixed with the episode's match seed: the placement's own stream
EVAL_SEED = 10_000  # evaluation episodes use seeds from here on, never seen in training
CURVE_WINDOW = 20  # training episodes per point of the smoothed curve
LOG_EVERY = 4096  # timesteps between two progress lines


@dataclass(frozen=True)
class Settings:
    """What one run does: ``timesteps`` learner steps over ``envs`` envs in ``workers`` processes,
    ``episode_steps`` steps an episode, ``eval_episodes`` evaluation episodes per policy."""

    timesteps: int = 40_000
    envs: int = 4
    workers: int = 2
    episode_steps: int = 60
    eval_episodes: int = 30
    seed: int = 0


# ---- the task ------------------------------------------------------------------------------


class LookAtBall(BaseParallelWrapper):
    """Places the learner and the ball at every reset and rewards the learner for looking at the ball.

    Wraps the raw env (it reads the ground truth of ``env.unwrapped.match.world``). The learner's
    reward each step is ``cos`` of the angle between its camera's optical axis and the direction
    from the camera to the ball's centre, in [-1, 1]; the other robots get 0. The placement is
    drawn from the episode's match seed (``env.unwrapped.episode_seed``), which differs between
    the sub-envs of a vector env even where they are handed the same seed.
    """

    def reset(self, seed: int | None = None, options: dict | None = None):
        self.env.reset(seed=seed, options=options)
        rng = np.random.default_rng([self.env.unwrapped.episode_seed, PLACEMENT_SALT])
        world = self.env.unwrapped.match.world
        while True:  # until the ball lies on the carpet
            x, y, theta = rng.uniform(-2.0, 2.0), rng.uniform(-1.2, 1.2), rng.uniform(-math.pi, math.pi)
            distance = rng.uniform(*BALL_DISTANCE_M)
            bearing = theta + rng.uniform(*BALL_BEARING_RAD)
            ball_x, ball_y = x + distance * math.cos(bearing), y + distance * math.sin(bearing)
            if abs(ball_x) < BALL_AREA_M[0] and abs(ball_y) < BALL_AREA_M[1]:
                break
        world.place_robot(LEARNER, Pose2D(x, y, theta))
        world.place_ball(ball_x, ball_y)
        settle = {agent: STAND_STILL for agent in self.env.agents}
        settle[LEARNER] = make_action(head=(0.0, HEAD_PITCH_RAD), camera=CameraChoice.TOP)
        observations, _, _, _, infos = self.env.step(settle)  # the first observation after placing
        return observations, infos

    def step(self, actions: dict):
        observations, rewards, terminations, truncations, infos = self.env.step(actions)
        if LEARNER in rewards:
            rewards = {**rewards, LEARNER: self.look()}
        return observations, rewards, terminations, truncations, infos

    def look(self) -> float:
        """The cosine of the angle between the learner's optical axis and the direction to the ball."""
        world = self.env.unwrapped.match.world
        rotation, position = world.camera_pose(LEARNER)
        ball = world.ball()
        direction = np.array([ball.x, ball.y, ball.z]) - position
        return float(rotation[:, 2] @ direction / np.linalg.norm(direction))


SEEN = tuple(PERCEPT_LABELS.index(label) for label in
             ("head_yaw", "head_pitch", "ball/seen", "ball/bearing", "ball/distance"))


class HeadAndBall(BaseParallelWrapper):
    """Keeps the head and ball entries of the percept vector (:data:`SEEN`), the ones the task needs."""

    def __init__(self, env):
        super().__init__(env)
        full = env.observation_space(env.possible_agents[0])
        self._space = spaces.Box(full.low[list(SEEN)], full.high[list(SEEN)], dtype=np.float32)

    def observation_space(self, agent: str) -> spaces.Box:
        return self._space

    def reset(self, seed: int | None = None, options: dict | None = None):
        observations, infos = self.env.reset(seed=seed, options=options)
        return {a: o[list(SEEN)] for a, o in observations.items()}, infos

    def step(self, actions: dict):
        observations, *rest = self.env.step(actions)
        return ({a: o[list(SEEN)] for a, o in observations.items()}, *rest)


class OnlyLearner(BaseParallelWrapper):
    """Shows the learner alone; every other robot stands with its camera off."""

    @property
    def possible_agents(self) -> list[str]:
        return [LEARNER]

    @property
    def agents(self) -> list[str]:
        return [LEARNER] if LEARNER in self.env.agents else []

    def reset(self, seed: int | None = None, options: dict | None = None):
        observations, infos = self.env.reset(seed=seed, options=options)
        return {LEARNER: observations[LEARNER]}, {LEARNER: infos[LEARNER]}

    def step(self, actions: dict):
        full = {agent: STAND_STILL for agent in self.env.agents}
        full.update(actions)
        results = self.env.step(full)
        return tuple({LEARNER: part[LEARNER]} for part in results)


def task_env(episode_steps: int):
    """The learner's view of the task: head and ball percepts in, one of 7 head yaws out (a PettingZoo
    parallel env)."""
    env = parallel_env(config=MatchConfig(free_play=FreePlay(STARTS, settle_steps=2)), max_cycles=episode_steps + 1)
    heads = tuple((yaw, HEAD_PITCH_RAD) for yaw in HEAD_YAWS_RAD)
    looks = ActionSet(motions=((Motion.STAND, (0.0, 0.0, 0.0)),), heads=heads, cameras=(CameraChoice.TOP,))
    return DiscreteActions(HeadAndBall(PerceptObservations(OnlyLearner(LookAtBall(env)))), looks, flat=True)


# ---- evaluation, training, figure ------------------------------------------------------------


def evaluate(policy, episodes: int, episode_steps: int) -> list[float]:
    """The return of each of ``episodes`` episodes (seeds from :data:`EVAL_SEED`) of ``policy(observation,
    env) -> action``, in this process."""
    env = task_env(episode_steps)
    returns = []
    try:
        for episode in range(episodes):
            observations, _ = env.reset(seed=EVAL_SEED + episode)
            total = 0.0
            while env.agents:
                action = policy(observations[LEARNER], env)
                observations, rewards, *_ = env.step({LEARNER: action})
                total += rewards.get(LEARNER, 0.0)
            returns.append(total)
    finally:
        env.close()
    return returns


def train(settings: Settings) -> tuple[object, list[tuple[int, float]], float]:
    """PPO on ``settings.envs`` copies of the task in ``settings.workers`` processes: the model, the
    training episodes' (timesteps, return) and the wall seconds."""
    import supersuit
    import torch
    from stable_baselines3 import PPO
    from stable_baselines3.common.callbacks import BaseCallback
    from stable_baselines3.common.logger import Logger
    from stable_baselines3.common.utils import set_random_seed
    from stable_baselines3.common.vec_env import VecMonitor
    from supersuit.vector.sb3_vector_wrapper import SB3VecEnvWrapper

    torch.set_num_threads(1)  # the envs' processes have the cores

    class Episodes(BaseCallback):
        """Keeps every training episode's (timesteps, return); logs their mean every ``LOG_EVERY`` timesteps."""

        def __init__(self) -> None:
            super().__init__()
            self.returns: list[tuple[int, float]] = []
            self.logged = 0

        def _on_step(self) -> bool:
            for info in self.locals["infos"]:
                if "episode" in info:
                    self.returns.append((self.num_timesteps, float(info["episode"]["r"])))
            if self.num_timesteps - self.logged >= LOG_EVERY and self.returns:
                self.logged = self.num_timesteps
                recent = [r for _, r in self.returns[-CURVE_WINDOW:]]
                log.info("%d timesteps: mean return %.2f over the last %d episodes", self.num_timesteps,
                         np.mean(recent), len(recent))
            return True

    vector = supersuit.pettingzoo_env_to_vec_env_v1(task_env(settings.episode_steps))
    vector = supersuit.concat_vec_envs_v1(vector, settings.envs, num_cpus=settings.workers, base_class="gymnasium")
    # Seeded here: SB3's own seeding asks SuperSuit's vector env for a seed() it lacks. PPO's first reset()
    # then draws every env's next seed from the sequence of this one.
    vector.reset(seed=settings.seed)
    with warnings.catch_warnings():  # SuperSuit's vector env has a render_mode SB3 does not find
        warnings.filterwarnings("ignore", message="The `render_mode` attribute is not defined")
        vector = VecMonitor(SB3VecEnvWrapper(vector))
    set_random_seed(settings.seed)
    n_steps = max(32, min(64, settings.timesteps // settings.envs))
    model = PPO("MlpPolicy", vector, n_steps=n_steps, batch_size=min(64, n_steps * settings.envs), n_epochs=10,
                learning_rate=1e-3, gamma=0.9, ent_coef=0.01, policy_kwargs={"net_arch": [64, 64]},
                device="cpu", verbose=0)
    model.set_logger(Logger(folder=None, output_formats=[]))  # SB3's default makes an empty run folder in the temp dir
    episodes = Episodes()
    start = time.perf_counter()
    try:
        model.learn(total_timesteps=settings.timesteps, callback=episodes)
    finally:
        vector.close()
    return model, episodes.returns, time.perf_counter() - start


def curve(returns: list[tuple[int, float]], window: int = CURVE_WINDOW) -> list[tuple[int, float]]:
    """(timesteps, mean return) of each run of ``window`` consecutive training episodes."""
    points = []
    for start in range(0, len(returns) - window + 1, window):
        chunk = returns[start:start + window]
        points.append((chunk[-1][0], float(np.mean([r for _, r in chunk]))))
    return points


def plot(path: Path, returns: list[tuple[int, float]], random_mean: float, learned_mean: float,
         episode_steps: int) -> Path:
    fig, ax = plt.subplots(figsize=(7, 4))
    if returns:
        steps, values = zip(*returns)
        ax.plot(steps, values, ".", color="0.75", markersize=3, label="training episode")
    points = curve(returns)
    if points:
        ax.plot(*zip(*points), "-", color="tab:blue", linewidth=2, label=f"mean of {CURVE_WINDOW} episodes")
    ax.axhline(random_mean, color="tab:red", linestyle="--", label=f"random policy ({random_mean:.1f})")
    ax.axhline(learned_mean, color="tab:green", label=f"trained policy, deterministic ({learned_mean:.1f})")
    ax.set_xlabel("timesteps (learner steps, 40 ms each)")
    ax.set_ylabel(f"episode return (max {episode_steps})")
    ax.set_title("PPO learning to look at the ball (home_0, percepts, 7 head yaws)")
    ax.legend(loc="lower right", fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return save_figure(fig, path, dpi=120)


def run(settings: Settings, out: Path) -> dict:
    """Train, evaluate both policies on the same seeds, write the figure and the JSON; return the results."""
    out.mkdir(parents=True, exist_ok=True)
    random_policy = spaces.Discrete(len(HEAD_YAWS_RAD), seed=settings.seed)
    random_returns = evaluate(lambda obs, env: random_policy.sample(), settings.eval_episodes, settings.episode_steps)
    log.info("random policy: mean return %.2f over %d episodes", np.mean(random_returns), len(random_returns))
    model, training, wall_s = train(settings)
    learned_returns = evaluate(lambda obs, env: int(model.predict(obs, deterministic=True)[0]),
                               settings.eval_episodes, settings.episode_steps)
    results = {
        "task": "look at the ball: home_0 picks one of 7 head yaws; reward cos(optical axis, ball direction)",
        "random_mean_return": float(np.mean(random_returns)),
        "random_std_return": float(np.std(random_returns)),
        "learned_mean_return": float(np.mean(learned_returns)),
        "learned_std_return": float(np.std(learned_returns)),
        "max_return": settings.episode_steps,
        "eval_episodes": settings.eval_episodes,
        "eval_seeds": [EVAL_SEED, EVAL_SEED + settings.eval_episodes - 1],
        "training_episodes": len(training),
        "training_wall_seconds": wall_s,
        "training_steps_per_second": settings.timesteps / wall_s,
        "curve": [{"timesteps": t, "mean_return": r} for t, r in curve(training)],
        "settings": asdict(settings),
    }
    write_json(out / "results.json", results)
    plot(out / "learning_curve.png", training, results["random_mean_return"], results["learned_mean_return"],
         settings.episode_steps)
    log.info("trained policy: mean return %.2f (random %.2f); %d timesteps in %.0f s",
             results["learned_mean_return"], results["random_mean_return"], settings.timesteps, wall_s)
    return results


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    defaults = Settings()
    parser.add_argument("--timesteps", type=int_in(64, 10_000_000), default=defaults.timesteps,
                        help=f"learner steps to train, 64-10000000 (default {defaults.timesteps})")
    parser.add_argument("--envs", type=int_in(1, 64), default=defaults.envs, help="envs in the vector env, 1-64")
    parser.add_argument("--workers", type=int_in(1, 64), default=defaults.workers,
                        help="their processes, 1-64 (1: in this process)")
    parser.add_argument("--episode-steps", type=int_in(5, 10_000), default=defaults.episode_steps,
                        help="steps an episode, 5-10000")
    parser.add_argument("--eval-episodes", type=int_in(1, 10_000), default=defaults.eval_episodes,
                        help="evaluation episodes per policy, 1-10000")
    parser.add_argument("--seed", type=int_in(0, 2**32 - 1), default=defaults.seed, help="seed, 0-4294967295")
    parser.add_argument("--out", type=Path, default=Path("out/look_at_ball"), help="output directory")
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.INFO, format="%(asctime)s %(name)s: %(message)s")
    settings = Settings(args.timesteps, args.envs, args.workers, args.episode_steps, args.eval_episodes, args.seed)
    results = run(settings, args.out)
    print(json.dumps({k: results[k] for k in ("random_mean_return", "learned_mean_return", "training_wall_seconds")}))
    print(args.out / "learning_curve.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
