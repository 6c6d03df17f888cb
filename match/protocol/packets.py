"""Radio packets: the bytes one robot may hand its emitter in one step, as standard spaces.

A packet in an action is a dict of two standard gymnasium spaces (:func:`packet_space`):
``length``, the number of bytes sent (``Discrete(129)``, 0 = no packet), and ``data``,
``Box(0, 255, (128,), uint8)``, whose first ``length`` bytes are the packet (the rest is
padding and ignored). So gymnasium's ``flatten_space``, ``iterate``, ``batch_space`` and
shared-memory vector envs handle actions like any other. ``bytes`` (at most 128) are
accepted in actions too, as a convenience; :func:`packet_of` and :func:`packet_bytes`
convert between the two forms. The inbox of an observation is laid out the same way
(``count`` packets of ``sender``, ``length`` and ``data``, see :mod:`match.protocol.spaces`).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from gymnasium import spaces

from match.errors import shown

MAX_PACKET_BYTES = 128  # SPL team-communication packet limit
INBOX_CAPACITY = 8  # packets one robot can read per step; more are dropped and counted
PACKET_KEYS = ("data", "length")


def packet_space(seed: int | np.random.Generator | None = None) -> spaces.Dict:
    """The space of one radio packet: ``{"data": Box(0, 255, (128,), uint8), "length": Discrete(129)}``.

    The packet is ``data[:length]``; ``length`` 0 sends nothing. ``sample()`` draws a length
    uniformly from 0 to 128 and random bytes.
    """
    return spaces.Dict(
        {
            "data": spaces.Box(0, 255, (MAX_PACKET_BYTES,), np.uint8),
            "length": spaces.Discrete(MAX_PACKET_BYTES + 1),
        },
        seed=seed,
    )


def packet_of(data: bytes | bytearray) -> dict[str, object]:
    """The packet ``data`` (at most 128 bytes) in the layout of :func:`packet_space`, zero-padded."""
    if not isinstance(data, (bytes, bytearray)) or len(data) > MAX_PACKET_BYTES:
        raise ValueError(f"packet data = {shown(data)} is invalid; expected bytes of length at most {MAX_PACKET_BYTES}")
    padded = np.zeros(MAX_PACKET_BYTES, np.uint8)
    padded[: len(data)] = np.frombuffer(bytes(data), np.uint8)
    return {"data": padded, "length": len(data)}


def packet_bytes(packet: Mapping[str, object]) -> bytes:
    """The bytes of a packet in the layout of :func:`packet_space` (unchecked: actions are checked by
    :func:`match.protocol.actions.parse_action`)."""
    length = int(packet["length"])  # type: ignore[call-overload]
    return np.asarray(packet["data"], np.uint8)[:length].tobytes()
