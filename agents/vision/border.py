"""Field border detection (thesis section 4.3, Algorithm 1).

Every third column, the first green pixel from the top is a dot. Algorithm 1 connects the
dots from a starting column, ignoring a dot that jumps more than ``HeightThreshold`` rows
from the last kept one, and gives up early once more than ``RejectionPercentage`` of the
dots were ignored. A mirrored pass runs from the right; the two alternate with starting
columns moving in from the image's ends until one succeeds. When none does, the frame has
no border and the rest of the recognition is skipped (the robot has fallen, or its view is
blocked).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from agents.vision.colors import ColorClass

BORDER_COLUMN_STEP_PX = 3  # thesis 4.3: "every third column"
HEIGHT_THRESHOLD_PX = 3  # thesis Algorithm 1, HeightThreshold default
REJECTION_PERCENTAGE = 0.75  # thesis Algorithm 1, RejectionPercentage default
NO_DOT = -1
GREEN = int(ColorClass.GREEN)


@dataclass(frozen=True, eq=False)
class FieldBorder:
    """The field border of one frame.

    ``columns`` are the sampled image columns; ``dots`` the first green row of each (or
    -1 when a column has no green); ``rows`` the border line: the dots kept by Algorithm 1,
    -1 where a dot was ignored. ``found`` is False when no border line could be drawn.
    """

    found: bool
    columns: np.ndarray
    dots: np.ndarray
    rows: np.ndarray
    start_column: int = -1

    def row_at(self, u: np.ndarray) -> np.ndarray:
        """Border row (float) at image columns ``u``, interpolated between kept dots."""
        kept_columns, kept_rows = self._kept_dots
        if not self.found or len(kept_columns) == 0:
            return np.full(np.shape(u), np.nan)
        return np.interp(np.asarray(u, float), kept_columns, kept_rows)

    @functools.cached_property
    def _kept_dots(self) -> tuple[np.ndarray, np.ndarray]:
        """Columns and rows (float) of the kept dots: the scan lines and every corner check read the border."""
        kept = self.rows >= 0
        return self.columns[kept], self.rows[kept].astype(float)


def first_green_rows(labels: np.ndarray, step: int = BORDER_COLUMN_STEP_PX) -> tuple[np.ndarray, np.ndarray]:
    """Sampled columns and the row of the first green pixel from the top in each (-1: none)."""
    columns = np.arange(0, labels.shape[1], step)
    green = labels[:, columns] == GREEN
    rows = np.argmax(green, axis=0)
    rows[~green.any(axis=0)] = NO_DOT
    return columns, rows


def border_line_from_left(
    heights: np.ndarray,
    start: int,
    height_threshold: int = HEIGHT_THRESHOLD_PX,
    rejection_percentage: float = REJECTION_PERCENTAGE,
) -> tuple[bool, np.ndarray]:
    """Algorithm 1 of the thesis, as written: (found, border line with ignored dots at -1).

    ``heights`` are the dots' rows (-1 for a column without green, which is never kept).
    The loop runs on Python ints (a numpy element costs more to read than to compare).
    """
    dots = heights.tolist()
    border = list(dots)
    size = len(border)
    left, right, counter = start, start + 1, 0
    while right < size - 1:
        if border[left] == NO_DOT:
            left += 1
        else:
            if dots[right] != NO_DOT and abs(dots[left] - dots[right]) < height_threshold:
                left += 1
            else:
                border[right] = NO_DOT
                counter += 1
            right += 1
        if counter > rejection_percentage * size:
            return False, np.array(border, heights.dtype)
    border[:start] = [NO_DOT] * start  # dots before the start and the last one (the loop stops before
    border[right:] = [NO_DOT] * (size - right)  # it, as written) were never connected to the line
    return True, np.array(border, heights.dtype)


def find_border(
    labels: np.ndarray,
    step: int = BORDER_COLUMN_STEP_PX,
    height_threshold: int = HEIGHT_THRESHOLD_PX,
    rejection_percentage: float = REJECTION_PERCENTAGE,
) -> FieldBorder:
    """Find the field border of a segmented image (H, W) uint8, alternating left and right passes."""
    columns, dots = first_green_rows(labels, step)
    size = len(dots)
    for offset in range((size + 1) // 2):
        for from_left in (True, False):
            heights = dots if from_left else dots[::-1]
            if heights[offset] == NO_DOT:
                continue
            found, line = border_line_from_left(heights, offset, height_threshold, rejection_percentage)
            if found:
                rows = line if from_left else line[::-1]
                start = offset if from_left else size - 1 - offset
                return FieldBorder(True, columns, dots, rows, int(columns[start]))
    return FieldBorder(False, columns, dots, np.full(size, NO_DOT), -1)
