"""PettingZoo environment: a thin adapter over :class:`match.game.Match`.

``from match import parallel_env``; ``env = parallel_env(home_players=2, away_players=2)``.
:func:`env` and :func:`raw_env` give the same match as a PettingZoo AEC env (robots act in
turn, the match steps once all have acted; each action is checked at its own agent's turn, so a
refused one is refused to that agent and leaves the turn where it was). Agents are ``home_0..home_3`` and ``away_0..away_3``
(player 0 the goalkeeper). Spaces are in :mod:`match.protocol.spaces`; the global
:meth:`~RobotStadiumEnv.state` is in :mod:`match.env_state`. Rewards are +1/-1 per goal to
every robot of the scoring / conceding team, or what a ``reward_fn`` (:mod:`match.rewards`)
makes of the match's truth; all agents terminate when the match is finished and are truncated
after ``max_cycles`` steps. An episode's length, pauses, shoot-out and start are settings
(:mod:`match.episodes`); seeds of copies and sub-envs are kept apart by streams
(:mod:`match.seeding`). Ground truth is in ``infos`` only with ``privileged=True``, and never in
an observation. A step is refused with a :class:`~match.errors.StepRefusedError` (bad
actions, before ``reset``, after the end, after ``close``) before anything of it happens.
"""

from __future__ import annotations

import logging
from collections.abc import Mapping
from dataclasses import replace

import cv2
import numpy as np
from gymnasium import spaces
from pettingzoo import AECEnv, ParallelEnv
from pettingzoo.utils.conversions import parallel_to_aec_wrapper
from pettingzoo.utils.wrappers import OrderEnforcingWrapper

from match import seeding
from match.env_state import global_state, state_space
from match.episodes import DEFAULT_MAX_CYCLES, Episode, episode_of
from match.errors import EnvClosedError, MatchConfigError, RewardError, StepRefusedError, UnknownAgentError, shown
from match.game import Match, MatchConfig
from match.human import HumanView
from match.protocol.actions import Action
from match.protocol.spaces import action_space, observation_space
from match.rewards import RewardFn
from match.truth import MatchTruth, match_truth

log = logging.getLogger(__name__)

ACTION_SPACE_SEED = 0  # agent i's action space of an env that is not a copy is seeded with this + i
__all__ = ["DEFAULT_MAX_CYCLES", "RobotStadiumEnv", "env", "parallel_env", "raw_env"]


