"""Where an image has edges: the pixels that two renderers may draw one pixel apart."""

from __future__ import annotations

import numpy as np


def near_edge(image: np.ndarray) -> np.ndarray:
    """Pixels (h, w) of an RGB image (h, w, 3) whose 3x3 neighbourhood holds another colour."""
    packed = image.astype(np.int64) @ np.array([1 << 16, 1 << 8, 1])
    padded = np.pad(packed, 1, mode="edge")
    height, width = packed.shape
    near = np.zeros(packed.shape, bool)
    for dy in range(3):
        for dx in range(3):
            near |= padded[dy : dy + height, dx : dx + width] != packed
    return near
