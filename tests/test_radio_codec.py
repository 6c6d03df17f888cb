"""The radio codec (agents.radio): round trip, size, the blocks a message leaves out, and packets that are
not ours."""

from __future__ import annotations

import math
import struct

from hypothesis import given
from hypothesis import strategies as st

from agents.radio import (
    MAX_MESSAGE_BYTES,
    ROLE_CODES,
    VERSION,
    DecodeStats,
    Intention,
    Role,
    TeamMessage,
    decode,
)
from match.protocol import MAX_PACKET_BYTES

coordinate = st.floats(-4.0, 4.0)
angle = st.floats(-math.pi + 1e-3, math.pi - 1e-3)


@given(
    player=st.integers(0, 3),
    pose=st.none() | st.tuples(coordinate, coordinate, angle),
    ball=st.none() | st.tuples(coordinate, coordinate),
    velocity=st.tuples(st.floats(-5, 5), st.floats(-5, 5)),
    sigma=st.floats(0.0, 2.5),
    age=st.floats(0.0, 60.0),
    role=st.sampled_from(sorted(ROLE_CODES)),
    intention=st.sampled_from(Intention),
    to_ball=st.floats(0.0, 60.0),
    fallen=st.booleans(),
)
def test_round_trip_keeps_every_field_to_its_resolution(player, pose, ball, velocity, sigma, age, role, intention,
                                                        to_ball, fallen) -> None:
    message = TeamMessage(player, 9, pose, sigma, sigma / 10, ball, velocity, sigma, age, fallen, role, intention,
                          to_ball)
    data = message.encode()
    assert len(data) <= MAX_MESSAGE_BYTES <= MAX_PACKET_BYTES
    back = decode(data)
    assert back is not None
    assert (back.player, back.role, back.intention, back.fallen) == (player, role, intention, fallen)
    if pose is None:
        assert back.pose is None
    else:
        assert all(abs(a - b) <= 6e-4 for a, b in zip(back.pose, pose))
    if ball is None:
        assert back.ball_xy is None
    else:
        assert all(abs(a - b) <= 6e-4 for a, b in zip(back.ball_xy, ball))
        assert all(abs(a - b) <= 6e-4 for a, b in zip(back.ball_velocity, velocity))
    assert abs(back.time_to_ball_s - to_ball) <= 6e-4
    if ball is not None:  # a message without a ball leaves its block out, its age and sigma with it
        assert abs(back.ball_age_s - age) <= 6e-4 and abs(back.ball_sigma_m - sigma) <= 0.006


def test_out_of_range_values_are_clipped_not_wrapped() -> None:
    message = TeamMessage(1, 70_000, (50.0, -50.0, 7.0), math.inf, 9.0, (math.nan, 1.0), (99.0, -99.0), -1.0,
                          1e9, time_to_ball_s=math.inf)
    back = decode(message.encode())
    assert back.pose[0] == 32.767 and back.pose[1] == -32.767
    assert back.pose[2] == math.remainder(7.0, math.tau).__round__(4)
    assert back.ball_velocity == (32.767, -32.767) and back.ball_sigma_m == 0.0
    assert back.ball_age_s == 65.535 and back.time_to_ball_s == math.inf and back.sequence == 70_000 % 65536


def test_packets_that_are_not_ours_are_ignored_and_counted() -> None:
    good = TeamMessage(1, 1, (0.0, 0.0, 0.0)).encode()
    future = good[:2] + bytes([VERSION + 1]) + good[3:]
    bad_player = good[:3] + bytes([9]) + good[4:]
    bad_role = good[:-4] + bytes([77]) + good[-3:]
    bad_flags = good[:4] + bytes([good[4] | 128]) + good[5:]
    not_finite = TeamMessage(1, ball_relative=(math.nan, 0.0)).encode()
    stats = DecodeStats()
    for packet in (b"", b"R", good[:-1], good + b"\0", b"\x01" + bytes(8), future, bad_player, bad_role, bad_flags,
                   not_finite, "text", None):
        assert decode(packet, stats) is None
    assert decode(good, stats) is not None
    assert stats.decoded == 1
    assert stats.ignored == {
        "another format": 3, "wrong length": 2, "unknown version": 1, "player out of range": 1,
        "unknown role or intention": 1, "unknown flags": 1, "values out of range": 1, "not bytes": 2,
    }


def test_a_message_leaves_out_the_blocks_that_hold_their_defaults() -> None:
    """A player without a pose (the scripted one) sends its own ball from itself in 13 bytes, or the header
    alone; the team agent's report with a pose, a ball and its play is 30 bytes."""
    seen = TeamMessage(2, ball_relative=(1.25, -0.5)).encode()
    unseen = TeamMessage(2).encode()
    assert (len(seen), len(unseen)) == (13, 5)
    back = decode(seen)
    assert back.ball_relative == (1.25, -0.5) and back.pose is None and back.ball_xy is None
    assert (back.role, back.intention, back.time_to_ball_s, back.sequence) == (Role.NONE, Intention.NONE, math.inf, 0)
    assert decode(unseen) == TeamMessage(2)
    full = TeamMessage(1, 7, (1.0, 2.0, 0.5), 0.1, 0.05, (0.5, 0.5), (0.0, 0.0), 0.2, 1.0, role=Role.STRIKER,
                       intention=Intention.KICK, time_to_ball_s=2.0)
    assert len(full.encode()) == 30 and len(TeamMessage(1, 7, (1.0, 2.0, 0.5)).encode()) == 19


@given(distance=st.floats(0.0, 10.0), bearing=angle)
def test_a_ball_seen_from_the_sender_keeps_float32_resolution(distance: float, bearing: float) -> None:
    back = decode(TeamMessage(3, ball_relative=(distance, bearing)).encode())
    assert back.ball_relative == tuple(struct.unpack("<ff", struct.pack("<ff", distance, bearing)))


@given(st.binary(max_size=MAX_PACKET_BYTES))
def test_random_bytes_never_raise(data: bytes) -> None:
    stats = DecodeStats()
    result = decode(data, stats)
    assert result is None or isinstance(result, TeamMessage)
    assert stats.decoded + sum(stats.ignored.values()) == 1


def test_a_role_is_a_name_and_the_radio_carries_its_code() -> None:
    from agents.radio import register_role_code

    data = TeamMessage(2, 1, None, role=Role.DEFENDER).encode()
    assert data[-4] == ROLE_CODES["defender"] == 4 and decode(data).role == "defender"
    register_role_code("libero", 9)
    try:
        assert decode(TeamMessage(2, 1, None, role="libero").encode()).role == "libero"
        for name, code in (("libero", 10), ("stopper", 4), ("stopper", 256)):
            try:
                register_role_code(name, code)
            except ValueError:
                continue
            raise AssertionError(f"{name} took code {code}")
    finally:
        from agents import radio as messages

        del messages.ROLE_CODES["libero"], messages._ROLE_NAMES[9]
