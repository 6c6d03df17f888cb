"""The team message: what a robot tells its teammates over the radio, in 30 bytes.

A compact, versioned, little-endian binary layout (the radio carries at most 128 bytes per
packet, one packet per robot per 0.2 s). Field frame (m, rad; see docs/design.md section
3); the sender's own estimates with their uncertainty (one standard deviation) and age.

Decoding never raises on what arrives: a packet that is too short or too long, has another
magic (another team's format), a version this code does not know, or values out of range
is ignored and counted by its reason in a :class:`DecodeStats`.
"""

from __future__ import annotations

import enum
import math
import struct
from collections import Counter
from dataclasses import dataclass, field

MAGIC = b"RS"
VERSION = 1
# magic, version, player, flags, sequence, pose x/y (mm), theta (1e-4 rad), pose sigma (cm, deg),
# ball x/y (mm), ball vx/vy (mm/s), ball sigma (cm), ball age (ms), role, intention, time to ball (ms)
_LAYOUT = struct.Struct("<2sBBBHhhhBBhhhhBHBBH")
MESSAGE_BYTES = _LAYOUT.size

_MM = 1000.0
_THETA_UNITS = 1e4
_INT16 = 32767
_UINT8 = 255
_UINT16 = 65535


class Role:
    """The built-in roles' names (section 8.1 of the thesis lists roles as future work). A role is its
    name (a str) everywhere but on the radio, which carries its code (:data:`ROLE_CODES`)."""

    NONE = "none"
    GOALKEEPER = "goalkeeper"
    STRIKER = "striker"
    SUPPORTER = "supporter"
    DEFENDER = "defender"


# The radio's role codes (format version 1). A new role takes a free code here (register_role_code).
ROLE_CODES: dict[str, int] = {Role.NONE: 0, Role.GOALKEEPER: 1, Role.STRIKER: 2, Role.SUPPORTER: 3, Role.DEFENDER: 4}
_ROLE_NAMES: dict[int, str] = {code: name for name, code in ROLE_CODES.items()}


def register_role_code(name: str, code: int) -> None:
    """Give the role ``name`` the radio code ``code`` (0-255); a code or name taken otherwise is refused."""
    if not 0 <= code <= _UINT8 or _ROLE_NAMES.get(code, name) != name or ROLE_CODES.get(name, code) != code:
        raise ValueError(f"role {name!r}: code {code} is taken or out of range 0-{_UINT8} ({ROLE_CODES})")
    ROLE_CODES[name] = code
    _ROLE_NAMES[code] = name


class Intention(enum.IntEnum):
    """What the robot is about to do, so that teammates can keep out of its way."""

    NONE = 0
    GO_TO_BALL = 1
    KICK = 2
    POSITION = 3
    SEARCH = 4
    RECOVER = 5  # fallen, standing up or replaced


class Flag(enum.IntFlag):
    POSE = 1  # the pose fields hold an estimate
    BALL = 2  # the ball fields hold an estimate
    FALLEN = 4


