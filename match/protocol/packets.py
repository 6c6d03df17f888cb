"""Radio packets: the bytes one robot may hand its emitter in one step."""

from __future__ import annotations

from typing import Any

import numpy as np
from gymnasium import spaces

MAX_PACKET_BYTES = 128  # SPL team-communication packet limit
INBOX_CAPACITY = 8  # packets one robot can read per step; more are dropped and counted


class PacketSpace(spaces.Space):
    """The space of radio packets: ``bytes`` of length 0 to ``max_bytes`` (empty = none).

    ``sample()`` draws an empty packet half of the time, otherwise random bytes of a
    random length from 1 to ``max_bytes``.
    """

    def __init__(self, max_bytes: int = MAX_PACKET_BYTES, seed: int | np.random.Generator | None = None):
        self.max_bytes = int(max_bytes)
        super().__init__(shape=None, dtype=None, seed=seed)

    @property
    def is_np_flattenable(self) -> bool:
        return False

    def sample(self, mask: Any | None = None, probability: Any | None = None) -> bytes:
        if mask is not None or probability is not None:
            raise ValueError("PacketSpace.sample takes no mask or probability")
        if self.np_random.random() < 0.5:
            return b""
        length = int(self.np_random.integers(1, self.max_bytes + 1))
        return self.np_random.integers(0, 256, size=length, dtype=np.uint8).tobytes()

    def contains(self, x: Any) -> bool:
        return isinstance(x, (bytes, bytearray)) and len(x) <= self.max_bytes

    def __repr__(self) -> str:
        return f"PacketSpace(max_bytes={self.max_bytes})"

    def __eq__(self, other: object) -> bool:
        return isinstance(other, PacketSpace) and other.max_bytes == self.max_bytes

    def __hash__(self) -> int:
        return hash(("PacketSpace", self.max_bytes))
