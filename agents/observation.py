"""One typed, frozen view of an agent's observation, decoded once per step and read by every agent.

The match hands each policy an observation dict laid out as
:func:`match.protocol.observation_space`; :meth:`Observation.of` turns it into this view
(plain Python numbers, enums and tuples, the image kept as it is). Units: metres, seconds,
radians; readings in the torso frame (x forward, y left, z up); head yaw CCW positive, head
pitch positive looking down.
"""

from __future__ import annotations

import enum
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, TypeVar

import numpy as np

from match.protocol import (
    MAX_SECONDS,
    MOTIONS,
    CameraChoice,
    Displacement,
    DropIn,
    GameControlView,
    GameState,
    GoalColor,
    KickOff,
    Motion,
    SecondaryState,
    TeamColor,
)
from world.camera_model import CameraPosition

E = TypeVar("E", bound=enum.Enum)


class ObservationError(ValueError):
    """An observation that does not have the layout of the observation space; names the key."""


@dataclass(frozen=True)
class RadioPacket:
    """One packet from a teammate, received this step: the sender's player number and the bytes."""

    sender: int
    data: bytes


@dataclass(frozen=True, eq=False)
class Observation:
    """What one robot sensed in one control step.

    ``image``: 120x160x3 RGB uint8, None when the camera is off; ``camera``: which camera
    took it. ``motion``: the motion playing now (None when idle); ``last_motion`` with
    ``last_motion_sequence`` (grows by one per finished motion) and ``odometry``: the last
    finished motion and its nominal displacement (its robot frame at the motion's start).
    ``packets``: teammates' radio packets delivered this step; ``packets_dropped``: this
    robot's packets the radio refused so far.
    """

    image: np.ndarray | None
    camera: CameraChoice
    head_yaw_rad: float
    head_pitch_rad: float
    accelerometer_mps2: tuple[float, float, float]  # specific force, about (0, 0, 9.81) upright
    gyro_radps: tuple[float, float, float]
    sonar_m: tuple[float, ...]
    bumpers: tuple[bool, ...]
    fallen: bool
    motion: Motion | None
    motion_elapsed_s: float
    motion_remaining_s: float
    last_motion: Motion | None
    last_motion_sequence: int
    last_motion_completed: bool
    odometry: Displacement
    game: GameControlView  # the referee's last broadcast as this robot's team reads it
    player: int  # this robot's number, 0 the goalkeeper
    packets: tuple[RadioPacket, ...]
    packets_dropped: int

    @classmethod
    def of(cls, observation: Observation | Mapping[str, Any]) -> Observation:
        """The view of an observation dict (an :class:`Observation` is returned as it is)."""
        if isinstance(observation, Observation):
            return observation
        if not isinstance(observation, Mapping):
            raise ObservationError(f"an observation must be a dict; got {type(observation).__name__}")
        try:
            return _decode(observation)
        except ObservationError:
            raise
        except KeyError as error:
            raise ObservationError(f"observation lacks the key {error.args[0]!r}") from None
        except (TypeError, ValueError, IndexError) as error:
            raise ObservationError(f"observation does not fit the observation space: {error}") from None

    @property
    def camera_position(self) -> CameraPosition | None:
        """The position of the camera that took ``image`` (None when the camera is off)."""
        return self.camera.position


def _motion(index: int) -> Motion | None:
    return MOTIONS[index] if 0 <= index < len(MOTIONS) else None


def _member(kind: type[E], value: int) -> E:
    """``kind(value)`` by a look-up of the value (a call of an enum class costs more, five times a step);
    ValueError as the call raises it."""
    try:
        return kind._value2member_map_[value]  # type: ignore[return-value]
    except KeyError:
        raise ValueError(f"{value!r} is not a valid {kind.__qualname__}") from None


def _floats(values: Any) -> tuple[float, ...]:
    return tuple(np.asarray(values, dtype=np.float64).reshape(-1).tolist())


def _decode(obs: Mapping[str, Any]) -> Observation:
    camera = _member(CameraChoice, int(obs["camera"]))
    head = _floats(obs["head"])
    if len(head) != 2:
        raise ObservationError(f"observation head must be (yaw, pitch); got {list(head)}")
    accelerometer = _floats(obs["accelerometer"])
    gyro = _floats(obs["gyro"])
    if len(accelerometer) != 3 or len(gyro) != 3:
        raise ObservationError(f"accelerometer and gyro must have 3 axes; got {accelerometer}, {gyro}")
    forward, left, turn = _floats(obs["odometry"])
    game = obs["game"]
    radio = obs["radio"]
    return Observation(
        image=None if camera is CameraChoice.OFF else obs["image"],
        camera=camera,
        head_yaw_rad=head[0],
        head_pitch_rad=head[1],
        accelerometer_mps2=accelerometer,  # type: ignore[arg-type]
        gyro_radps=gyro,  # type: ignore[arg-type]
        sonar_m=_floats(obs["sonar"]),
        bumpers=tuple(np.asarray(obs["bumpers"], dtype=bool).reshape(-1).tolist()),
        fallen=int(obs["fallen"]) == 1,
        motion=_motion(int(obs["motion"])),
        motion_elapsed_s=float(obs["motion_elapsed_s"]),
        motion_remaining_s=float(obs["motion_remaining_s"]),
        last_motion=_motion(int(obs["last_motion"])),
        last_motion_sequence=int(obs["last_motion_sequence"]),
        last_motion_completed=int(obs["last_motion_completed"]) == 1,
        odometry=Displacement(forward, left, turn),
        game=_game(game),
        player=int(game["player"]),
        packets=_packets(radio),
        packets_dropped=int(radio["dropped"]),
    )


def _game(game: Mapping[str, Any]) -> GameControlView:
    score = np.asarray(game["score"]).reshape(-1)
    shootout = np.asarray(game["shootout_score"]).reshape(-1)
    return GameControlView(
        state=_member(GameState, int(game["state"])),
        secondary=_member(SecondaryState, int(game["secondary"])),
        kickoff=_member(KickOff, int(game["kickoff"])),
        own_score=int(score[0]),
        opponent_score=int(score[1]),
        own_shootout_score=int(shootout[0]),
        opponent_shootout_score=int(shootout[1]),
        seconds_remaining=float(game["seconds_remaining"]),
        half=int(game["half"]),
        team_color=TeamColor.BLUE if int(game["team_color"]) == 0 else TeamColor.RED,
        defended_goal=GoalColor.BLUE if int(game["defended_goal"]) == 0 else GoalColor.YELLOW,
        drop_in_team=_member(DropIn, int(game["drop_in_team"])),
        seconds_since_drop_in=_seconds_since_drop_in(float(game["seconds_since_drop_in"])),
    )


def _seconds_since_drop_in(seconds: float) -> float:
    """The observation's clipped figure back to the view's: inf when there was no throw-in this half."""
    return math.inf if seconds >= MAX_SECONDS else seconds


def _packets(radio: Mapping[str, Any]) -> tuple[RadioPacket, ...]:
    packets = []
    for i in range(int(radio["count"])):
        length = int(radio["length"][i])
        data = np.asarray(radio["data"][i][:length], dtype=np.uint8).tobytes()
        packets.append(RadioPacket(int(radio["sender"][i]), data))
    return tuple(packets)
