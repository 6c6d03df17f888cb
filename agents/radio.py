"""The team radio's packet format: one codec for the built-in policies' messages.

A packet is a header and the blocks its flags name, little-endian, in this order (the radio
carries at most :data:`match.protocol.MAX_PACKET_BYTES` per packet, one packet per robot per 0.2 s):

=============  ======  ======================================================================
block (flag)   bytes   fields
=============  ======  ======================================================================
header         5       magic ``RS``, format :data:`VERSION`, the sender's player number, flags
POSE           8       the pose (field frame): x, y (mm, int16), theta (1e-4 rad, int16),
                       its sigmas (cm, deg; uint8)
BALL           11      the ball (field frame): x, y (mm), vx, vy (mm/s; int16), sigma (cm,
                       uint8), age (ms, uint16)
BALL_RELATIVE  8       the ball in the sender's torso frame: distance (m), bearing (rad; float32)
PLAY           6       sequence (uint16), role code (:data:`ROLE_CODES`), intention, time to
                       the ball (ms, uint16; 65535: none)
FALLEN         0       lying or standing up
=============  ======  ======================================================================

A block is left out when its fields hold their defaults (no pose, no ball, no play), so a robot
that localizes (the ``team`` agent) sends its pose, its field ball and its play, and one that does
not (the ``scripted`` player) only where it sees the ball from itself. Values are clipped to what
the layout holds. Decoding never raises on what arrives: a packet that is not bytes, has another
magic (another team's format), a version this code does not know, a length its flags do not give,
or values out of range is ignored and counted by its reason in a :class:`DecodeStats`.
"""

from __future__ import annotations

import enum
import math
import struct
from collections import Counter
from dataclasses import dataclass, field

MAGIC = b"RS"
VERSION = 2
MAX_PLAYER = 3

_HEADER = struct.Struct("<2sBBB")  # magic, version, player, flags
_POSE = struct.Struct("<hhhBB")
_BALL = struct.Struct("<hhhhBH")
_BALL_RELATIVE = struct.Struct("<ff")
_PLAY = struct.Struct("<HBBH")

_MM = 1000.0
_THETA_UNITS = 1e4
_INT16 = 32767
_UINT8 = 255
_UINT16 = 65535
_FLOAT32_MAX = 3.4028234663852886e38


class Role:
    """The built-in roles' names (section 8.1 of the thesis lists roles as future work). A role is its
    name (a str) everywhere but on the radio, which carries its code (:data:`ROLE_CODES`)."""

    NONE = "none"
    GOALKEEPER = "goalkeeper"
    STRIKER = "striker"
    SUPPORTER = "supporter"
    DEFENDER = "defender"


# The radio's role codes. A new role takes a free code here (register_role_code).
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


_INTENTIONS: dict[int, Intention] = {int(i): i for i in Intention}


class Flag(enum.IntFlag):
    """The header's flags: which blocks follow (FALLEN has none)."""

    POSE = 1
    BALL = 2
    FALLEN = 4
    BALL_RELATIVE = 8
    PLAY = 16


_BLOCKS = ((int(Flag.POSE), _POSE.size), (int(Flag.BALL), _BALL.size), (int(Flag.BALL_RELATIVE), _BALL_RELATIVE.size),
           (int(Flag.PLAY), _PLAY.size))
_KNOWN_FLAGS = int(Flag.POSE | Flag.BALL | Flag.FALLEN | Flag.BALL_RELATIVE | Flag.PLAY)
MAX_MESSAGE_BYTES = _HEADER.size + sum(size for _, size in _BLOCKS)


@dataclass(frozen=True)
class TeamMessage:
    """One robot's report. Positions m, velocities m/s, angles rad, ages and times s.

    ``pose`` and ``ball_xy`` (field frame) are None when the sender has no estimate; ``*_sigma_*``
    are one standard deviation; ``ball_age_s``: time since the sender last saw the ball itself or
    heard of it; ``ball_relative``: the ball it sees, (distance m, bearing rad) in its torso frame
    (None: not seen lately; a sender without a pose reports this); ``time_to_ball_s``: its own estimate
    of how long it needs to reach the ball (the role assignment compares these); ``fallen``: lying or
    standing up (teammates then leave it out of the role assignment and the team ball).
    """

    player: int
    sequence: int = 0
    pose: tuple[float, float, float] | None = None
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
    ball_relative: tuple[float, float] | None = None

    def encode(self) -> bytes:
        """The packet (at most :data:`MAX_MESSAGE_BYTES`); values are clipped to what the layout holds."""
        flags, blocks = 0, []
        if self.pose is not None:
            flags |= Flag.POSE.value
            theta = _clip_int(round(math.remainder(self.pose[2], math.tau) * _THETA_UNITS), -_INT16, _INT16)
            blocks.append(_POSE.pack(_mm(self.pose[0]), _mm(self.pose[1]), theta,
                                     _unsigned(self.pose_sigma_m * 100.0, _UINT8),
                                     _unsigned(math.degrees(self.pose_sigma_rad), _UINT8)))
        if self.ball_xy is not None:
            flags |= Flag.BALL.value
            blocks.append(_BALL.pack(_mm(self.ball_xy[0]), _mm(self.ball_xy[1]), _mm(self.ball_velocity[0]),
                                     _mm(self.ball_velocity[1]), _unsigned(self.ball_sigma_m * 100.0, _UINT8),
                                     _unsigned(self.ball_age_s * 1000.0, _UINT16)))
        if self.ball_relative is not None:
            flags |= Flag.BALL_RELATIVE.value
            blocks.append(_BALL_RELATIVE.pack(*(_float32(v) for v in self.ball_relative)))
        sequence = self.sequence % (_UINT16 + 1)
        if sequence or self.role != Role.NONE or self.intention is not Intention.NONE or self.time_to_ball_s != math.inf:
            flags |= Flag.PLAY.value
            blocks.append(_PLAY.pack(sequence, ROLE_CODES[self.role], int(self.intention),
                                     _unsigned(self.time_to_ball_s * 1000.0, _UINT16)))
        if self.fallen:
            flags |= Flag.FALLEN.value
        return b"".join((_HEADER.pack(MAGIC, VERSION, self.player, flags), *blocks))


