"""PettingZoo environment: a thin adapter over :class:`match.game.Match`.

``from match import parallel_env``; ``env = parallel_env(home_players=2, away_players=2)``.
:func:`env` and :func:`raw_env` give the same match as a PettingZoo AEC env (robots act in
turn, the match steps once all have acted; each action is checked at its own agent's turn, so a
refused one is refused to that agent and leaves the turn where it was). Agents are ``home_0..home_3`` and ``away_0..away_3``
(player 0 the goalkeeper). Spaces are in :mod:`match.protocol.spaces`; the global
:meth:`~RobotStadiumEnv.state` is in :mod:`match.env_state`. Rewards are +1/-1 per goal to
every robot of the scoring / conceding team; all agents terminate when the match is finished
and are truncated after ``max_cycles`` steps. Ground truth is in ``infos`` only with
``privileged=True``. A step is refused with a :class:`~match.errors.StepRefusedError` (bad
actions, before ``reset``, after the end, after ``close``) before anything of it happens.
"""

from __future__ import annotations

import logging
from dataclasses import replace

import cv2
import numpy as np
from gymnasium import spaces
from pettingzoo import AECEnv, ParallelEnv
from pettingzoo.utils.conversions import parallel_to_aec_wrapper
from pettingzoo.utils.wrappers import OrderEnforcingWrapper

from match.env_state import global_state, state_space
from match.errors import EnvClosedError, MatchConfigError, StepRefusedError, UnknownAgentError, shown
from match.game import Match, MatchConfig
from match.protocol.actions import Action
from match.protocol.spaces import action_space, observation_space

log = logging.getLogger(__name__)

DEFAULT_MAX_CYCLES = 100_000  # 4000 s of simulated time: a full match with its pauses fits
ACTION_SPACE_SEED = 0  # agent i's action space is seeded once, at construction, with this + i


class RobotStadiumEnv(ParallelEnv):
    """The match as a PettingZoo parallel env.

    Action spaces are seeded once, at construction (agent ``i`` of ``possible_agents`` with
    ``ACTION_SPACE_SEED + i``), so that two envs built alike sample the same actions; ``reset``
    never seeds them, so ``env.action_space(agent).seed(n)`` holds until the user seeds again.

    A copy (``pickle``, ``copy.copy``, ``copy.deepcopy``) is a new env with the same settings
    and its own physics world, not a snapshot: it must be ``reset()`` before ``step``, its
    action spaces are seeded as at construction, and its ``reset()`` without a seed draws the
    seed the original's next ``reset()`` without a seed would draw.
    """

    metadata = {"name": "robotstadium_v0", "render_modes": ["rgb_array"], "render_fps": 25, "is_parallelizable": True}

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
            raise MatchConfigError(
                f"render_mode {render_mode!r}; expected None or one of {self.metadata['render_modes']}"
                " (opencv-python-headless opens no window; show the 'rgb_array' frames yourself)"
            )
        if not isinstance(max_cycles, int) or max_cycles < 1:
            raise MatchConfigError(f"max_cycles {max_cycles!r}; expected an integer >= 1")
        self._settings = {
            "home_players": home_players,
            "away_players": away_players,
            "half_seconds": half_seconds,
            "max_cycles": max_cycles,
            "render_mode": render_mode,
            "privileged": privileged,
            "config": config,
        }
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
        self.state_space = state_space(self.possible_agents)
        self._observation_spaces = {a: observation_space() for a in self.possible_agents}
        self._action_spaces = {a: action_space() for a in self.possible_agents}
        for i, agent in enumerate(self.possible_agents):
            self._action_spaces[agent].seed(ACTION_SPACE_SEED + i)
        self._seeds: np.random.SeedSequence | None = None
        self._closed = False

    # ---- copies -----------------------------------------------------------------------

    def __getstate__(self) -> dict:
        """The settings and the seed sequence: a copy builds its own world (see the class docstring)."""
        return {"settings": self._settings, "seeds": self._seeds}

    def __setstate__(self, state: dict) -> None:
        self.__init__(**state["settings"])
        self._seeds = state["seeds"]

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
        """Start a new match. ``seed`` None: the next seed of the sequence of the last seed given.
        ``options``: ``{"random_start": True}`` starts the robots at poses drawn from the seed
        (uniform inside the field's lines, apart from each other and the ball) instead of their
        kick-off poses; other keys are ignored with a warning. Raises :class:`EnvClosedError` after
        :meth:`close` and :class:`MatchConfigError` for options that are not a dict or a
        ``random_start`` that is not a bool, before anything changes."""
        self._open("reset()")
        random_start = _random_start(options)
        if seed is not None:
            self._seeds = np.random.SeedSequence(seed)
            match_seed = int(seed)
        else:
            if self._seeds is None:
                self._seeds = np.random.SeedSequence()
            self._seeds = self._seeds.spawn(1)[0]
            match_seed = int(self._seeds.generate_state(1)[0])
        observations = self.match.reset(match_seed, random_start=random_start)
        self.agents = list(self.possible_agents)
        self.num_cycles = 0
        return observations, self._infos()

    def step(self, actions: dict):
        """One control step for the live agents. A :class:`StepRefusedError` (actions not a dict of
        agent id -> valid action, no live agent: before reset, after the end or after close) changes nothing."""
        if self._closed:
            raise StepRefusedError("the env is closed; build a new one")
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
        return observations, rewards, terminations, truncations, {a: infos[a] for a in live}

    def check_action(self, agent: str, action: object) -> Action:
        """``agent``'s action checked as :meth:`step` checks it, without stepping: the checked Action, or the
        :class:`StepRefusedError` :meth:`step` would raise for it. Nothing changes."""
        if self._closed:
            raise StepRefusedError("the env is closed; build a new one")
        return self.match.check_action(agent, action)

    def state(self) -> np.ndarray:
        """The global state now: a float32 vector in :attr:`state_space` (layout in :mod:`match.env_state`).

        Ground truth of the whole match, not an agent's observation. Before the first ``reset``
        it describes the world as built (game state INITIAL)."""
        self._open("state()")
        return global_state(self.match, self.possible_agents, self.state_space)

    def _infos(self, events=()) -> dict[str, dict]:
        if not self.privileged:
            return {a: {} for a in self.possible_agents}
        truth = self.match.truth()
        game = [e.to_json() for e in events]
        return {
            a: {
                "true_pose": truth["robots"][a]["pose"],
                "fallen": truth["robots"][a]["fallen"],
                "ball": truth["ball"],
                "events": game,
            }
            for a in self.possible_agents
        }

    def _open(self, what: str) -> None:
        if self._closed:
            raise EnvClosedError(f"{what} of a closed env; build a new one")

    # ---- rendering --------------------------------------------------------------------

    def render(self) -> np.ndarray | None:
        """A broadcast view of the field with the score and clock (``rgb_array``); None without a render_mode."""
        if self.render_mode is None:
            log.warning("render() called without a render_mode; pass render_mode='rgb_array'")
            return None
        self._open("render()")
        return broadcast_frame(self.match)

    def close(self) -> None:
        """Free the physics world; a second call does nothing. Afterwards only copies and spaces work."""
        if self._closed:
            return
        self._closed = True
        self.agents = []
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


