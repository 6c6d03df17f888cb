"""Observation and action spaces of one agent (gymnasium spaces).

Observation (a dict):

- ``image``: the 160x120 RGB camera image, uint8, rows top to bottom; zeros when the
  camera is off.
- ``head`` (yaw, pitch) rad; ``camera``: :class:`CameraChoice`.
- ``accelerometer`` m/s^2 (specific force, torso frame), ``gyro`` rad/s, ``sonar`` m
  (upper-left, upper-right, lower-left, lower-right), ``bumpers`` (left foot left/right,
  right foot left/right), ``fallen``.
- motion status: ``motion`` (index into :data:`MOTIONS`, ``len(MOTIONS)`` = none),
  ``motion_elapsed_s``, ``motion_remaining_s`` (capped at 1e6 for the endless walk),
  ``last_motion``, ``last_motion_sequence`` (increases by one per finished motion),
  ``last_motion_completed`` and ``odometry``: the nominal (forward m, left m, turn rad)
  of the last finished motion, in the robot frame at that motion's start.
- ``game``: the robot's view of the last game-control broadcast (``drop_in_team`` and
  ``seconds_since_drop_in``: who put the ball out before the last throw-in and how long ago
  the referee put it back, :data:`MAX_SECONDS` when there was none this half).
- ``radio``: the inbox (packets from teammates delivered this step) and ``dropped``, the
  number of the robot's own packets not sent since its last observation (over budget).

Action (a dict; missing keys take the defaults of :func:`match.protocol.actions.parse_action`):

- ``motion``: index into :data:`MOTIONS` (``walk`` uses ``walk``: vx, vy m/s, omega rad/s);
- ``head``: yaw, pitch targets (rad); ``camera``: :class:`CameraChoice`;
- ``radio``: a packet, :func:`match.protocol.packets.packet_space`: ``data``, 128 bytes
  (``Box(0, 255, (128,), uint8)``), of which the first ``length`` (``Discrete(129)``, 0: no
  packet) are sent; ``bytes`` of at most 128 are accepted too.

Every space is a standard gymnasium space (``Dict``, ``Box``, ``Discrete``, ``MultiBinary``),
so ``gymnasium.spaces.flatten_space``, ``gymnasium.vector.utils.iterate`` and shared-memory
vector envs work on them.
"""

from __future__ import annotations

import enum

import numpy as np
from gymnasium import spaces

from match.protocol.game_control import DropIn, GameState, KickOff, SecondaryState
from match.protocol.ids import MAX_PLAYERS_PER_TEAM
from match.protocol.packets import INBOX_CAPACITY, MAX_PACKET_BYTES, packet_space
from world.camera_model import NAO_CAMERA, NAO_HEAD, CameraPosition
from world.motions import Motion, WalkLimits

MOTIONS: tuple[Motion, ...] = tuple(Motion)
NO_MOTION = len(MOTIONS)  # index meaning "no motion" in observations
WALK_LIMITS = WalkLimits()

IMAGE_SHAPE = (NAO_CAMERA.height_px, NAO_CAMERA.width_px, 3)
ACCELEROMETER_LIMIT_MPS2 = 200.0
GYRO_LIMIT_RADPS = 100.0
SONAR_MAX_RANGE_M = 2.55
ODOMETRY_LIMIT = 10.0
MOTION_TIME_LIMIT_S = 1e6
MAX_SEQUENCE = 2**31 - 1
MAX_SCORE = 255
MAX_SECONDS = 1e5


class CameraChoice(enum.IntEnum):
    OFF = 0
    TOP = 1
    BOTTOM = 2

    @property
    def position(self) -> CameraPosition | None:
        """The camera position this choice switches to (None: off)."""
        return None if self is CameraChoice.OFF else CameraPosition[self.name]

    @classmethod
    def of(cls, position: CameraPosition) -> CameraChoice:
        return cls[position.name]


def _box(low, high, shape, dtype=np.float32) -> spaces.Box:
    low = np.broadcast_to(np.asarray(low, dtype), shape).copy()
    high = np.broadcast_to(np.asarray(high, dtype), shape).copy()
    return spaces.Box(low=low, high=high, shape=shape, dtype=dtype)


