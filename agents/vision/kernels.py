"""The per-pixel passes of the vision in compiled code (numba): the segmentation of a frame.

They compute exactly what the array formulations they replace computed (tests compare them with
pixel-by-pixel references); ``python -m agents.compile`` (run by ``make install``) puts
their machine code in numba's cache, so no controller process compiles them.
"""

from __future__ import annotations

import numba
import numpy as np

from agents.vision.colors import ColorClass

WHITE, GREEN, ORANGE = int(ColorClass.WHITE), int(ColorClass.GREEN), int(ColorClass.ORANGE)
LEVEL_SHIFT = 2  # 256 levels -> 64 per channel in the colour table


@numba.njit(cache=True, nogil=True)
def classify_pixels(image: np.ndarray, table: np.ndarray) -> np.ndarray:
    """Raw class labels (H, W) uint8 of an RGB uint8 image (H, W, 3) through the lookup table over
    quantized RGB (``(r >> 2) << 12 | (g >> 2) << 6 | (b >> 2)``)."""
    h, w = image.shape[0], image.shape[1]
    labels = np.empty((h, w), np.uint8)
    for r in range(h):
        for c in range(w):
            index = ((image[r, c, 0] >> LEVEL_SHIFT) << 12) | ((image[r, c, 1] >> LEVEL_SHIFT) << 6) | (
                image[r, c, 2] >> LEVEL_SHIFT)
            labels[r, c] = table[index]
    return labels


@numba.njit(cache=True, nogil=True)
def clean_isolated(labels: np.ndarray) -> np.ndarray:
    """The thesis' neighbour check (section 4.1) on a copy of ``labels`` (H, W) uint8: a non-white pixel
    with no 8-neighbour of its own class becomes white; a white one with no white 8-neighbour becomes
    orange when at least 4 of its neighbours are orange, green otherwise. Outside the image counts as
    no class."""
    h, w = labels.shape
    out = labels.copy()
    for r in range(h):
        for c in range(w):
            own = labels[r, c]
            if c > 0 and labels[r, c - 1] == own:
                continue
            if c < w - 1 and labels[r, c + 1] == own:
                continue
            isolated = True
            orange = 0
            for dr in range(-1, 2):
                rr = r + dr
                if rr < 0 or rr >= h:
                    continue
                for dc in range(-1, 2):
                    cc = c + dc
                    if (dr == 0 and dc == 0) or cc < 0 or cc >= w:
                        continue
                    neighbour = labels[rr, cc]
                    if neighbour == own:
                        isolated = False
                    elif neighbour == ORANGE:
                        orange += 1
            if not isolated:
                continue
            if own != WHITE:
                out[r, c] = WHITE
            elif orange >= 4:
                out[r, c] = ORANGE
            else:
                out[r, c] = GREEN
    return out


@numba.njit(cache=True, nogil=True)
def white_runs(labels: np.ndarray, columns: np.ndarray, start: np.ndarray, forbidden_beside: np.ndarray,
               white: int, green: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The runs of ``white`` pixels of each scan column ``columns[k]`` (K,) from row ``start[k]`` down, as
    (scan column index, top row, bottom row, criterion) arrays in column then row order, with the first
    two criteria of thesis 4.5.1 applied (criterion 0: passed, 1: an end not against ``green`` inside
    the scan, 2: a forbidden class (``forbidden_beside`` over labels 0-255) beside an interior pixel in
    a neighbouring column inside the image)."""
    height, width = labels.shape
    capacity = len(columns) * (height // 2 + 1)
    scan_index = np.empty(capacity, np.int64)
    tops = np.empty(capacity, np.int64)
    bottoms = np.empty(capacity, np.int64)
    criteria = np.zeros(capacity, np.int64)
    n = 0
    for k in range(len(columns)):
        column = columns[k]
        row = start[k]
        while row < height:
            if labels[row, column] != white:
                row += 1
                continue
            top = row
            while row + 1 < height and labels[row + 1, column] == white:
                row += 1
            bottom = row
            row += 1
            scan_index[n], tops[n], bottoms[n] = k, top, bottom
            above_ok = top > start[k] and labels[top - 1, column] == green
            below_ok = bottom < height - 1 and labels[bottom + 1, column] == green
            if not (above_ok and below_ok):
                criteria[n] = 1
            else:
                for interior in range(top + 1, bottom):
                    if ((column > 0 and forbidden_beside[labels[interior, column - 1]])
                            or (column < width - 1 and forbidden_beside[labels[interior, column + 1]])):
                        criteria[n] = 2
                        break
            n += 1
    return scan_index[:n], tops[:n], bottoms[:n], criteria[:n]