class CheckedTurns(parallel_to_aec_wrapper):
    """PettingZoo's AEC view of the parallel env, each action checked at its own agent's turn.

    PettingZoo's wrapper stores every action unchecked and steps the parallel env at the last
    agent's turn, so one bad action would be refused at every later turn until ``reset``. Here
    a refused action raises the :class:`StepRefusedError` (naming the agent, the field, the value
    and what was expected) at its own agent's turn and is not stored: the turn stays with that
    agent and nothing of the env changes.
    """

    def step(self, action: object) -> None:
        agent = self.agent_selection
        if not (self.terminations[agent] or self.truncations[agent]):
            action = self.env.check_action(agent, action)
        super().step(action)


def raw_env(**kwargs) -> AECEnv:
    """The match as a PettingZoo AEC env (:class:`CheckedTurns`), without PettingZoo's order-enforcing wrapper."""
    return CheckedTurns(RobotStadiumEnv(**kwargs))


def env(**kwargs) -> AECEnv:
    """The match as a PettingZoo AEC env (:func:`raw_env` in PettingZoo's order-enforcing wrapper)."""
    return OrderEnforcingWrapper(raw_env(**kwargs))


RESET_OPTIONS = ("random_start",)


def _random_start(options: object) -> bool:
    """``options["random_start"]`` of a ``reset`` (other keys are ignored with a warning); a
    :class:`MatchConfigError` for options that are not a dict or a ``random_start`` that is not a bool."""
    if options is None:
        return False
    if not isinstance(options, dict):
        raise MatchConfigError(
            f"reset options = {shown(options)} are invalid; expected None or a dict with keys {RESET_OPTIONS}"
        )
    unknown = sorted(map(shown, set(options) - set(RESET_OPTIONS)))
    if unknown:  # PettingZoo's api_test passes options of its own: ignored, as gymnasium envs do
        log.warning("reset options %s are not this env's (%s): ignored", ", ".join(unknown), ", ".join(RESET_OPTIONS))
    value = options.get("random_start", False)
    if not isinstance(value, bool):
        raise MatchConfigError(f"reset option random_start = {shown(value)} is invalid; expected True or False")
    return value
