"""A simple scripted policy: an honest ball chaser for field players, a line-holding keeper.

A keeper that has heard no teammate for 4 s (a team of one) chases the ball as a field player.

It decides only from its observation (see :mod:`match.protocol.spaces`): the camera image
(ball found by :mod:`agents.vision.ball`), head angles, accelerometer, gyro,
motion status, game-control view and the teammates' radio packets. No localization: the
heading is the gyro integrated from the kick-off heading.

Frames: torso frame x forward, y left, bearings CCW positive; field headings CCW from +x
(toward the yellow goal). Its motions are the skills of :mod:`agents.behavior.skills`.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from agents.behavior.skills import (
    BOTTOM_CAMERA_BELOW_M,
    CONTROL_STEP_S,
    IDLE_SCAN_RATE_RADPS,
    KEEPER_PLAYER,
    LONE_SILENCE_S,
    NEAR_SCAN_PITCH_RAD,
    SCAN_PITCH_RAD,
    SEARCH_SCAN_RATE_RADPS,
    SEARCH_TURN_HEAD,
    SEARCH_TURN_RADPS,
    SEARCH_TURN_STEPS,
    STILL,
    plays_alone,
    TOP_CAMERA_BEYOND_M,
    HeadSweep,
    chase,
    clip_head,
    keep_goal,
    look_at,
    stand_up_for,
    walk_command,
)
from agents.observation import Observation, RadioPacket
from agents.radio import TeamMessage, decode
from agents.vision.ball import BallPercept, find_ball
from match.protocol import CameraChoice, GameState, GoalColor, Motion, make_action
from world.camera_model import CameraPosition
from world.field import normalize_angle

LOG = logging.getLogger(__name__)

# Radio.
BALL_MEMORY_STEPS = 12
YIELD_MARGIN_M = 0.3  # hold position when a teammate is this much nearer to the ball

RADIO_EVERY_STEPS = 5
TEAMMATE_MEMORY_STEPS = 12
LONE_SILENCE_STEPS = round(LONE_SILENCE_S / CONTROL_STEP_S)  # then the keeper chases the ball (a team of one)
UNKNOWN_DISTANCE_M = -1.0



@dataclass(frozen=True)
class TeammateReport:
    """A teammate's ball report: its distance (m, -1 unknown) and bearing (rad, its torso frame)."""

    player: int
    ball_distance_m: float
    ball_bearing_rad: float


@dataclass(frozen=True)
class Command:
    """What to do this step: a motion (with its walk velocity) and where to look."""

    motion: Motion
    walk: tuple[float, float, float] = STILL
    head: tuple[float, float] = (0.0, SCAN_PITCH_RAD)


def encode_report(player: int, ball: BallPercept | None) -> bytes:
    """The radio packet (:mod:`agents.radio`) announcing this robot's ball as it sees it (torso frame):
    it has no pose to put it in the field."""
    relative = None if ball is None else (ball.distance_m, ball.bearing_rad)
    return TeamMessage(player, ball_relative=relative).encode()


def decode_reports(packets: tuple[RadioPacket, ...], own_player: int) -> tuple[TeammateReport, ...]:
    """Teammates' ball reports among the packets received (a teammate without a ball of its own reports
    :data:`UNKNOWN_DISTANCE_M`); packets that are not the radio's format, or not from their sender, are
    ignored."""
    reports = []
    for packet in packets:
        if packet.sender == own_player:
            continue
        message = decode(packet.data)
        if message is None or message.player != packet.sender:
            continue
        distance, bearing = (UNKNOWN_DISTANCE_M, 0.0) if message.ball_relative is None else message.ball_relative
        reports.append(TeammateReport(packet.sender, distance, bearing))
    return tuple(reports)


def kickoff_heading(defended_goal: GoalColor) -> float:
    """Field heading at kick-off, which is also the attacked direction: +x when defending blue."""
    return 0.0 if defended_goal is GoalColor.BLUE else math.pi


