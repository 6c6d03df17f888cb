"""A simple scripted policy: an honest ball chaser for field players, a line-holding keeper.

It decides only from its observation (see :mod:`match.protocol.spaces`): the camera image
(ball found by :mod:`agents.behavior.ball_finder`), head angles, accelerometer, gyro,
motion status, game-control view and the teammates' radio packets. No localization: the
heading is the gyro integrated from the kick-off heading.

Frames: torso frame x forward, y left, bearings CCW positive; field headings CCW from +x
(toward the yellow goal). One control step is :data:`CONTROL_STEP_S`.
"""

from __future__ import annotations

import logging
import math
import struct
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from agents.behavior.ball_finder import BallPercept, find_ball
from agents.observation import Observation, RadioPacket
from match.protocol import WALK_HIGH, WALK_LOW, CameraChoice, GameState, GoalColor, Motion, make_action
from world.camera_model import NAO_HEAD, CameraPosition
from world.field import FIELD, normalize_angle

LOG = logging.getLogger(__name__)

CONTROL_STEP_S = 0.04

# Head limits with a margin (walk limits: WALK_LOW, WALK_HIGH of the action space).
_HEAD_MARGIN_RAD = 1e-3
YAW_LIMITS_RAD = (NAO_HEAD.yaw_limits_rad[0] + _HEAD_MARGIN_RAD, NAO_HEAD.yaw_limits_rad[1] - _HEAD_MARGIN_RAD)
PITCH_LIMITS_RAD = (NAO_HEAD.pitch_limits_rad[0] + _HEAD_MARGIN_RAD, NAO_HEAD.pitch_limits_rad[1] - _HEAD_MARGIN_RAD)

# Head scanning (ball unknown, or not playing).
SCAN_PITCH_RAD = 0.3
# Every other sweep looks near the feet with the bottom camera (ground about 0.06-0.42 m
# ahead): a ball right in front of the robot (a kick-off, a penalty) is seen there.
NEAR_SCAN_PITCH_RAD = 0.45
SCAN_AMPLITUDE_RAD = math.radians(100.0)
SEARCH_SCAN_RATE_RADPS = 1.5
IDLE_SCAN_RATE_RADPS = 0.5
FULL_SWEEP_REVERSALS = 2  # one end and then the other: the whole range was looked at
SEARCH_TURN_RADPS = 0.8
SEARCH_TURN_STEPS = 50  # about 90 degrees at SEARCH_TURN_RADPS
# While turning, look ahead with the bottom camera: it covers the ground 0.25-0.9 m ahead,
# which the top camera at SCAN_PITCH_RAD (from about 0.7 m) misses.
SEARCH_TURN_HEAD = (0.0, 0.1)

# Ball memory and cameras.
BALL_MEMORY_STEPS = 12
BOTTOM_CAMERA_BELOW_M = 0.6  # the top camera cannot see the ground nearer than about 0.5 m
TOP_CAMERA_BEYOND_M = 0.8  # hysteresis

# Field player.
TURN_IN_PLACE_RAD = 0.35
TURN_GAIN_PER_S = 2.0  # omega = gain * bearing
MIN_TURN_RADPS = 0.4
APPROACH_GAIN_PER_S = 0.6  # vx = gain * (distance - APPROACH_STOP_M)
APPROACH_STOP_M = 0.12
MIN_APPROACH_MPS = 0.05
ALIGN_WITHIN_M = 0.4  # nearer than this, side-step to put the ball in front of a foot
ALIGN_GAIN_PER_S = 1.5  # vy = gain * lateral error
FOOT_OFFSET_M = 0.05  # lateral offset of a foot from the torso centre
KICK_DISTANCE_M = 0.19  # kicks are strongest with the ball 0.12-0.17 m ahead, 0.03-0.08 m to the side
KICK_HEADING_TOLERANCE_RAD = math.radians(60.0)
ORBIT_RADPS = 0.5
ORBIT_DISTANCE_M = 0.15
ORBIT_DISTANCE_GAIN_PER_S = 0.5
YIELD_MARGIN_M = 0.3  # hold position when a teammate is this much nearer to the ball