@dataclass(frozen=True)
class TeamMessage:
    """One robot's report. Positions m, velocities m/s, angles rad, ages and times s.

    ``pose`` and ``ball_xy`` are None when the sender has no estimate; ``*_sigma_*`` are
    one standard deviation; ``ball_age_s``: time since the sender last saw the ball itself
    or heard of it; ``time_to_ball_s``: its own estimate of how long it needs to reach the
    ball (the role assignment compares these); ``fallen``: lying or standing up (teammates then
    leave it out of the role assignment and the team ball).
    """

    player: int
    sequence: int
    pose: tuple[float, float, float] | None
    pose_sigma_m: float = 0.0
    pose_sigma_rad: float = 0.0
    ball_xy: tuple[float, float] | None = None
    ball_velocity: tuple[float, float] = (0.0, 0.0)
    ball_sigma_m: float = 0.0
    ball_age_s: float = 0.0
    fallen: bool = False
    role: str = Role.NONE
    intention: Intention = Intention.NONE
    time_to_ball_s: float = math.inf

    def encode(self) -> bytes:
        """The packet (:data:`MESSAGE_BYTES` bytes); values are clipped to what the layout holds."""
        flags = Flag(0)
        x = y = theta = 0
        if self.pose is not None:
            flags |= Flag.POSE
            x, y = _mm(self.pose[0]), _mm(self.pose[1])
            theta = _clip_int(round(math.remainder(self.pose[2], math.tau) * _THETA_UNITS), -_INT16, _INT16)
        bx = by = bvx = bvy = 0
        if self.ball_xy is not None:
            flags |= Flag.BALL
            bx, by = _mm(self.ball_xy[0]), _mm(self.ball_xy[1])
            bvx, bvy = _mm(self.ball_velocity[0]), _mm(self.ball_velocity[1])
        if self.fallen:
            flags |= Flag.FALLEN
        return _LAYOUT.pack(
            MAGIC,
            VERSION,
            self.player,
            int(flags),
            self.sequence % (_UINT16 + 1),
            x,
            y,
            theta,
            _unsigned(self.pose_sigma_m * 100.0, _UINT8),
            _unsigned(math.degrees(self.pose_sigma_rad), _UINT8),
            bx,
            by,
            bvx,
            bvy,
            _unsigned(self.ball_sigma_m * 100.0, _UINT8),
            _unsigned(self.ball_age_s * 1000.0, _UINT16),
            ROLE_CODES[self.role],
            int(self.intention),
            _unsigned(self.time_to_ball_s * 1000.0, _UINT16),
        )


@dataclass
class DecodeStats:
    """How many packets were read, and how many ignored by reason."""

    decoded: int = 0
    ignored: Counter = field(default_factory=Counter)

    def to_json(self) -> dict:
        return {"decoded": self.decoded, "ignored": dict(sorted(self.ignored.items()))}


def decode(data: bytes, stats: DecodeStats | None = None) -> TeamMessage | None:
    """The message in a packet, or None (counted in ``stats`` by reason) when it is not one of ours."""
    reason = _check(data)
    if reason is None:
        fields = _LAYOUT.unpack(data)
        (_, _, player, flags, sequence, x, y, theta, pose_cm, pose_deg, bx, by, bvx, bvy, ball_cm, age_ms, role,
         intention, to_ball_ms) = fields
        if player > 3:
            reason = "player out of range"
        elif role not in _ROLE_NAMES or intention not in Intention._value2member_map_:
            reason = "unknown role or intention"
        elif flags & ~int(Flag.POSE | Flag.BALL | Flag.FALLEN):
            reason = "unknown flags"
    if reason is not None:
        if stats is not None:
            stats.ignored[reason] += 1
        return None
    if stats is not None:
        stats.decoded += 1
    has_pose, has_ball = bool(flags & Flag.POSE), bool(flags & Flag.BALL)
    return TeamMessage(
        player=player,
        sequence=sequence,
        pose=(x / _MM, y / _MM, theta / _THETA_UNITS) if has_pose else None,
        pose_sigma_m=pose_cm / 100.0,
        pose_sigma_rad=math.radians(pose_deg),
        ball_xy=(bx / _MM, by / _MM) if has_ball else None,
        ball_velocity=(bvx / _MM, bvy / _MM) if has_ball else (0.0, 0.0),
        ball_sigma_m=ball_cm / 100.0,
        ball_age_s=age_ms / 1000.0,
        fallen=bool(flags & Flag.FALLEN),
        role=_ROLE_NAMES[role],
        intention=Intention(intention),
        time_to_ball_s=math.inf if to_ball_ms == _UINT16 else to_ball_ms / 1000.0,
    )


def _check(data: object) -> str | None:
    if not isinstance(data, (bytes, bytearray, memoryview)):
        return "not bytes"
    if len(data) < 3 or bytes(data[:2]) != MAGIC:
        return "another format"
    if data[2] != VERSION:
        return "unknown version"
    if len(data) != MESSAGE_BYTES:
        return "wrong length"
    return None


def _clip_int(value: float, low: int, high: int) -> int:
    if not math.isfinite(value):
        return high if value > 0 else low
    return int(min(max(value, low), high))


def _mm(metres: float) -> int:
    return _clip_int(round(metres * _MM) if math.isfinite(metres) else metres, -_INT16, _INT16)


def _unsigned(value: float, high: int) -> int:
    return _clip_int(round(value) if math.isfinite(value) else value, 0, high)
