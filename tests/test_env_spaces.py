"""The env's spaces are standard gymnasium spaces: flattening, batching, iterating and shared memory work
on them, and the radio packet is a standard Dict of a byte Box and a length."""

from __future__ import annotations

import multiprocessing as mp

import numpy as np
import pytest
from gymnasium import spaces
from gymnasium.vector.utils import (
    batch_space,
    concatenate,
    create_empty_array,
    create_shared_memory,
    iterate,
    read_from_shared_memory,
    write_to_shared_memory,
)

from match.errors import RadioPacketError
from match.protocol import (
    INBOX_CAPACITY,
    MAX_PACKET_BYTES,
    action_space,
    make_action,
    observation_space,
    packet_bytes,
    packet_of,
    packet_space,
    parse_action,
)

STANDARD = (spaces.Dict, spaces.Box, spaces.Discrete, spaces.MultiBinary)


def _leaves(space: spaces.Space):
    if isinstance(space, spaces.Dict):
        for sub in space.spaces.values():
            yield from _leaves(sub)
    else:
        yield space


@pytest.mark.parametrize("make", [observation_space, action_space], ids=["observation", "action"])
def test_every_space_is_standard_and_flattens(make):
    space = make()
    space.seed(3)
    assert all(type(leaf) in STANDARD for leaf in _leaves(space))
    assert space.is_np_flattenable
    flat = spaces.flatten_space(space)
    sample = space.sample()
    vector = spaces.flatten(space, sample)
    assert flat.contains(vector.astype(flat.dtype))
    back = spaces.unflatten(space, vector)
    assert space.contains(back)
    assert np.array_equal(spaces.flatten(space, back), vector)


@pytest.mark.parametrize("make", [observation_space, action_space], ids=["observation", "action"])
def test_batching_iterating_and_shared_memory(make):
    space = make()
    space.seed(5)
    samples = [space.sample() for _ in range(3)]
    batch = concatenate(space, samples, create_empty_array(space, 3))
    batched = batch_space(space, 3)
    assert batched.contains(batch)
    for item, sample in zip(iterate(batched, batch), samples, strict=True):
        assert np.array_equal(spaces.flatten(space, item), spaces.flatten(space, sample))
    memory = create_shared_memory(space, n=3, ctx=mp.get_context("spawn"))
    for i, sample in enumerate(samples):
        write_to_shared_memory(space, i, sample, memory)
    shared = read_from_shared_memory(space, memory, n=3)
    assert np.array_equal(spaces.flatten(batch_space(space, 3), shared), spaces.flatten(batch_space(space, 3), batch))


def test_packet_space_layout_and_conversions():
    space = packet_space(seed=0)
    assert space["length"] == spaces.Discrete(MAX_PACKET_BYTES + 1)
    assert space["data"] == spaces.Box(0, 255, (MAX_PACKET_BYTES,), np.uint8)
    assert action_space()["radio"] == space
    packet = packet_of(b"hello")
    assert space.contains(packet) and packet["length"] == 5 and not packet["data"][5:].any()
    assert packet_bytes(packet) == b"hello"
    assert packet_bytes(packet_of(b"")) == b""
    with pytest.raises(ValueError, match="at most 128"):
        packet_of(b"x" * 129)
    with pytest.raises(ValueError, match="'text'"):
        packet_of("text")  # type: ignore[arg-type]
    inbox = observation_space()["radio"]
    assert inbox["count"] == spaces.Discrete(INBOX_CAPACITY + 1)
    assert inbox["data"].shape == (INBOX_CAPACITY, MAX_PACKET_BYTES) and inbox["data"].dtype == np.uint8


def test_sampled_packets_and_bytes_are_the_same_packet():
    space = action_space()
    space.seed(11)
    for _ in range(20):
        action = space.sample()
        expected = action["radio"]["data"][: action["radio"]["length"]].tobytes()
        assert parse_action("home_0", action).radio == expected
        as_bytes = {**action, "radio": expected}
        assert parse_action("home_0", as_bytes) == parse_action("home_0", action)
    assert parse_action("home_0", make_action(radio=b"abc")).radio == b"abc"


def test_a_bad_packet_dict_names_the_agent_the_field_and_the_value():
    with pytest.raises(RadioPacketError, match=r"'away_1'.*'radio.length' = 129.*\[0, 128\]"):
        parse_action("away_1", {"radio": {"data": np.zeros(128, np.uint8), "length": 129}})
    with pytest.raises(RadioPacketError, match=r"'radio.data'.*dtype uint8"):
        parse_action("away_1", {"radio": {"data": np.zeros(128, np.float32), "length": 1}})
    with pytest.raises(RadioPacketError, match=r"'radio'.*the key 'sender'"):
        parse_action("away_1", {"radio": {"data": np.zeros(128, np.uint8), "length": 1, "sender": 0}})