# Goalkeeper.
KEEPER_PLAYER = 0
KEEPER_REACT_DISTANCE_M = 2.5
KEEPER_KICK_DISTANCE_M = 0.25
KEEPER_KICK_BEARING_RAD = 0.5
KEEPER_SIDE_GAIN_PER_S = 1.0  # vy = gain * ball lateral offset
KEEPER_HEADING_GAIN_PER_S = 1.0
KEEPER_MAX_TURN_RADPS = 0.5

# Radio.
RADIO_EVERY_STEPS = 5
REPORT = struct.Struct("<Bff")  # player, ball distance m (-1 unknown), ball bearing rad
TEAMMATE_MEMORY_STEPS = 12
UNKNOWN_DISTANCE_M = -1.0

_STILL = (0.0, 0.0, 0.0)


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
    walk: tuple[float, float, float] = _STILL
    head: tuple[float, float] = (0.0, SCAN_PITCH_RAD)


def encode_report(player: int, ball: BallPercept | None) -> bytes:
    """The radio packet announcing this robot's ball estimate."""
    if ball is None:
        return REPORT.pack(player, UNKNOWN_DISTANCE_M, 0.0)
    return REPORT.pack(player, ball.distance_m, ball.bearing_rad)


def decode_reports(packets: tuple[RadioPacket, ...], own_player: int) -> tuple[TeammateReport, ...]:
    """Teammates' ball reports among the packets received; packets of another layout are ignored."""
    reports = []
    for packet in packets:
        if packet.sender == own_player or len(packet.data) != REPORT.size:
            continue
        player, distance, bearing = REPORT.unpack(packet.data)
        if player == packet.sender and math.isfinite(distance) and math.isfinite(bearing):
            reports.append(TeammateReport(packet.sender, distance, bearing))
    return tuple(reports)


def kickoff_heading(defended_goal: GoalColor) -> float:
    """Field heading at kick-off, which is also the attacked direction: +x when defending blue."""
    return 0.0 if defended_goal is GoalColor.BLUE else math.pi


def stand_up_for(accelerometer_x_mps2: float) -> Motion:
    """Lying on the back reads about +9.81 m/s^2 on torso x, on the front about -9.81."""
    return Motion.STAND_UP_FROM_BACK if accelerometer_x_mps2 > 0.0 else Motion.STAND_UP_FROM_FRONT


def walk_command(vx: float, vy: float, omega: float) -> tuple[float, float, float]:
    """(vx, vy, omega) clipped to the walk limits."""
    return tuple(float(min(max(v, lo), hi)) for v, lo, hi in zip((vx, vy, omega), WALK_LOW, WALK_HIGH))


def clip_head(yaw_rad: float, pitch_rad: float) -> tuple[float, float]:
    return (
        min(max(yaw_rad, YAW_LIMITS_RAD[0]), YAW_LIMITS_RAD[1]),
        min(max(pitch_rad, PITCH_LIMITS_RAD[0]), PITCH_LIMITS_RAD[1]),
    )


def look_at(ball: BallPercept, camera: CameraPosition) -> tuple[float, float]:
    """Head (yaw, pitch) that centres the ball in ``camera`` (approximately; rad)."""
    mount = NAO_HEAD.mount(camera)
    height = NAO_HEAD.neck_height_m + mount.up_m - FIELD.ball_radius
    ahead = max(ball.distance_m - mount.forward_m, 0.01)
    return clip_head(ball.bearing_rad, math.atan2(height, ahead) - mount.pitch_rad)


def turn_toward(bearing_rad: float) -> tuple[float, float, float]:
    """Turn in place toward a bearing."""
    omega = TURN_GAIN_PER_S * bearing_rad
    return walk_command(0.0, 0.0, math.copysign(max(abs(omega), MIN_TURN_RADPS), bearing_rad))