@dataclass
class DecodeStats:
    """How many packets were read, and how many ignored by reason."""

    decoded: int = 0
    ignored: Counter = field(default_factory=Counter)

    def to_json(self) -> dict:
        return {"decoded": self.decoded, "ignored": dict(sorted(self.ignored.items()))}


def decode(data: bytes, stats: DecodeStats | None = None) -> TeamMessage | None:
    """The message in a packet, or None (counted in ``stats`` by reason) when it is not one of ours."""
    reason, fields = _check(data), {}
    if reason is None:
        reason = _read(bytes(data), fields)
    if reason is not None:
        if stats is not None:
            stats.ignored[reason] += 1
        return None
    if stats is not None:
        stats.decoded += 1
    return TeamMessage(**fields)


def _check(data: object) -> str | None:
    if not isinstance(data, (bytes, bytearray, memoryview)):
        return "not bytes"
    if len(data) < _HEADER.size or bytes(data[:2]) != MAGIC:
        return "another format"
    if data[2] != VERSION:
        return "unknown version"
    flags = data[4]
    if flags & ~_KNOWN_FLAGS:
        return "unknown flags"
    if len(data) != _HEADER.size + sum(size for flag, size in _BLOCKS if flags & flag):
        return "wrong length"
    return None


def _read(data: bytes, fields: dict) -> str | None:
    """The fields of a packet of the right layout into ``fields``; the reason it is not ours, or None."""
    _, _, player, flags = _HEADER.unpack_from(data)
    if player > MAX_PLAYER:
        return "player out of range"
    fields.update(player=player, fallen=bool(flags & Flag.FALLEN.value))
    offset = _HEADER.size
    if flags & Flag.POSE.value:
        x, y, theta, sigma_cm, sigma_deg = _POSE.unpack_from(data, offset)
        offset += _POSE.size
        fields.update(pose=(x / _MM, y / _MM, theta / _THETA_UNITS), pose_sigma_m=sigma_cm / 100.0,
                      pose_sigma_rad=math.radians(sigma_deg))
    if flags & Flag.BALL.value:
        bx, by, bvx, bvy, sigma_cm, age_ms = _BALL.unpack_from(data, offset)
        offset += _BALL.size
        fields.update(ball_xy=(bx / _MM, by / _MM), ball_velocity=(bvx / _MM, bvy / _MM), ball_sigma_m=sigma_cm / 100.0,
                      ball_age_s=age_ms / 1000.0)
    if flags & Flag.BALL_RELATIVE.value:
        distance, bearing = _BALL_RELATIVE.unpack_from(data, offset)
        offset += _BALL_RELATIVE.size
        if not (math.isfinite(distance) and math.isfinite(bearing)):
            return "values out of range"
        fields["ball_relative"] = (distance, bearing)
    if flags & Flag.PLAY.value:
        sequence, role, intention, to_ball_ms = _PLAY.unpack_from(data, offset)
        if role not in _ROLE_NAMES or intention not in _INTENTIONS:
            return "unknown role or intention"
        fields.update(sequence=sequence, role=_ROLE_NAMES[role], intention=_INTENTIONS[intention],
                      time_to_ball_s=math.inf if to_ball_ms == _UINT16 else to_ball_ms / 1000.0)
    return None


def _clip_int(value: float, low: int, high: int) -> int:
    if not math.isfinite(value):
        return high if value > 0 else low
    return int(min(max(value, low), high))


def _float32(value: float) -> float:
    """``value`` clipped to a float32's range (inf and nan pass, and the decoder refuses them)."""
    return min(max(value, -_FLOAT32_MAX), _FLOAT32_MAX) if math.isfinite(value) else value


def _mm(metres: float) -> int:
    return _clip_int(round(metres * _MM) if math.isfinite(metres) else metres, -_INT16, _INT16)


def _unsigned(value: float, high: int) -> int:
    return _clip_int(round(value) if math.isfinite(value) else value, 0, high)