@dataclass
class _Memory:
    """What the player carries from step to step."""

    step: int = 0
    heading_rad: float = 0.0
    ball: BallPercept | None = None
    ball_age: int = BALL_MEMORY_STEPS + 1
    camera: CameraPosition = CameraPosition.TOP
    scan: HeadSweep = field(default_factory=HeadSweep)
    searching: bool = False
    search_turn_steps: int = 0
    last_bearing_rad: float = 0.0
    teammates: dict[int, tuple[float, int]] = field(default_factory=dict)  # player -> (ball distance m, step)


class ScriptedPlayer:
    """The scripted policy (:class:`match.protocol.policy.Policy`): ball chaser, or keeper as player 0
    (unless it plays alone).

    ``camera_every_steps``: the camera is on every this many control steps, off between.
    It draws no random numbers, so the seed of :meth:`reset` changes nothing.
    """

    def __init__(self, *, camera_every_steps: int = 2):
        if not isinstance(camera_every_steps, int) or camera_every_steps < 1:
            raise ValueError(f"camera_every_steps={camera_every_steps!r}; expected an integer >= 1")
        self.agent = ""
        self.camera_every_steps = camera_every_steps
        self._m = _Memory()

    def reset(self, agent_id: str, seed: int) -> None:
        """Forget everything; play robot ``agent_id``."""
        self.agent = agent_id
        self._m = _Memory()

    # ---- the step -----------------------------------------------------------------------

    def act(self, observation: Observation | Mapping[str, Any]) -> dict:
        """The action for one control step."""
        obs = Observation.of(observation)
        self._update_heading(obs)
        self._update_ball(obs)
        self._update_teammates(obs)
        command = self._decide(obs)
        camera = self._camera_choice()
        radio = encode_report(obs.player, self._known_ball()) if self._m.step % RADIO_EVERY_STEPS == 0 else b""
        self._m.step += 1
        return make_action(command.motion, walk=command.walk, head=clip_head(*command.head), camera=camera, radio=radio)

    # ---- beliefs ------------------------------------------------------------------------

    def _update_heading(self, obs: Observation) -> None:
        """Integrate gyro z; reset to the kick-off heading in INITIAL and SET."""
        if obs.game.state in (GameState.INITIAL, GameState.SET):
            self._m.heading_rad = kickoff_heading(obs.game.defended_goal)
        elif not obs.fallen and not (obs.motion is not None and obs.motion.is_stand_up):
            self._m.heading_rad = normalize_angle(self._m.heading_rad + obs.gyro_radps[2] * CONTROL_STEP_S)

    def _update_ball(self, obs: Observation) -> None:
        self._m.ball_age += 1
        if obs.image is None or obs.fallen or (obs.motion is not None and obs.motion.is_stand_up):
            return
        percept = find_ball(obs.image, obs.head_yaw_rad, obs.head_pitch_rad, obs.camera.position)
        if percept is not None:
            self._m.ball, self._m.ball_age = percept, 0
            self._m.last_bearing_rad = percept.bearing_rad

    def _update_teammates(self, obs: Observation) -> None:
        for report in decode_reports(obs.packets, obs.player):
            self._m.teammates[report.player] = (report.ball_distance_m, self._m.step)

    def _known_ball(self) -> BallPercept | None:
        return self._m.ball if self._m.ball_age <= BALL_MEMORY_STEPS else None

    def _teammate_nearer(self, player: int, distance_m: float) -> bool:
        """A teammate field player heard recently is YIELD_MARGIN_M nearer to the ball."""
        for mate, (mate_distance, heard) in self._m.teammates.items():
            recent = self._m.step - heard <= TEAMMATE_MEMORY_STEPS
            if mate not in (player, KEEPER_PLAYER) and recent and 0.0 <= mate_distance < distance_m - YIELD_MARGIN_M:
                return True
        return False

    def _silent_for_s(self) -> float:
        """Seconds since a teammate was last heard (since the reset, when none ever was)."""
        last_heard = max((heard for _, heard in self._m.teammates.values()), default=0)
        return (self._m.step - last_heard) * CONTROL_STEP_S

    def _heading_error(self, obs: Observation) -> float:
        return normalize_angle(kickoff_heading(obs.game.defended_goal) - self._m.heading_rad)

    # ---- decisions ----------------------------------------------------------------------

    def _decide(self, obs: Observation) -> Command:
        if obs.motion is not None and obs.motion.is_stand_up:
            return Command(obs.motion, head=(0.0, 0.0))
        if obs.fallen:
            motion = stand_up_for(obs.accelerometer_mps2[0])
            LOG.debug("%s: fallen, %s", self.agent, motion.value)
            return Command(motion, head=(0.0, 0.0))
        if obs.game.state is not GameState.PLAYING:
            head = self._scan(IDLE_SCAN_RATE_RADPS)
            self._m.scan.reversals = 0  # idle sweeps do not count toward a search turn
            return Command(Motion.STAND, head=head)
        ball = self._known_ball()
        head = self._track(ball) if ball is not None else self._scan(SEARCH_SCAN_RATE_RADPS)
        if obs.motion is not None and obs.motion.is_kick:
            return Command(obs.motion, head=head)
        if obs.player == KEEPER_PLAYER and not plays_alone(obs.player, self._silent_for_s()):
            return self._goalkeeper(obs, ball, head)
        return self._field_player(obs, ball, head)

    def _field_player(self, obs: Observation, ball: BallPercept | None, head: tuple[float, float]) -> Command:
        if ball is None:
            if not self._search_turning():
                return Command(Motion.STAND, head=head)
            self._m.camera = CameraPosition.BOTTOM
            return Command(Motion.WALK, self._search_turn(), SEARCH_TURN_HEAD)
        if self._teammate_nearer(obs.player, ball.distance_m):
            return Command(Motion.STAND, head=head)
        motion, walk = chase(ball, self._heading_error(obs))
        if motion.is_kick:
            LOG.debug("%s: %s, ball %.2f m at %.2f rad", self.agent, motion.value, ball.distance_m, ball.bearing_rad)
        return Command(motion, walk, head)

    def _goalkeeper(self, obs: Observation, ball: BallPercept | None, head: tuple[float, float]) -> Command:
        if ball is None:
            return Command(Motion.STAND, head=head)
        motion, walk = keep_goal(ball, self._heading_error(obs))
        return Command(motion, walk, head)

    # ---- head and camera ----------------------------------------------------------------

    def _track(self, ball: BallPercept) -> tuple[float, float]:
        """Look at the ball with the camera that can see it at its distance."""
        self._m.searching = False
        if ball.distance_m < BOTTOM_CAMERA_BELOW_M:
            self._m.camera = CameraPosition.BOTTOM
        elif ball.distance_m > TOP_CAMERA_BEYOND_M:
            self._m.camera = CameraPosition.TOP
        return look_at(ball, self._m.camera)

    def _scan(self, rate_radps: float) -> tuple[float, float]:
        """Sweep the head, starting where the ball was last seen: far sweeps with the top
        camera alternate with near sweeps with the bottom camera."""
        if not self._m.searching:
            self._m.searching = True
            self._m.search_turn_steps = 0
            start = self._m.scan.yaw_rad if self._m.ball is None else self._m.ball.bearing_rad
            self._m.scan.restart(start, self._m.last_bearing_rad)
        yaw = self._m.scan.advance(rate_radps)
        if self._m.scan.reversals % 2 == 1:
            self._m.camera = CameraPosition.BOTTOM
            return yaw, NEAR_SCAN_PITCH_RAD
        self._m.camera = CameraPosition.TOP
        return yaw, SCAN_PITCH_RAD

    def _search_turning(self) -> bool:
        """After a full sweep without the ball, turn in place for SEARCH_TURN_STEPS, then sweep again."""
        if self._m.search_turn_steps == 0 and self._m.scan.swept:
            self._m.search_turn_steps = SEARCH_TURN_STEPS
        if self._m.search_turn_steps == 0:
            return False
        self._m.search_turn_steps -= 1
        if self._m.search_turn_steps == 0:
            self._m.scan.reversals = 0
        return True

    def _search_turn(self) -> tuple[float, float, float]:
        return walk_command(0.0, 0.0, math.copysign(SEARCH_TURN_RADPS, self._m.last_bearing_rad or 1.0))

    def _camera_choice(self) -> CameraChoice:
        """The camera on every ``camera_every_steps``-th step, off otherwise."""
        if self._m.step % self.camera_every_steps != 0:
            return CameraChoice.OFF
        return CameraChoice.of(self._m.camera)