def approach(ball: BallPercept) -> tuple[float, float, float]:
    """Walk forward to the ball: steer toward it, then, when near, side-step it in front of a foot."""
    vx = max(APPROACH_GAIN_PER_S * (ball.distance_m - APPROACH_STOP_M), MIN_APPROACH_MPS)
    if ball.distance_m >= ALIGN_WITHIN_M:
        return walk_command(vx, 0.0, TURN_GAIN_PER_S * ball.bearing_rad)
    foot = math.copysign(FOOT_OFFSET_M, ball.left_m)
    return walk_command(vx, ALIGN_GAIN_PER_S * (ball.left_m - foot), 0.0)


def orbit(ball: BallPercept, turn_rad: float) -> tuple[float, float, float]:
    """Side-step around the ball (vy opposite to omega) to turn by ``turn_rad`` while facing it."""
    omega = math.copysign(ORBIT_RADPS, turn_rad)
    vx = ORBIT_DISTANCE_GAIN_PER_S * (ball.distance_m - ORBIT_DISTANCE_M)
    return walk_command(vx, -omega * max(ball.distance_m, ORBIT_DISTANCE_M), omega + TURN_GAIN_PER_S * ball.bearing_rad)


def kick_for(ball: BallPercept) -> Motion:
    return Motion.KICK_LEFT if ball.left_m > 0.0 else Motion.KICK_RIGHT


def chase(ball: BallPercept, heading_error_rad: float) -> tuple[Motion, tuple[float, float, float]]:
    """Field player with the ball in sight: turn to it, walk to it, kick it toward the goal.

    ``heading_error_rad``: attacked direction minus estimated heading, normalized.
    """
    if abs(ball.bearing_rad) > TURN_IN_PLACE_RAD:
        return Motion.WALK, turn_toward(ball.bearing_rad)
    if ball.distance_m >= KICK_DISTANCE_M:
        return Motion.WALK, approach(ball)
    if abs(heading_error_rad) <= KICK_HEADING_TOLERANCE_RAD:
        return kick_for(ball), _STILL
    return Motion.WALK, orbit(ball, heading_error_rad)


def keep_goal(ball: BallPercept, heading_error_rad: float) -> tuple[Motion, tuple[float, float, float]]:
    """Goalkeeper with the ball in sight: side-step in front of it, kick it when it is close."""
    if ball.distance_m < KEEPER_KICK_DISTANCE_M and abs(ball.bearing_rad) < KEEPER_KICK_BEARING_RAD:
        return kick_for(ball), _STILL
    if ball.distance_m > KEEPER_REACT_DISTANCE_M:
        return Motion.STAND, _STILL
    omega = KEEPER_HEADING_GAIN_PER_S * heading_error_rad
    omega = min(max(omega, -KEEPER_MAX_TURN_RADPS), KEEPER_MAX_TURN_RADPS)
    return Motion.WALK, walk_command(0.0, KEEPER_SIDE_GAIN_PER_S * ball.left_m, omega)


@dataclass
class HeadSweep:
    """A triangular head-yaw sweep across +-SCAN_AMPLITUDE_RAD, counting its reversals."""

    yaw_rad: float = 0.0
    direction: float = 1.0
    reversals: int = 0

    def restart(self, yaw_rad: float, direction: float) -> None:
        self.yaw_rad = min(max(yaw_rad, -SCAN_AMPLITUDE_RAD), SCAN_AMPLITUDE_RAD)
        self.direction = 1.0 if direction >= 0.0 else -1.0
        self.reversals = 0

    def advance(self, rate_radps: float) -> float:
        """Move the yaw target one control step on; return it (rad)."""
        self.yaw_rad += self.direction * rate_radps * CONTROL_STEP_S
        if abs(self.yaw_rad) >= SCAN_AMPLITUDE_RAD:
            self.yaw_rad = math.copysign(SCAN_AMPLITUDE_RAD, self.yaw_rad)
            self.direction = -math.copysign(1.0, self.yaw_rad)
            self.reversals += 1
        return self.yaw_rad

    @property
    def swept(self) -> bool:
        return self.reversals >= FULL_SWEEP_REVERSALS


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
    """The scripted policy (:class:`match.protocol.policy.Policy`): ball chaser, or keeper as player 0.

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
        if obs.player == KEEPER_PLAYER:
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
