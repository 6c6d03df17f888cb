"""Line formation, split and merge, and classification (thesis sections 4.5.2-4.5.4).

GetStart/GetLine (Algorithm 2) chain the kept black lines into lines; Algorithm 3 labels
each line's 3-black-line segments up/down/straight; lines whose label sequence is not one
of Table 4.2 are split, compatible neighbours merged; each line is then classified by a
least-squares parabola against the thresholds of Table 4.3, with the curve verification.

Image coordinates: ``w`` is the column, ``h`` the row (growing downward). "Up" means the
line rises in the image as ``w`` grows, i.e. ``h`` decreases: Algorithm 3's
``diff = h1 - h2 >= +2`` over a segment.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from agents.vision.lines.scan import DIST_PX, BlackLine, add_limit

MAX_GAP_FACTOR = 6  # thesis 4.5.2 criterion 3: stop when the next run is 6 * dist columns away
MAX_LENGTH_RATIO = 3.0  # ours: thesis 4.5.2 criterion 4's "large deviation" of two runs' lengths
MIN_BLACK_LINES = 3  # thesis 4.5.2: lines of fewer black lines are rejected
SEGMENT = 3  # thesis 4.5.3: segments of three black lines
SLOPE_LABEL = 2  # thesis Algorithm 3: diff1 + diff2 >= +2 is up, <= -2 down
MERGE_MAX_DW_PX = 20  # thesis 4.5.3 Merge continuity: width
MERGE_MAX_DH_PX = 10  # thesis 4.5.3 Merge continuity: height
A_CURVE, A_CORNER, B_CURVE, B_SIDE = 0.7, 5.2, 0.6, 0.07  # thesis Table 4.3 (a scaled by 1000)
A_HALF = 1.0  # thesis 4.5.4 curve verification: |a1| > 1 and |a2| > 1

UP, DOWN, STRAIGHT = "up", "down", "straight"
TABLE_4_2 = {
    (UP,): "S1",
    (DOWN,): "S2",
    (STRAIGHT,): "S3",
    (UP, STRAIGHT): "S4",
    (STRAIGHT, UP): "S5",
    (DOWN, STRAIGHT): "S6",
    (STRAIGHT, DOWN): "S7",
    (UP, STRAIGHT, DOWN): "S8",
    (DOWN, STRAIGHT, UP): "S9",
}
MERGEABLE = {("S1", "S1"), ("S2", "S2"), ("S3", "S3"), ("S4", "S2"), ("S6", "S1"), ("S2", "S5"), ("S1", "S7")}  # thesis 4.5.3


class LineType:
    UPPER_HALF_CIRCLE = "upper_half_circle"
    DOWN_HALF_CIRCLE = "down_half_circle"
    UP_CORNER = "up_corner"
    DOWN_CORNER = "down_corner"
    SIDE_DOWN = "side_down"
    SIDE_UP = "side_up"
    STRAIGHT = "straight"


@dataclass(frozen=True)
class FieldLine:
    """A formed line: its black lines left to right, label sequence, fit and type."""

    runs: tuple[BlackLine, ...]
    labels: tuple[str, ...]
    fit: tuple[float, float, float]  # a (scaled by 1000), b, c of h = a w'^2 + b w' + c, w' = w - w_mean
    line_type: str

    @property
    def w(self) -> np.ndarray:
        return np.array([r.u for r in self.runs], float)

    @property
    def h(self) -> np.ndarray:
        return np.array([r.mid for r in self.runs], float)

    @property
    def start(self) -> tuple[float, float]:
        return float(self.runs[0].u), self.runs[0].mid

    @property
    def end(self) -> tuple[float, float]:
        return float(self.runs[-1].u), self.runs[-1].mid

    def h_at(self, w: float) -> float:
        a, b, c = self.fit
        x = w - float(self.w.mean())
        return a / 1000.0 * x * x + b * x + c


def form_lines(runs: list[BlackLine], dist: int = DIST_PX) -> list[list[BlackLine]]:
    """GetStart and GetLine (Algorithm 2) over the kept runs, sorted upper left to lower right."""
    ordered = sorted((r for r in runs if r.rejected == 0), key=lambda r: (r.u, r.top))
    used = [False] * len(ordered)
    lines = []
    for start in range(len(ordered)):  # GetStart: the next run not yet in a line
        if used[start]:
            continue
        used[start] = True
        line = [ordered[start]]
        for nxt in range(start + 1, len(ordered)):
            current, candidate = line[-1], ordered[nxt]
            if candidate.u - current.u >= MAX_GAP_FACTOR * dist:
                break
            if used[nxt] or candidate.u == current.u:
                continue
            if abs(candidate.mid - current.mid) > add_limit(current, candidate, dist):
                continue
            if max(current.length, candidate.length) > MAX_LENGTH_RATIO * min(current.length, candidate.length):
                continue
            if len(line) >= 2:  # criterion 5: the direction may not change sign
                before = np.sign(current.mid - line[-2].mid)
                after = np.sign(candidate.mid - current.mid)
                if before and after and before != after:
                    continue
            line.append(candidate)
            used[nxt] = True
        if len(line) >= MIN_BLACK_LINES:
            lines.append(line)
    return lines


def direction_labels(line: list[BlackLine]) -> tuple[tuple[str, ...], tuple[int, ...]]:
    """Algorithm 3: the line's label sequence and the segment index where each label starts."""
    labels, starts = [], []
    for k in range(0, len(line) - SEGMENT + 1, SEGMENT):
        h1, h2, h3 = (r.mid for r in line[k : k + SEGMENT])
        diff = (h1 - h2) + (h2 - h3)
        label = UP if diff >= SLOPE_LABEL else DOWN if diff <= -SLOPE_LABEL else STRAIGHT
        if not labels or labels[-1] != label:
            labels.append(label)
            starts.append(k // SEGMENT)
    return tuple(labels), tuple(starts)


def split_line(line: list[BlackLine]) -> list[list[BlackLine]]:
    """Split at unacceptable label changes (thesis 4.5.3 rules 1-3) until every piece is in Table 4.2."""
    labels, starts = direction_labels(line)
    if labels in TABLE_4_2 or len(labels) < 2:
        return [line]
    cut = None
    for i in range(1, len(labels)):  # rule 1: up and down may not be consecutive (a corner)
        if {labels[i - 1], labels[i]} == {UP, DOWN}:
            cut = starts[i]
            break
    if cut is None and labels[0] == STRAIGHT:  # rule 3: a straight piece before a circle's sequence
        cut = starts[1]
    if cut is None:  # rule 2 (up-straight-up, down-straight-down) and the rest: cut at the last change
        cut = starts[-1]
    head, tail = line[: cut * SEGMENT], line[cut * SEGMENT :]
    return [piece for part in (head, tail) if len(part) >= MIN_BLACK_LINES for piece in split_line(part)]


def merge_lines(lines: list[list[BlackLine]]) -> list[list[BlackLine]]:
    """Merge ordered pairs of compatible, non-overlapping, continuous lines (thesis 4.5.3 Merge)."""
    lines = sorted(lines, key=lambda line: line[0].u)
    merged = True
    while merged:
        merged = False
        for i in range(len(lines)):
            for j in range(len(lines)):
                first, second = lines[i], lines[j]
                if i == j or first[-1].u >= second[0].u:
                    continue
                pair = (TABLE_4_2.get(direction_labels(first)[0]), TABLE_4_2.get(direction_labels(second)[0]))
                if pair not in MERGEABLE:
                    continue
                if second[0].u - first[-1].u > MERGE_MAX_DW_PX or abs(second[0].mid - first[-1].mid) > MERGE_MAX_DH_PX:
                    continue
                lines[i] = first + second
                del lines[j]
                merged = True
                break
            if merged:
                break
    return lines


def fit_parabola(w: np.ndarray, h: np.ndarray) -> tuple[float, float, float]:
    """Least squares h = a w'^2 + b w' + c with w' = w - mean(w); a scaled by 1000 (thesis 4.5.4).

    The thesis does not say where w is measured from; from the line's mean column, b is the
    slope at the line's middle, whatever the line's place in the image.
    """
    x = w - w.mean()
    if len(np.unique(x)) < 3:
        slope = float(np.polyfit(x, h, 1)[0]) if len(np.unique(x)) > 1 else 0.0
        return 0.0, slope, float(h.mean())
    a, b, c = np.polyfit(x, h, 2)
    return float(a) * 1000.0, float(b), float(c)


def classify(a: float, b: float) -> str:
    """Thesis Table 4.3."""
    if A_CURVE < a < A_CORNER and -B_CURVE < b < B_CURVE:
        return LineType.UPPER_HALF_CIRCLE
    if -A_CORNER < a < -A_CURVE and -B_CURVE < b < B_CURVE:
        return LineType.DOWN_HALF_CIRCLE
    if a >= A_CORNER and -B_CURVE < b < B_CURVE:
        return LineType.UP_CORNER
    if a <= -A_CORNER and -B_CURVE < b < B_CURVE:
        return LineType.DOWN_CORNER
    if b > B_SIDE:
        return LineType.SIDE_DOWN
    if b < -B_SIDE:
        return LineType.SIDE_UP
    return LineType.STRAIGHT


def process_line(line: list[BlackLine]) -> FieldLine:
    """ProcessLine: fit, classify, and verify a curve on the two halves (thesis 4.5.4)."""
    w = np.array([r.u for r in line], float)
    h = np.array([r.mid for r in line], float)
    a, b, c = fit_parabola(w, h)
    line_type = classify(a, b)
    if line_type in (LineType.UPPER_HALF_CIRCLE, LineType.DOWN_HALF_CIRCLE):
        half = len(line) // 2
        if half >= 3 and len(line) - half >= 3:
            a1 = fit_parabola(w[:half], h[:half])[0]
            a2 = fit_parabola(w[half:], h[half:])[0]
            if abs(a1) > A_HALF and abs(a2) > A_HALF:
                pass  # a curve, verified
            elif abs(a1) < A_HALF and abs(a2) < A_HALF:
                line_type = LineType.SIDE_DOWN if b > B_SIDE else LineType.SIDE_UP if b < -B_SIDE else LineType.STRAIGHT
            else:
                line_type = LineType.UP_CORNER if a > 0 else LineType.DOWN_CORNER
        else:
            line_type = LineType.STRAIGHT if abs(b) <= B_SIDE else (LineType.SIDE_DOWN if b > 0 else LineType.SIDE_UP)
    return FieldLine(tuple(line), direction_labels(line)[0], (a, b, c), line_type)
