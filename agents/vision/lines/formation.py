"""Line formation (thesis section 4.5.2): GetStart, GetLine (Algorithm 2) and AddLimit.

The kept black lines, in their "upper left to lower right" order (column, then row), are
grouped into lines: GetStart picks the first black line not yet used, GetLine walks the
array from it and adds each following black line that passes the five criteria:

1. it is not used by another line (flag 0);
2. it is in another column than the current black line;
3. it is less than ``6 * dist`` columns to the right (else the walk stops);
4. its midpoint is within AddLimit rows of the current one's, and the two lengths do not
   deviate much;
5. the direction (previous -> current -> next midpoint heights) does not change sign.

Lines of fewer than three black lines are dropped, with their black lines.
"""

from __future__ import annotations

import numpy as np

from agents.vision.kernels import formed_lines
from agents.vision.lines.scan_lines import DIST

MAX_GAP_DISTS = 6  # thesis 4.5.2 criterion 3: width difference must stay below 6 x dist
MIN_BLACK_LINES = 3  # thesis 4.5.2: "less than three black lines in length, then it is rejected"
# Thesis 4.5.2 criterion 4: AddLimit applies only "provided that len1 and len2 do not have a
# large deviation", with no number given. Ours: the longer more than twice the shorter and
# at least 3 px longer (dashes of a far line, 1 px versus 2 px, are not a large deviation).
LENGTH_DEVIATION_RATIO = 2.0
LENGTH_DEVIATION_MIN_PX = 3
# Thesis 4.5.2 criterion 5 tracks the sign of midpoint height differences. Midpoints are
# half-pixel quantized, so differences of at most 1 px count as "no direction" (sign 0);
# Algorithm 3 likewise needs 2 px over two steps before it calls a segment up or down.
DIRECTION_DEADBAND_PX = 1.0


def add_limit(len1: float, len2: float, w1: float, w2: float, dist: int = DIST) -> float:
    """AddLimit (thesis 4.5.2): the largest allowed midpoint height difference, pixels."""
    return (len1 + len2) / 2.0 + (w2 - w1) / dist - 1.0


def form_lines(column: np.ndarray, middle: np.ndarray, length: np.ndarray, dist: int = DIST) -> list[list[int]]:
    """AddLines without Split: lines as lists of indices into the (sorted) kept black lines: GetStart picks
    the first black line not yet used, GetLine (thesis Algorithm 2) walks on from it (module docstring;
    compiled: :func:`agents.vision.kernels.formed_lines`)."""
    members, starts = formed_lines(np.ascontiguousarray(column, np.int64), np.ascontiguousarray(middle, float),
                                   np.ascontiguousarray(length, np.int64), dist, MAX_GAP_DISTS, MIN_BLACK_LINES,
                                   LENGTH_DEVIATION_RATIO, LENGTH_DEVIATION_MIN_PX, DIRECTION_DEADBAND_PX)
    members, starts = members.tolist(), starts.tolist()
    return [members[a:b] for a, b in zip(starts[:-1], starts[1:])]
