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


def large_deviation(len1: float, len2: float) -> bool:
    """True when two black-line lengths deviate too much for AddLimit to apply."""
    short, long_ = (len1, len2) if len1 <= len2 else (len2, len1)
    return long_ > LENGTH_DEVIATION_RATIO * short and long_ - short >= LENGTH_DEVIATION_MIN_PX


def _sign(d: float) -> int:
    return 0 if abs(d) <= DIRECTION_DEADBAND_PX else (1 if d > 0 else -1)


def form_lines(column: np.ndarray, middle: np.ndarray, length: np.ndarray, dist: int = DIST) -> list[list[int]]:
    """AddLines without Split: lines as lists of indices into the (sorted) kept black lines."""
    w, h, n = column.tolist(), middle.tolist(), length.tolist()
    count = len(w)
    flag = [0] * count
    lines = []
    start = 0
    while True:
        start = get_start(flag, start)
        if start < 0:
            return lines
        line = get_line(w, h, n, flag, start, dist)
        if len(line) >= MIN_BLACK_LINES:
            lines.append(line)


def get_start(flag: list[int], begin: int = 0) -> int:
    """GetStart: index of the first black line from ``begin`` not used by a line, or -1."""
    for i in range(begin, len(flag)):
        if flag[i] == 0:
            return i
    return -1


def get_line(w: list, h: list, n: list, flag: list[int], start: int, dist: int = DIST) -> list[int]:
    """GetLine (thesis Algorithm 2): the black lines of the line starting at ``start``; flags them."""
    line = [start]
    flag[start] = 1
    current = start
    direction = 0  # the sign of the last step (0 until the line has two black lines)
    limit_w = MAX_GAP_DISTS * dist
    for nxt in range(start + 1, len(w)):
        if w[nxt] - w[current] >= limit_w:  # criterion 3
            break
        if flag[nxt] or w[nxt] == w[current]:  # criteria 1 and 2
            continue
        d2 = h[nxt] - h[current]
        if abs(d2) > add_limit(n[current], n[nxt], w[current], w[nxt], dist) or large_deviation(n[current], n[nxt]):
            continue  # criterion 4
        step = _sign(d2)
        if direction * step < 0:
            continue  # criterion 5: the direction changes sign
        line.append(nxt)
        flag[nxt] = 1
        current = nxt
        direction = step
    return line
