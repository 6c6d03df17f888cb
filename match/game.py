"""The Match: a plain game class that owns the world, the referee and the radio.

One :meth:`Match.step` is one control step (40 ms): every action is checked first (a bad
one raises and nothing is applied), then heads, cameras, motions and radio packets are
applied, the world steps, the referee judges, cameras are rendered for the robots whose
camera is on, and the observations are built. :mod:`match.env` adapts it to PettingZoo;
:func:`match.runner.run_match` plays it with one policy per robot.

With ``MatchConfig.free_play`` set, the same match runs without a ball in play and without
referee decisions (:mod:`match.free_play`): the scenario runs alone on the field.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from dataclasses import field as default

import numpy as np

from match.errors import InvalidActionError, MatchConfigError, StepRefusedError, UnknownAgentError
from match.events import MatchEvent
from match.free_play import FreePlay, free_play_control
from match.observations import build_observation, game_observation, radio_observation
from match.protocol.actions import Action, parse_action, parse_actions
from match.protocol.game_control import GameControlView, GameState
from match.protocol.ids import AgentId, Side, roster
from match.protocol.spaces import CameraChoice
from match.radio import Radio, RadioConfig
from match.referee import Referee, RefereeConfig
from match.starts import Start, placement
from world.config import RobotSpec, WorldConfig
from world.errors import InvalidCommandError
from world.field import Pose2D
from world.motions import Motion
from world.teams import TeamColor
from world.world import World

log = logging.getLogger(__name__)

ObservedCallback = Callable[[str, dict], None]
"""Gets (robot name, its new observation) during :meth:`Match.step`."""
RANDOM_START_MARGIN_M = 0.3  # a random start pose lies this far inside the field's lines ...
RANDOM_START_SPACING_M = 0.5  # ... this far from the ball and the robots placed before it
RANDOM_START_TRIES = 100  # draws per robot before the last one is taken whatever its spacing


@dataclass(frozen=True)
class MatchConfig:
    home_players: int = 4
    away_players: int = 4
    referee: RefereeConfig = default(default_factory=RefereeConfig)
    radio: RadioConfig = default(default_factory=RadioConfig)
    world: WorldConfig = default(default_factory=WorldConfig)
    initial_camera: CameraChoice = CameraChoice.TOP
    free_play: FreePlay | None = None  # set: no ball in play, no referee; its starts name the robots

    def __post_init__(self) -> None:
        if self.free_play is None:
            roster(self.home_players, self.away_players)  # raises on bad team sizes

    @property
    def agents(self) -> tuple[AgentId, ...]:
        """The robots on the field: the free-play starts, else home_0.. and away_0.. by the team sizes."""
        if self.free_play is not None:
            return self.free_play.agents
        return roster(self.home_players, self.away_players)


@dataclass(frozen=True)
class StepResult:
    observations: dict[str, dict]
    rewards: dict[str, float]
    events: tuple[MatchEvent, ...]
    finished: bool
    goals: tuple[Side, ...] = ()  # the sides that scored in this step, one entry per goal


class Match:
    """A match between two teams of 1-4 robots. Build once, :meth:`reset` for every new match."""

    def __init__(self, config: MatchConfig | None = None, *, gui: bool = False):
        self.config = config or MatchConfig()
        self.agents: tuple[AgentId, ...] = self.config.agents
        self.agent_names: tuple[str, ...] = tuple(str(a) for a in self.agents)
        self._by_name = dict(zip(self.agent_names, self.agents))
        specs = [RobotSpec(str(a), TeamColor.BLUE if a.side is Side.HOME else TeamColor.RED) for a in self.agents]
        self.world = World(specs, self.config.world, gui=gui)
        self.referee = Referee(self.world, self.agents, self.config.referee)
        self.radio = Radio(self.agents, self.config.radio, self.config.world.physics.control_step_s)
        self.step_index = 0
        self.events: list[MatchEvent] = []
        self._cameras: dict[AgentId, CameraChoice] = {}
        self._started = False

    # ---- life cycle -------------------------------------------------------------------

    def reset(self, seed: int = 0, random_start: bool = False, start: Start = Start.KICKOFF,
              referee: RefereeConfig | None = None) -> dict[str, dict]:
        """Start a new match from the world's initial state; the same seed gives the same match.

        ``random_start``: the robots start at poses drawn from the seed (:meth:`_place_at_random`)
        instead of their kick-off poses (or the free play's starts), and the referee's kick-off
        follows. ``start``: another start (:class:`match.starts.Start`, drawn from the seed), with play
        at once. ``referee``: the referee's settings from this match on (None: as they were)."""
        if start is not Start.KICKOFF and self.config.free_play is not None:
            raise MatchConfigError(f"start {start.value!r} in free play; free play starts where its starts say")
        if referee is not None:
            self.referee.config = referee
        world_seed, radio_seed, start_seed = np.random.SeedSequence(seed).spawn(3)
        self.world.reset(np.random.default_rng(world_seed))
        self.radio.reset(np.random.default_rng(radio_seed))
        self.step_index = 0
        self.events = []
        self._cameras = {a: self.config.initial_camera for a in self.agents}
        for agent in self.agents:
            if self.config.initial_camera.position is not None:
                self.world.set_camera(str(agent), self.config.initial_camera.position)
        if self.config.free_play is None:
            self.events.extend(self.referee.start().events)
        else:
            self._place_free_play(self.config.free_play)
        if random_start:
            self._place_at_random(np.random.default_rng(start_seed))
        if start is not Start.KICKOFF:
            defended = {side: self.referee.defended_goal(side) for side in Side}
            placed = placement(start, self.agents, defended, np.random.default_rng(start_seed))
            for robot, pose in placed.robots:
                self.world.place_robot(robot, pose)
            self.world.place_ball(*placed.ball)
            self.events.extend(self.referee.play_on().events)
        self._started = True
        return self.observe({a: [] for a in self.agents})

    def _place_free_play(self, free_play: FreePlay) -> None:
        for robot, pose in free_play.starts:
            self.world.place_robot(robot, pose)
        self.world.place_ball(*free_play.ball_xy)
        self.world.step(free_play.settle_steps)

    def _place_at_random(self, rng: np.random.Generator) -> None:
        """Every robot standing at a uniform pose inside the field's lines (at least
        :data:`RANDOM_START_MARGIN_M` in), at least :data:`RANDOM_START_SPACING_M` from the
        robots placed before it and from the ball."""
        ball = self.world.ball()
        taken = [(ball.x, ball.y)]
        field = self.config.world.field
        half_x, half_y = field.half_length - RANDOM_START_MARGIN_M, field.half_width - RANDOM_START_MARGIN_M
        for agent in self.agents:
            for _ in range(RANDOM_START_TRIES):
                x, y = float(rng.uniform(-half_x, half_x)), float(rng.uniform(-half_y, half_y))
                if all(math.hypot(x - px, y - py) >= RANDOM_START_SPACING_M for px, py in taken):
                    break
            theta = float(rng.uniform(-math.pi, math.pi))
            self.world.place_robot(str(agent), Pose2D(x, y, theta))
            taken.append((x, y))

    def close(self) -> None:
        self.world.close()

    @property
    def state(self) -> GameState:
        """The game state now (always PLAYING in free play)."""
        return GameState.PLAYING if self.free_play else self.referee.state

    @property
    def free_play(self) -> bool:
        """Whether this match runs in free play (no ball in play, no referee decisions)."""
        return self.config.free_play is not None

    @property
    def finished(self) -> bool:
        return self.referee.finished

    # ---- stepping ---------------------------------------------------------------------

    def check_actions(self, actions: object) -> dict[AgentId, Action]:
        """Every action parsed and checked, the walk against the world's walk limits; agents
        without one stand. Raises a :class:`StepRefusedError` before anything changes."""
        parsed = parse_actions(actions, self.agent_names)
        for name, action in parsed.items():
            self._check_walk(name, action)
        return {self._by_name[name]: action for name, action in parsed.items()}

    def check_action(self, agent: str, action: object) -> Action:
        """One agent's action parsed and checked as :meth:`check_actions` checks it in a step (an agent
        not in the match is an :class:`UnknownAgentError`); nothing changes."""
        if not isinstance(agent, str) or str.__str__(agent) not in self._by_name:
            raise UnknownAgentError(agent, self.agent_names)
        name = str.__str__(agent)
        checked = parse_action(name, action)
        self._check_walk(name, checked)
        return checked

    def _check_walk(self, name: str, action: Action) -> None:
        if action.motion is Motion.WALK:
            try:
                self.config.world.walk_limits.check(*action.walk)
            except InvalidCommandError as error:
                raise InvalidActionError(name, "walk", action.walk, str(error)) from None

    def step(self, actions: Mapping[str, object], observed: ObservedCallback | None = None) -> StepResult:
        """One control step; a :class:`StepRefusedError` (bad actions, not started, finished) changes nothing.

        ``observed(robot, observation)``, if given, gets each robot's new observation as soon as it is
        built, while the others' cameras are still rendered (controller processes start on it early); not
        called on the step that ends the match."""
        if not self._started:
            raise StepRefusedError("the match has not started; call reset() before step()")
        if self.finished:
            raise StepRefusedError("the match is finished; call reset() to start a new one")
        checked = self.check_actions(actions)
        sent_now = self.world.time_s
        for agent, action in checked.items():
            self._apply(agent, action)
            if action.radio:
                self.radio.send(agent, action.radio, sent_now, self.step_index)
        self.world.step()
        self.step_index += 1
        rewards = {name: 0.0 for name in self.agent_names}
        events: tuple[MatchEvent, ...] = ()
        goals: tuple[Side, ...] = ()
        if not self.free_play:
            update = self.referee.update()
            events, goals = update.events, update.goals
            self.events.extend(events)
            for scorer in update.goals:
                for agent in self.agents:
                    rewards[str(agent)] += 1.0 if agent.side is scorer else -1.0
        positions = self._positions() if self.config.radio.range_m is not None else None
        inboxes = self.radio.deliver(self.step_index, positions)
        # a finished match is asked for no more actions: nobody is told to start on these observations
        return StepResult(self.observe(inboxes, None if self.finished else observed), rewards, events,
                          self.finished, goals)

    def _apply(self, agent: AgentId, action: Action) -> None:
        robot = str(agent)
        if action.head is not None:
            self.world.set_head(robot, *action.head)
        if action.camera is not None:
            self._cameras[agent] = action.camera
            if action.camera.position is not None:
                self.world.set_camera(robot, action.camera.position)
        motion = action.motion
        if not self.free_play and self.referee.holds(agent) and not motion.is_stand_up:
            motion = Motion.STAND
        if motion is Motion.WALK:
            self.world.command_walk(robot, *action.walk)
        else:
            self.world.command_motion(robot, motion)

    # ---- what agents get --------------------------------------------------------------

    def observe(self, inboxes: Mapping[AgentId, list], observed: ObservedCallback | None = None) -> dict[str, dict]:
        """Every robot's observation (robot name -> observation dict), in agent order; ``observed`` as in :meth:`step`
        gets them in the order they are built: the robots whose camera is off first."""
        readings = self.world.sensors_all(self.agent_names)
        broadcast = free_play_control(self.world.time_s) if self.free_play else self.referee.broadcast
        views: dict[Side, GameControlView] = {side: broadcast.view_for(side) for side in Side}
        observations = {}

        def built(robot: str, image: np.ndarray | None) -> None:
            agent = self._by_name[robot]
            observations[robot] = build_observation(
                readings[robot],
                image,
                game_observation(views[agent.side], agent.player),
                radio_observation(inboxes.get(agent, []), self.radio.take_drops(agent)),
            )
            if observed is not None:
                observed(robot, observations[robot])

        # robots whose camera is off first: their observations are ready before any frame is rendered
        seeing = [str(agent) for agent in self.agents if self._cameras[agent] is not CameraChoice.OFF]
        for robot in self.agent_names:
            if robot not in seeing:
                built(robot, None)
        # one side's frames at a time (each side's in one call): the first side's controller acts on its
        # observations while the other side's frames are drawn
        for side in Side:
            for robot, image in self.world.render_cameras([r for r in seeing if self._by_name[r].side is side]):
                built(robot, image)
        return {robot: observations[robot] for robot in self.agent_names}

    # ---- ground truth (evaluation only) -------------------------------------------------

    def truth(self) -> dict:
        """True poses of every robot and the ball: for infos in privileged mode and for logs."""
        robots = {}
        for agent in self.agents:
            t = self.world.robot_truth(str(agent))
            robots[str(agent)] = {"pose": (t.pose.x, t.pose.y, t.pose.theta), "fallen": t.fallen}
        ball = self.world.ball()
        return {
            "time_s": self.world.time_s,
            "robots": robots,
            "ball": {"position": (ball.x, ball.y, ball.z), "velocity": (ball.vx, ball.vy), "last_toucher": ball.last_toucher},
        }

    def _positions(self) -> dict[AgentId, tuple[float, float]]:
        positions = {}
        for agent in self.agents:
            pose = self.world.robot_pose(str(agent))
            positions[agent] = (pose.x, pose.y)
        return positions

    @property
    def score(self) -> dict[str, int]:
        return {side.value: self.referee.score[side] for side in Side}
