"""Scan lines (thesis section 4.5.1): white runs below the field border, and the four rejection criteria.

Every ``dist``-th column is scanned from the field border down to the bottom of the image;
each run of white pixels is a "black line" (the thesis paints them black). A black line is
kept only if it passes the four criteria; the first criterion that fails is recorded (the
debug overlay paints criterion 1 orange, 2 magenta, 3 cyan, 4 yellow):

1. both its ends touch green: the pixel above its top and the one below its bottom are
   green (a run starting at the border or running off the image bottom fails);
2. the pixels left and right of its interior points (the two ends ignored) are white;
3. it is not longer than twice the average length of all black lines longer than 3 px;
4. it belongs to a chain of three "close-enough" black lines in consecutive scan columns,
   and it is not significantly smaller than its close neighbour in the next column.

Pixel coordinates: ``(u, v)`` = (column, row), integers are pixel centres; rows grow down
(the thesis' "height coordinate").
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from agents.vision.border import FieldBorder
from agents.vision.colors import ColorClass
from agents.vision.kernels import chained_runs, white_runs

DIST = 5  # thesis 4.5.1: "every fifth column", called dist
LONG_RUN_MIN_PX = 3  # thesis 4.5.1 criterion 3: average over black lines "larger than three pixels"
LONG_RUN_FACTOR = 2.0  # thesis 4.5.1 criterion 3: "The threshold is twice this average"
# Thesis 4.5.1 criterion 4 asks for "some kind of overlap in height coordinates" without a
# number. We count row intervals that overlap or touch (gap of 0 rows): the same closeness
# AddLimit (thesis 4.5.2) accepts between neighbouring scan columns, (len1 + len2) / 2.
CLOSE_GAP_PX = 0
# Criterion 4's "significantly smaller compared to the next black line" has no number in
# the thesis either: we read it as at most a third of the next one's length, and at least
# SMALLER_MIN_DIFF_PX shorter, so that 1-px versus 2-px dashes of a far line do not count.
SMALLER_RATIO = 1.0 / 3.0
SMALLER_MIN_DIFF_PX = 3

# Criterion 2, as the thesis states it: only white pixels may lie beside a black line's
# interior points.
NEIGHBOURS_THESIS = (ColorClass.WHITE,)
# Ours: white or green. A vertical scan crosses a field line that is steeper than about 45
# degrees in the image with a run whose interior has green on one side, so the thesis' rule
# drops every such line: the receding legs of L corners and the middle line at a T
# junction whenever the head looks at them. Other colours (robots, goals, ball) still reject.
NEIGHBOURS_ALLOWED = (ColorClass.WHITE, ColorClass.GREEN)

KEPT = 0
WHITE = int(ColorClass.WHITE)
GREEN = int(ColorClass.GREEN)
CRITERION_COLOR = {1: ColorClass.ORANGE, 2: ColorClass.MAGENTA, 3: ColorClass.CYAN, 4: ColorClass.YELLOW}
"""Overlay colour of the black lines rejected by each criterion (thesis 4.5.1)."""


@dataclass(frozen=True, eq=False)
class BlackLines:
    """The white runs of the scan columns, sorted by column then top row ("upper left" first).

    ``column``, ``top``, ``bottom`` are pixel indices (``top``/``bottom`` inclusive rows);
    ``rejected_by`` is 0 for a kept black line, else the number (1-4) of the criterion that
    rejected it.
    """

    column: np.ndarray
    top: np.ndarray
    bottom: np.ndarray
    rejected_by: np.ndarray

    @property
    def length(self) -> np.ndarray:
        """Run length in pixels."""
        return self.bottom - self.top + 1

    @property
    def middle(self) -> np.ndarray:
        """Row of the run's midpoint (float, pixel-index units)."""
        return (self.top + self.bottom) / 2.0

    @property
    def kept(self) -> np.ndarray:
        return self.rejected_by == KEPT

    def __len__(self) -> int:
        return len(self.column)

    @classmethod
    def empty(cls) -> BlackLines:
        none = np.zeros(0, np.int64)
        return cls(none, none, none, none)


@functools.lru_cache(maxsize=4)
def _forbidden_beside(neighbours_allowed: tuple[ColorClass, ...]) -> np.ndarray:
    """Lookup table over labels 0-255: True for a class criterion 2 rejects beside an interior point (read-only)."""
    forbidden = np.ones(256, bool)
    forbidden[[int(c) for c in neighbours_allowed]] = False
    forbidden.setflags(write=False)
    return forbidden


def scan_columns(width: int, dist: int = DIST) -> np.ndarray:
    """The scanned columns: 0, dist, 2 dist, ..."""
    return np.arange(0, width, dist)


def scan_black_lines(
    labels: np.ndarray,
    border: FieldBorder,
    dist: int = DIST,
    neighbours_allowed: tuple[ColorClass, ...] = NEIGHBOURS_ALLOWED,
) -> BlackLines:
    """Black lines of a segmented image (H, W) below ``border``, with the criteria applied.

    ``neighbours_allowed``: the classes criterion 2 accepts beside interior points
    (:data:`NEIGHBOURS_THESIS` for the thesis' rule).
    """
    height, width = labels.shape
    if not border.found:
        return BlackLines.empty()
    columns = scan_columns(width, dist)
    start = np.ceil(border.row_at(columns) - 1e-9).astype(np.int64)
    start = np.minimum(np.maximum(start, 0), height)
    k_top, top, bottom, rejected = white_runs(np.ascontiguousarray(labels, np.uint8), columns, start,
                                              _forbidden_beside(neighbours_allowed), WHITE, GREEN)
    if len(top) == 0:
        return BlackLines.empty()
    column = columns[k_top]

    # Criterion 3: not longer than twice the average length of all black lines longer than 3 px.
    length = bottom - top + 1
    long_runs = length[length > LONG_RUN_MIN_PX]
    if len(long_runs):
        rejected[(rejected == KEPT) & (length > LONG_RUN_FACTOR * (long_runs.sum() / len(long_runs)))] = 3

    # Criterion 4: part of a chain of three close-enough black lines in consecutive columns.
    alive = np.flatnonzero(rejected == KEPT)
    if len(alive):
        ok = continuity(k_top[alive], top[alive], bottom[alive])
        rejected[alive[~ok]] = 4
    return BlackLines(column, top, bottom, rejected)


def continuity(scan_index: np.ndarray, top: np.ndarray, bottom: np.ndarray) -> np.ndarray:
    """Criterion 4 on black lines (scan column index, top, bottom), sorted by scan column: which pass
    (:func:`agents.vision.kernels.chained_runs`)."""
    return chained_runs(np.ascontiguousarray(scan_index, np.int64), np.ascontiguousarray(top, np.int64),
                        np.ascontiguousarray(bottom, np.int64), CLOSE_GAP_PX, SMALLER_RATIO, SMALLER_MIN_DIFF_PX)