class RobotStadiumEnv(ParallelEnv):
    """The match as a PettingZoo parallel env.

    Episode settings (:class:`match.episodes.Episode`): ``half_seconds``, ``halves``, ``pauses``,
    ``shootout``, ``start`` and ``max_cycles``, on top of ``preset`` (``"match"``, the default, or
    ``"learning"``) and of ``config``'s referee; ``reset(options=...)`` changes them for one episode.
    ``reward_fn`` (:mod:`match.rewards`) replaces the goal rewards. ``stream``: this env's seed
    stream (:mod:`match.seeding`; ``()`` for a standalone env).

    Action spaces of an env built here are seeded once, at construction (agent ``i`` of
    ``possible_agents`` with ``ACTION_SPACE_SEED + i``), so that two envs built alike sample the
    same actions; ``reset`` never seeds them, so ``env.action_space(agent).seed(n)`` holds until
    the user seeds again.

    A copy (``pickle``, ``copy.copy``, ``copy.deepcopy``, a vector env's sub-env) is a new env
    with the same settings and its own physics world, not a snapshot: it must be ``reset()``
    before ``step``. It lies on its own stream (its original's plus the copy's index), so its
    ``reset(seed=s)`` plays another match than the original's or another copy's; until it is
    seeded, its resets draw seeds from fresh entropy, and its action spaces are seeded from
    fresh entropy.
    """

    metadata = {"name": "robotstadium_v0", "render_modes": ["human", "rgb_array"], "render_fps": 25,
                "is_parallelizable": True}

    def __init__(
        self,
        home_players: int = 4,
        away_players: int = 4,
        *,
        half_seconds: float | None = None,
        halves: int | None = None,
        pauses: bool | None = None,
        shootout: bool | None = None,
        start: str | None = None,
        max_cycles: int | None = None,
        preset: str | Episode | None = None,
        reward_fn: RewardFn | None = None,
        render_mode: str | None = None,
        privileged: bool = False,
        config: MatchConfig | None = None,
        stream: tuple[int, ...] = (),
    ):
        self._settings = {
            "home_players": home_players, "away_players": away_players, "half_seconds": half_seconds,
            "halves": halves, "pauses": pauses, "shootout": shootout, "start": start, "max_cycles": max_cycles,
            "preset": preset, "reward_fn": reward_fn, "render_mode": render_mode, "privileged": privileged,
            "config": config, "stream": stream,
        }
        self._build(copy_of=None)

    def _build(self, copy_of: tuple[int, ...] | None) -> None:
        """Check the settings and build the match; ``copy_of``: the stream of a copy (None: not a copy)."""
        s = self._settings
        if s["render_mode"] not in (None, *self.metadata["render_modes"]):
            raise MatchConfigError(f"render_mode {s['render_mode']!r}; expected None or one of "
                                   f"{self.metadata['render_modes']}")
        if s["render_mode"] == "human":
            HumanView.check_available()
        if s["reward_fn"] is not None and not isinstance(s["reward_fn"], RewardFn):
            raise MatchConfigError(f"reward_fn = {shown(s['reward_fn'])} is invalid; expected None or an object with "
                                   "reset(truth) and __call__(truth) -> {agent: reward} (match.rewards)")
        if not isinstance(s["privileged"], bool):
            raise MatchConfigError(f"privileged = {shown(s['privileged'])} is invalid; expected True or False")
        self.episode = episode_of(s["preset"], half_seconds=s["half_seconds"], halves=s["halves"], pauses=s["pauses"],
                                  shootout=s["shootout"], start=s["start"], max_cycles=s["max_cycles"])
        self.stream = seeding.check_stream(s["stream"] if copy_of is None else copy_of)
        config = s["config"] or MatchConfig()
        if not isinstance(config, MatchConfig):
            raise MatchConfigError(f"config = {shown(config)} is invalid; expected None or a MatchConfig")
        config = replace(config, home_players=s["home_players"], away_players=s["away_players"])
        self._base_referee = config.referee
        config = replace(config, referee=self.episode.referee(config.referee))
        self.match = Match(config)
        self.possible_agents = list(self.match.agent_names)
        self.agents: list[str] = []
        self.max_cycles = self.episode.max_cycles
        self.render_mode = s["render_mode"]
        self.privileged = s["privileged"]
        self.reward_fn = s["reward_fn"]
        self.num_cycles = 0
        self.episode_seed: int | None = None  # the match seed of the episode under way
        self._episode = self.episode
        self._copies = 0
        self.state_space = state_space(self.possible_agents)
        self._observation_spaces = {a: observation_space() for a in self.possible_agents}
        self._action_spaces = {a: action_space() for a in self.possible_agents}
        self._space_seeds = (seeding.fresh_space_seeds(len(self.possible_agents)) if copy_of is not None
                             else [ACTION_SPACE_SEED + i for i in range(len(self.possible_agents))])
        for agent, seed in zip(self.possible_agents, self._space_seeds):
            self._action_spaces[agent].seed(seed)
        self._seeds: np.random.SeedSequence | None = None
        self._human = HumanView() if self.render_mode == "human" else None
        self._closed = False

    # ---- copies -----------------------------------------------------------------------

    def __getstate__(self) -> dict:
        """The settings and the copy's stream: a copy builds its own world (see the class docstring)."""
        index = self._copies
        self._copies += 1
        return {"settings": self._settings, "stream": seeding.copy_stream(self.stream, index)}

    def __setstate__(self, state: dict) -> None:
        self._settings = dict(state["settings"])
        self._build(copy_of=tuple(state["stream"]))

    def space_seed(self, index: int) -> int:
        """The seed of agent ``possible_agents[index]``'s action space at construction; wrappers that make
        action spaces of their own seed them with it, so copies sample apart as the env's spaces do."""
        return self._space_seeds[index]

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
        """Start a new episode.

        ``seed``: an integer 0 .. 2**64 - 1; None: the next seed of the sequence of the last seed
        given (fresh entropy before any). The match seed played is :attr:`episode_seed`.
        ``options``: a dict of :class:`match.episodes.Episode` settings for this episode only
        (``start``, ``half_seconds``, ``halves``, ``pauses``, ``shootout``, ``max_cycles``), and
        ``random_start``: True starts the robots at poses drawn from the seed (uniform inside the
        field's lines, apart from each other and the ball) before the referee's kick-off; other
        keys are ignored with a warning. Raises :class:`EnvClosedError` after :meth:`close` and
        :class:`MatchConfigError` for a bad seed or options, before anything changes."""
        self._open("reset()")
        episode = self.episode.with_options(options)
        random_start = _random_start(options)
        if seed is not None:
            match_seed, sequence = seeding.seeded(seeding.check_seed(seed), self.stream)
        else:
            match_seed, sequence = seeding.continued_seeds(self._seeds)
        referee = episode.referee(self._base_referee)
        observations = self.match.reset(match_seed, random_start=random_start, start=episode.start, referee=referee)
        self._seeds = sequence
        self.episode_seed = match_seed
        self._episode = episode
        self.agents = list(self.possible_agents)
        self.num_cycles = 0
        if self.reward_fn is not None:
            self.reward_fn.reset(self.truth())
        if self._human is not None:
            self._human.reopen()
            self.render()
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
        truncated = self.num_cycles >= self._episode.max_cycles
        live = list(self.agents)
        observations = {a: result.observations[a] for a in live}
        if self.reward_fn is None:
            rewards = {a: result.rewards[a] for a in live}
        else:
            rewards = self._shaped(live, self.truth(result.goals, result.events))
        terminations = dict.fromkeys(live, finished)
        truncations = dict.fromkeys(live, truncated and not finished)
        infos = self._infos(result.events)
        if finished or truncated:
            self.agents = []
        if self._human is not None:
            self.render()
        return observations, rewards, terminations, truncations, {a: infos[a] for a in live}

    def _shaped(self, live: list[str], truth: MatchTruth) -> dict[str, float]:
        """The reward function's rewards for the live agents; a :class:`RewardError` for what is not a finite
        number of a known agent."""
        given = self.reward_fn(truth)
        if not isinstance(given, Mapping):
            raise RewardError(f"reward_fn returned {shown(given)}; expected a dict of agent id -> float")
        rewards = dict.fromkeys(live, 0.0)
        for agent, value in given.items():
            if agent not in self._observation_spaces:
                raise RewardError(f"reward_fn gave a reward to {shown(agent)}; expected agents of {self.possible_agents}")
            if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)) or not np.isfinite(value):
                raise RewardError(f"reward_fn gave {agent!r} the reward {shown(value)}; expected a finite number")
            if agent in rewards:
                rewards[agent] = float(value)
        return rewards

    def truth(self, goals=(), events=()) -> MatchTruth:
        """The match's truth now (:class:`match.truth.MatchTruth`: the ball, every pose, the score), for
        rewards, evaluation and logs; never part of an observation. ``goals`` and ``events``: those of the
        last step, as the env hands them to its reward function."""
        self._open("truth()")
        return match_truth(self.match, tuple(goals), tuple(events))

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

    def render(self, mode: str | None = None) -> np.ndarray | None:
        """The broadcast view of the field with the score and clock: the frame (``rgb_array``), or None after
        showing it in the window (``human``); None without a render_mode. ``mode``, as RLlib's PettingZoo
        adapter passes it: None or this env's render_mode."""
        if mode is not None and mode != self.render_mode:
            raise MatchConfigError(f"render(mode={shown(mode)}); this env renders {self.render_mode!r}: build it with "
                                   "that render_mode")
        if self.render_mode is None:
            log.warning("render() called without a render_mode; pass render_mode='rgb_array' or 'human'")
            return None
        self._open("render()")
        frame = broadcast_frame(self.match)
        if self._human is not None:
            self._human.show(frame)
            return None
        return frame

    def close(self) -> None:
        """Free the physics world; a second call does nothing. Afterwards only copies and spaces work."""
        if self._closed:
            return
        self._closed = True
        self.agents = []
        if self._human is not None:
            self._human.close()
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


def parallel_env(*args, **kwargs) -> RobotStadiumEnv:
    """The PettingZoo parallel environment (see :class:`RobotStadiumEnv` for the options)."""
    return RobotStadiumEnv(*args, **kwargs)


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


def raw_env(*args, **kwargs) -> AECEnv:
    """The match as a PettingZoo AEC env (:class:`CheckedTurns`), without PettingZoo's order-enforcing wrapper."""
    return CheckedTurns(RobotStadiumEnv(*args, **kwargs))


def env(*args, **kwargs) -> AECEnv:
    """The match as a PettingZoo AEC env (:func:`raw_env` in PettingZoo's order-enforcing wrapper)."""
    return OrderEnforcingWrapper(raw_env(*args, **kwargs))


def _random_start(options: object) -> bool:
    """``options["random_start"]`` of a ``reset`` (the options were checked to be None or a dict); a
    :class:`MatchConfigError` for a ``random_start`` that is not a bool."""
    value = False if options is None else options.get("random_start", False)
    if not isinstance(value, bool):
        raise MatchConfigError(f"reset option random_start = {shown(value)} is invalid; expected True or False")
    return value
