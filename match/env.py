"""PettingZoo parallel environment: a thin adapter over :class:`match.game.Match`.

``from match import parallel_env``; ``env = parallel_env(home_players=2, away_players=2)``.
Agents are ``home_0..home_3`` and ``away_0..away_3`` (player 0 the goalkeeper). Spaces are
in :mod:`match.protocol.spaces`. Rewards are +1/-1 per goal to every robot of the scoring /
conceding team; all agents terminate when the match is finished and are truncated after
``max_cycles`` steps. Ground truth is in ``infos`` only with ``privileged=True``. A step is
refused with a :class:`~match.errors.StepRefusedError` (bad actions, before ``reset``, after the
end) before anything of it happens.
"""

from __future__ import annotations

import logging
import os
from dataclasses import replace

import cv2
import numpy as np
from gymnasium import spaces
from pettingzoo import ParallelEnv

from match.errors import MatchConfigError, StepRefusedError, UnknownAgentError
from match.game import Match, MatchConfig
from match.protocol.spaces import action_space, observation_space

log = logging.getLogger(__name__)

DEFAULT_MAX_CYCLES = 100_000  # 4000 s of simulated time: a full match with its pauses fits


class RobotStadiumEnv(ParallelEnv):
    metadata = {"name": "robotstadium_v0", "render_modes": ["rgb_array", "human"], "render_fps": 25, "is_parallelizable": True}

    def __init__(
        self,
        home_players: int = 4,
        away_players: int = 4,
        *,
        half_seconds: float | None = None,
        max_cycles: int = DEFAULT_MAX_CYCLES,
        render_mode: str | None = None,
        privileged: bool = False,
        config: MatchConfig | None = None,
    ):
        if render_mode not in (None, *self.metadata["render_modes"]):
            raise MatchConfigError(f"render_mode {render_mode!r}; expected None or one of {self.metadata['render_modes']}")
        if not isinstance(max_cycles, int) or max_cycles < 1:
            raise MatchConfigError(f"max_cycles {max_cycles!r}; expected an integer >= 1")
        config = config or MatchConfig()
        config = replace(config, home_players=home_players, away_players=away_players)
        if half_seconds is not None:
            config = replace(config, referee=replace(config.referee, half_seconds=half_seconds))
        self.match = Match(config)
        self.possible_agents = list(self.match.agent_names)
        self.agents: list[str] = []
        self.max_cycles = max_cycles
        self.render_mode = render_mode
        self.privileged = privileged
        self.num_cycles = 0
        self._observation_spaces = {a: observation_space() for a in self.possible_agents}
        self._action_spaces = {a: action_space() for a in self.possible_agents}
        self._seeds: np.random.SeedSequence | None = None
        self._window = None

    # ---- spaces -----------------------------------------------------------------------

    def observation_space(self, agent: str) -> spaces.Dict:
        return self._observation_spaces[self._known(agent)]

    def action_space(self, agent: str) -> spaces.Dict:
        return self._action_spaces[self._known(agent)]

    def _known(self, agent: str) -> str:
        if agent not in self._observation_spaces:
            raise UnknownAgentError(agent, self.possible_agents)
        return agent

    # ---- life cycle -------------------------------------------------------------------

    def reset(self, seed: int | None = None, options: dict | None = None):
        """Start a new match. ``seed`` None: the next seed of the sequence of the last seed given."""
        if seed is not None:
            self._seeds = np.random.SeedSequence(seed)
            match_seed = int(seed)
        else:
            if self._seeds is None:
                self._seeds = np.random.SeedSequence()
            self._seeds = self._seeds.spawn(1)[0]
            match_seed = int(self._seeds.generate_state(1)[0])
        for i, agent in enumerate(self.possible_agents):
            self._action_spaces[agent].seed(match_seed + i)
        observations = self.match.reset(match_seed)
        self.agents = list(self.possible_agents)
        self.num_cycles = 0
        return observations, self._infos()

    def step(self, actions: dict):
        """One control step for the live agents. A :class:`StepRefusedError` (actions not a dict of
        agent id -> valid action, no live agent: before reset or after the end) changes nothing."""
        if not self.agents:
            raise StepRefusedError("no live agents (the episode has not started or is over); call reset() first")
        result = self.match.step(actions)  # the live agents are all the match's agents: it checks the actions
        self.num_cycles += 1
        finished = result.finished
        truncated = self.num_cycles >= self.max_cycles
        live = list(self.agents)
        observations = {a: result.observations[a] for a in live}
        rewards = {a: result.rewards[a] for a in live}
        terminations = dict.fromkeys(live, finished)
        truncations = dict.fromkeys(live, truncated and not finished)
        infos = self._infos(result.events)
        if finished or truncated:
            self.agents = []
        if self.render_mode == "human":
            self.render()
        return observations, rewards, terminations, truncations, {a: infos[a] for a in live}

    def _infos(self, events=()) -> dict[str, dict]:
        if not self.privileged:
            return {a: {} for a in self.possible_agents}
        truth = self.match.truth()
        game = [e.to_json() for e in events]
        return {
            a: {"true_pose": truth["robots"][a]["pose"], "fallen": truth["robots"][a]["fallen"], "ball": truth["ball"], "events": game}
            for a in self.possible_agents
        }

    # ---- rendering --------------------------------------------------------------------

    def render(self) -> np.ndarray | None:
        """A broadcast view of the field with the score and clock (rgb_array), or a window (human)."""
        if self.render_mode is None:
            log.warning("render() called without a render_mode; pass render_mode='rgb_array' or 'human'")
            return None
        frame = broadcast_frame(self.match)
        if self.render_mode == "rgb_array":
            return frame
        if not os.environ.get("DISPLAY") and os.name != "nt":
            log.warning("render_mode 'human' needs a display; none found, rendering as 'rgb_array' from now on")
            self.render_mode = "rgb_array"
            return None
        try:
            cv2.imshow("robotstadium", cv2.cvtColor(frame, cv2.COLOR_RGB2BGR))
            cv2.waitKey(1)
        except cv2.error as error:  # opencv-python-headless has no GUI
            log.warning("cannot open a window (%s); use render_mode='rgb_array'", error)
            self.render_mode = "rgb_array"
        return None

    def close(self) -> None:
        self.match.close()


def broadcast_frame(match: Match) -> np.ndarray:
    """The overview image of the field with a score bar (RGB uint8, 480x640)."""
    frame = np.ascontiguousarray(match.world.render_overview())
    referee = match.referee
    gc = referee.game_control()
    minutes, seconds = divmod(int(round(gc.seconds_remaining)), 60)
    home, away = gc.score
    text = f"home {home} - {away} away   half {gc.half}   {minutes:02d}:{seconds:02d}   {gc.state.name}"
    if referee.shootout is not None:
        text += f"   pens {gc.shootout_score[0]}-{gc.shootout_score[1]}"
    cv2.rectangle(frame, (0, 0), (frame.shape[1], 26), (20, 20, 20), thickness=-1)
    cv2.putText(frame, text, (8, 18), cv2.FONT_HERSHEY_SIMPLEX, 0.5, (255, 255, 255), 1, cv2.LINE_AA)
    return frame


def parallel_env(**kwargs) -> RobotStadiumEnv:
    """The PettingZoo parallel environment (see :class:`RobotStadiumEnv` for the options)."""
    return RobotStadiumEnv(**kwargs)
