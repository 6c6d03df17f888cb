"""The scales of :class:`match.wrappers.FlatObservations`: every entry mapped onto [-1, 1].

Each entry of the flat vector (:func:`match.wrappers.flat_layout`) has a range [low, high] in
its own units (:data:`RANGES`, else the observation space's bounds); its value is clipped to
the range and mapped linearly onto [-1, 1] (low to -1, high to +1; a 0/1 value reads -1/+1,
a discrete index ``i`` of ``n`` reads ``-1 + 2 i / (n - 1)``). Two values that stand for
"none" with a placeholder magnitude get a flag entry right after them (:data:`PLACEHOLDERS`):
the flag reads +1 when the placeholder stands there (and the value reads as its range's low),
-1 otherwise. ``last_motion_sequence`` enters as its parity, which flips whenever a motion ends.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from gymnasium import spaces

from match.protocol.spaces import MAX_SECONDS, MOTION_TIME_LIMIT_S

RANGES: dict[str, tuple[float, float]] = {
    "accelerometer": (-30.0, 30.0),  # m/s^2: gravity and the shocks of walking; a fall reads beyond
    "gyro": (-10.0, 10.0),  # rad/s
    "motion_elapsed_s": (0.0, 10.0),  # s; the endless walk reads 1 after 10 s
    "motion_remaining_s": (0.0, 10.0),  # s
    "last_motion_sequence": (0.0, 1.0),  # its parity
    "odometry": (-1.0, 1.0),  # m, m, rad of one motion
    "game/score": (0.0, 10.0),  # goals
    "game/shootout_score": (0.0, 10.0),
    "game/seconds_remaining": (0.0, 600.0),  # s: a half's default length
    "game/seconds_since_drop_in": (0.0, 60.0),  # s
    "radio/dropped": (0.0, 10.0),  # packets
}
"""Ranges (in the entry's units) that differ from the observation space's bounds, by path."""

PLACEHOLDERS: dict[str, tuple[float, str]] = {
    "motion_remaining_s": (MOTION_TIME_LIMIT_S, "endless"),  # the walk goes on until another motion
    "game/seconds_since_drop_in": (MAX_SECONDS, "none"),  # no throw-in this half
}
"""Path -> (the placeholder value, the flag's name): values at or above the placeholder set the flag."""


@dataclass(frozen=True)
class ScaledLayout:
    """The scaled vector of a flat layout: ``labels`` (flags named ``"<value>/<flag>"``), the range of each
    raw entry (``low``, ``high``) and the :class:`gymnasium.spaces.Box` ``space`` (-1 .. 1, float32)."""

    labels: tuple[str, ...]
    low: np.ndarray
    high: np.ndarray
    flag_of: tuple[tuple[int, float], ...]  # (raw index, placeholder) per flag, in order
    flag_at: np.ndarray  # where each flag goes in the scaled vector (its value's index + 1)
    parity: np.ndarray  # raw indices that enter as their parity
    space: spaces.Box

    def scale(self, raw: np.ndarray) -> np.ndarray:
        """The scaled vector (float32, in [-1, 1]) of a raw flat vector."""
        values = raw.astype(np.float64)
        flags = []
        for index, placeholder in self.flag_of:
            flagged = values[index] >= placeholder
            flags.append(1.0 if flagged else -1.0)
            if flagged:
                values[index] = self.low[index]
        values[self.parity] = np.mod(values[self.parity], 2.0)
        clipped = np.clip(values, self.low, self.high)
        scaled = 2.0 * (clipped - self.low) / (self.high - self.low) - 1.0
        return np.insert(scaled, self.flag_at, flags).astype(np.float32)


def scaled_layout(paths: tuple[tuple[str, ...], ...], sizes: tuple[int, ...], labels: tuple[str, ...],
                  space: spaces.Box) -> ScaledLayout:
    """The scaled layout of a flat layout (its ``paths``, ``sizes``, ``labels`` and raw ``space``)."""
    low, high = space.low.astype(np.float64), space.high.astype(np.float64)
    flag_of, flag_at, parity, out_labels = [], [], [], []
    start = 0
    for path, size in zip(paths, sizes):
        name = "/".join(path)
        if name in RANGES:
            low[start:start + size], high[start:start + size] = RANGES[name]
        if name == "last_motion_sequence":
            parity.append(start)
        out_labels.extend(labels[start:start + size])
        if name in PLACEHOLDERS:
            placeholder, flag = PLACEHOLDERS[name]
            flag_of.append((start, placeholder))
            flag_at.append(start + 1)
            out_labels.append(f"{name}/{flag}")
        start += size
    if not all(math.isfinite(v) for v in (*low, *high)) or np.any(high <= low):
        raise ValueError("every flat entry needs a finite range with high > low")
    box = spaces.Box(-1.0, 1.0, (len(out_labels),), np.float32)
    return ScaledLayout(tuple(out_labels), low, high, tuple(flag_of), np.array(flag_at, np.int64),
                        np.array(parity, np.int64), box)