HEAD_LOW = (NAO_HEAD.yaw_limits_rad[0], NAO_HEAD.pitch_limits_rad[0])
HEAD_HIGH = (NAO_HEAD.yaw_limits_rad[1], NAO_HEAD.pitch_limits_rad[1])
WALK_LOW = (-WALK_LIMITS.max_backward_mps, -WALK_LIMITS.max_side_mps, -WALK_LIMITS.max_turn_radps)
WALK_HIGH = (WALK_LIMITS.max_forward_mps, WALK_LIMITS.max_side_mps, WALK_LIMITS.max_turn_radps)


def observation_space() -> spaces.Dict:
    """A new observation space (the same for every agent)."""
    game = spaces.Dict(
        {
            "state": spaces.Discrete(len(GameState)),
            "secondary": spaces.Discrete(len(SecondaryState)),
            "kickoff": spaces.Discrete(len(KickOff)),
            "score": _box(0, MAX_SCORE, (2,), np.int32),  # own, opponent
            "shootout_score": _box(0, MAX_SCORE, (2,), np.int32),
            "seconds_remaining": _box(0.0, MAX_SECONDS, ()),
            "half": spaces.Discrete(2, start=1),
            "team_color": spaces.Discrete(2),  # 0 blue, 1 red
            "defended_goal": spaces.Discrete(2),  # 0 blue (x = -3), 1 yellow (x = +3)
            "player": spaces.Discrete(MAX_PLAYERS_PER_TEAM),
            "drop_in_team": spaces.Discrete(len(DropIn)),  # who put the ball out before the last throw-in
            "seconds_since_drop_in": _box(0.0, MAX_SECONDS, ()),  # MAX_SECONDS: no throw-in this half
        }
    )
    radio = spaces.Dict(
        {
            "count": spaces.Discrete(INBOX_CAPACITY + 1),
            "sender": _box(0, MAX_PLAYERS_PER_TEAM - 1, (INBOX_CAPACITY,), np.int8),
            "length": _box(0, MAX_PACKET_BYTES, (INBOX_CAPACITY,), np.int16),
            "data": _box(0, 255, (INBOX_CAPACITY, MAX_PACKET_BYTES), np.uint8),
            "dropped": _box(0, MAX_SEQUENCE, (), np.int64),
        }
    )
    return spaces.Dict(
        {
            "image": _box(0, 255, IMAGE_SHAPE, np.uint8),
            "head": _box(HEAD_LOW, HEAD_HIGH, (2,)),
            "camera": spaces.Discrete(len(CameraChoice)),
            "accelerometer": _box(-ACCELEROMETER_LIMIT_MPS2, ACCELEROMETER_LIMIT_MPS2, (3,)),
            "gyro": _box(-GYRO_LIMIT_RADPS, GYRO_LIMIT_RADPS, (3,)),
            "sonar": _box(0.0, SONAR_MAX_RANGE_M, (4,)),
            "bumpers": spaces.MultiBinary(4),
            "fallen": spaces.Discrete(2),
            "motion": spaces.Discrete(len(MOTIONS) + 1),
            "motion_elapsed_s": _box(0.0, MOTION_TIME_LIMIT_S, ()),
            "motion_remaining_s": _box(0.0, MOTION_TIME_LIMIT_S, ()),
            "last_motion": spaces.Discrete(len(MOTIONS) + 1),
            "last_motion_sequence": _box(0, MAX_SEQUENCE, (), np.int64),
            "last_motion_completed": spaces.Discrete(2),
            "odometry": _box(-ODOMETRY_LIMIT, ODOMETRY_LIMIT, (3,)),
            "game": game,
            "radio": radio,
        }
    )


def action_space() -> spaces.Dict:
    """A new action space (the same for every agent)."""
    return spaces.Dict(
        {
            "motion": spaces.Discrete(len(MOTIONS)),
            "walk": _box(WALK_LOW, WALK_HIGH, (3,)),
            "head": _box(HEAD_LOW, HEAD_HIGH, (2,)),
            "camera": spaces.Discrete(len(CameraChoice)),
            "radio": packet_space(),
        }
    )
