"""A self-localization task: each agent acts and reports where it thinks it stands, and is rewarded by its error.

:class:`PoseEstimates` wraps the env (or one of :mod:`match.wrappers`' views): an agent's action
becomes ``{"action": <the wrapped env's action>, "pose": (x m, y m, theta rad)}``, its estimate
of its torso pose in the field frame at the observation it acts on. Its reward is the wrapped
env's plus ``-(position_weight * distance error m + heading_weight * |heading error| rad)``
against the truth (:meth:`match.env.RobotStadiumEnv.truth`), which stays out of observations.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np
from gymnasium import spaces
from pettingzoo.utils.wrappers import BaseParallelWrapper

from match.errors import InvalidActionError, MatchConfigError, shown
from match.truth import MatchTruth

POSE_LOW = (-5.0, -4.0, -math.pi)  # x m, y m, theta rad: the hall
POSE_HIGH = (5.0, 4.0, math.pi)


class PoseEstimates(BaseParallelWrapper):
    """Each agent's action carries its pose estimate; its reward adds minus the estimate's error
    (see the module docstring). ``position_weight`` per metre, ``heading_weight`` per radian."""

    def __init__(self, env, position_weight: float = 1.0, heading_weight: float = 0.5):
        for name, value in (("position_weight", position_weight), ("heading_weight", heading_weight)):
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value < 0:
                raise MatchConfigError(f"{name} = {shown(value)} is invalid; expected a finite number >= 0")
        super().__init__(env)
        self.position_weight = float(position_weight)
        self.heading_weight = float(heading_weight)
        self._truth: MatchTruth | None = None
        self._spaces: dict[str, spaces.Dict] = {}

    def __getstate__(self) -> dict:
        return {"env": self.env, "weights": (self.position_weight, self.heading_weight)}

    def __setstate__(self, state: dict) -> None:
        self.__init__(state["env"], *state["weights"])

    def action_space(self, agent: str) -> spaces.Dict:
        if agent not in self._spaces:
            pose = spaces.Box(np.array(POSE_LOW, np.float32), np.array(POSE_HIGH, np.float32), dtype=np.float32)
            self._spaces[agent] = spaces.Dict({"action": self.env.action_space(agent), "pose": pose})
        return self._spaces[agent]

    def reset(self, seed: int | None = None, options: dict | None = None):
        result = self.env.reset(seed=seed, options=options)
        self._truth = self.env.unwrapped.truth()
        return result

    def step(self, actions: dict):
        if not isinstance(actions, Mapping):
            return self.env.step(actions)  # the env refuses what is not a dict
        inner, estimates = {}, {}
        for agent, action in actions.items():
            if not isinstance(action, Mapping) or set(action) != {"action", "pose"}:
                raise InvalidActionError(agent, "action", action, "a dict with the keys 'action' and 'pose'")
            pose = np.asarray(action["pose"], dtype=np.float64)
            if pose.shape != (3,) or not np.all(np.isfinite(pose)):
                raise InvalidActionError(agent, "pose", action["pose"], "(x m, y m, theta rad), three finite numbers")
            inner[agent], estimates[agent] = action["action"], pose
        observations, rewards, terminations, truncations, infos = self.env.step(inner)
        before, self._truth = self._truth, self.env.unwrapped.truth()
        rewards = dict(rewards)
        for agent, pose in estimates.items():
            if agent in rewards and before is not None:
                rewards[agent] -= self.error(pose, before, agent)
        return observations, rewards, terminations, truncations, infos

    def error(self, pose: np.ndarray, truth: MatchTruth, agent: str) -> float:
        """The weighted error of ``pose`` (x, y, theta) against ``agent``'s true pose in ``truth``."""
        robot = truth.robots[agent]
        distance = math.hypot(pose[0] - robot.x, pose[1] - robot.y)
        heading = abs(math.remainder(pose[2] - robot.theta, math.tau))
        return self.position_weight * distance + self.heading_weight * heading
