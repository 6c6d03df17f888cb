"""The team message: round trip, size, and packets that are not ours."""

from __future__ import annotations

import math

from hypothesis import given
from hypothesis import strategies as st

from agents.team.messages import (
    MESSAGE_BYTES,
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
    assert len(data) == MESSAGE_BYTES <= MAX_PACKET_BYTES
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
    assert abs(back.ball_age_s - age) <= 6e-4 and abs(back.time_to_ball_s - to_ball) <= 6e-4
    assert abs(back.ball_sigma_m - sigma) <= 0.006


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
    stats = DecodeStats()
    for packet in (b"", b"R", good[:-1], good + b"\0", b"\x01" + bytes(8), future, bad_player, bad_role, "text", None):
        assert decode(packet, stats) is None
    assert decode(good, stats) is not None
    assert stats.decoded == 1
    assert stats.ignored == {
        "another format": 3, "wrong length": 2, "unknown version": 1, "player out of range": 1,
        "unknown role or intention": 1, "not bytes": 2,
    }


@given(st.binary(max_size=MAX_PACKET_BYTES))
def test_random_bytes_never_raise(data: bytes) -> None:
    stats = DecodeStats()
    result = decode(data, stats)
    assert result is None or isinstance(result, TeamMessage)
    assert stats.decoded + sum(stats.ignored.values()) == 1


def test_a_role_is_a_name_and_the_radio_carries_its_code() -> None:
    from agents.team.messages import register_role_code

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
        from agents.team import messages

        del messages.ROLE_CODES["libero"], messages._ROLE_NAMES[9]
