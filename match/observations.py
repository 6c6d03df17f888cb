"""Build one agent's observation dict (the layout of :func:`match.protocol.observation_space`)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from match.protocol import spaces as sp
from match.protocol.game_control import GameControlView
from match.protocol.packets import INBOX_CAPACITY, MAX_PACKET_BYTES
from match.radio import RadioMessage
from world.field import GoalColor
from world.sensors import SensorReading
from world.teams import TeamColor

_MOTION_INDEX = {m: i for i, m in enumerate(sp.MOTIONS)}


def blank_image() -> np.ndarray:
    return np.zeros(sp.IMAGE_SHAPE, dtype=np.uint8)


def game_observation(view: GameControlView, player: int) -> dict:
    return {
        "state": int(view.state),
        "secondary": int(view.secondary),
        "kickoff": int(view.kickoff),
        "score": _clip(np.array([view.own_score, view.opponent_score], dtype=np.int32), 0, sp.MAX_SCORE),
        "shootout_score": _clip(
            np.array([view.own_shootout_score, view.opponent_shootout_score], dtype=np.int32), 0, sp.MAX_SCORE
        ),
        "seconds_remaining": np.array(min(max(view.seconds_remaining, 0.0), sp.MAX_SECONDS), dtype=np.float32),
        "half": int(view.half),
        "team_color": 0 if view.team_color is TeamColor.BLUE else 1,
        "defended_goal": 0 if view.defended_goal is GoalColor.BLUE else 1,
        "player": int(player),
        "drop_in_team": int(view.drop_in_team),
        "seconds_since_drop_in": np.array(min(max(view.seconds_since_drop_in, 0.0), sp.MAX_SECONDS), dtype=np.float32),
    }


def radio_observation(messages: Sequence[RadioMessage], dropped: int) -> dict:
    sender = np.zeros(INBOX_CAPACITY, dtype=np.int8)
    length = np.zeros(INBOX_CAPACITY, dtype=np.int16)
    data = np.zeros((INBOX_CAPACITY, MAX_PACKET_BYTES), dtype=np.uint8)
    for i, message in enumerate(messages[:INBOX_CAPACITY]):
        sender[i] = message.sender.player
        length[i] = len(message.data)
        data[i, : len(message.data)] = np.frombuffer(message.data, dtype=np.uint8)
    return {
        "count": min(len(messages), INBOX_CAPACITY),
        "sender": sender,
        "length": length,
        "data": data,
        "dropped": np.array(min(dropped, sp.MAX_SEQUENCE), dtype=np.int64),
    }


def build_observation(
    reading: SensorReading,
    image: np.ndarray | None,
    game: dict,
    radio: dict,
) -> dict:
    """``image`` None means the camera is off (the observation carries zeros)."""
    motion = reading.motion
    finished = motion.last_finished
    if finished is None:
        odometry = np.zeros(3, dtype=np.float32)
        last_motion, sequence, completed = sp.NO_MOTION, 0, 0
    else:
        nominal = finished.nominal
        odometry = np.array([nominal.forward_m, nominal.left_m, nominal.turn_rad], dtype=np.float32)
        last_motion, sequence, completed = _MOTION_INDEX[finished.motion], finished.sequence, int(finished.completed)
    head = np.array([reading.head_yaw_rad, reading.head_pitch_rad], dtype=np.float32)
    return {
        "image": blank_image() if image is None else image,
        "head": _clip(head, np.float32(sp.HEAD_LOW), np.float32(sp.HEAD_HIGH)),
        "camera": int(sp.CameraChoice.OFF if image is None else sp.CameraChoice.of(reading.camera)),
        "accelerometer": _clipped(reading.accelerometer_mps2, sp.ACCELEROMETER_LIMIT_MPS2),
        "gyro": _clipped(reading.gyro_radps, sp.GYRO_LIMIT_RADPS),
        "sonar": _clip(np.array(reading.sonar_m, dtype=np.float32), 0.0, sp.SONAR_MAX_RANGE_M),
        "bumpers": np.array(reading.bumpers, dtype=np.int8),
        "fallen": int(reading.fallen),
        "motion": sp.NO_MOTION if motion.current is None else _MOTION_INDEX[motion.current],
        "motion_elapsed_s": np.array(min(max(motion.elapsed_s, 0.0), sp.MOTION_TIME_LIMIT_S), dtype=np.float32),
        "motion_remaining_s": np.array(min(max(motion.remaining_s, 0.0), sp.MOTION_TIME_LIMIT_S), dtype=np.float32),
        "last_motion": last_motion,
        "last_motion_sequence": np.array(min(sequence, sp.MAX_SEQUENCE), dtype=np.int64),
        "last_motion_completed": completed,
        "odometry": _clip(odometry, -sp.ODOMETRY_LIMIT, sp.ODOMETRY_LIMIT),
        "game": game,
        "radio": radio,
    }


def _clipped(values: Sequence[float], limit: float) -> np.ndarray:
    return _clip(np.array(values, dtype=np.float32), -limit, limit)


def _clip(values: np.ndarray, low, high) -> np.ndarray:
    """``np.clip(values, low, high)`` (the same values and dtype) without its per-call overhead: these
    arrays have two or three elements, and every robot's observation clips several every step."""
    return np.minimum(np.maximum(values, low), high)
