"""Line splitting and merging (thesis section 4.5.3): Algorithm 3, the split rules, Table 4.2, Merge.

Direction convention (our reading of Algorithm 3): heights are image rows, growing down,
and a line is walked left to right (column increasing). Algorithm 3 takes
``diff1 = height1 - height2`` and ``diff2 = height2 - height3`` and calls a segment "up"
when ``diff1 + diff2 >= 2``: the row decreases as the column increases, so "up" is up in
the displayed image (a "/" stroke), "down" a "\\" stroke.
"""

from __future__ import annotations

import enum
from collections.abc import Sequence

SEGMENT_SIZE = 3  # thesis 4.5.3: "non-overlapping adjacent segments of three black lines each"
DIRECTION_THRESHOLD_PX = 2  # thesis Algorithm 3: diff1 + diff2 >= +2 is up, <= -2 is down
MERGE_MAX_WIDTH_PX = 20  # thesis 4.5.3 Merge continuity: "no more than 20 pixels" in width
MERGE_MAX_HEIGHT_PX = 10  # thesis 4.5.3 Merge continuity: "no more than 10 pixels" in height
MIN_BLACK_LINES = 3  # thesis 4.5.2: a line has at least three black lines


class Direction(enum.Enum):
    """Direction label of a three-black-line segment (thesis Algorithm 3)."""

    UP = "up"
    DOWN = "down"
    STRAIGHT = "straight"


U, D, S = Direction.UP, Direction.DOWN, Direction.STRAIGHT
SEQUENCES: dict[tuple[Direction, ...], str] = {  # thesis Table 4.2
    (U,): "S1",  # side line with up gradient
    (D,): "S2",  # side line with down gradient
    (S,): "S3",  # straight line
    (U, S): "S4",  # up corner
    (S, U): "S5",  # down corner
    (D, S): "S6",  # down corner
    (S, D): "S7",  # up corner
    (U, S, D): "S8",  # upper half-circle
    (D, S, U): "S9",  # down half-circle
}
MERGE_COMPATIBLE = frozenset(  # thesis 4.5.3 Merge, criterion 1 (ordered pairs)
    {("S1", "S1"), ("S2", "S2"), ("S3", "S3"), ("S4", "S2"), ("S6", "S1"), ("S2", "S5"), ("S1", "S7")}
)
CIRCLE_SEQUENCES = ((U, S, D), (D, S, U))


def segment_direction(h1: float, h2: float, h3: float) -> Direction:
    """Algorithm 3's label of one segment from its three midpoint heights (rows)."""
    total = (h1 - h2) + (h2 - h3)
    if total >= DIRECTION_THRESHOLD_PX:
        return Direction.UP
    if total <= -DIRECTION_THRESHOLD_PX:
        return Direction.DOWN
    return Direction.STRAIGHT


def direction_labels(heights: Sequence[float]) -> tuple[tuple[Direction, ...], tuple[int, ...]]:
    """Algorithm 3: (LineDirection, ChangeSegments) of a line's midpoint heights (rows, left to right).

    Segments are consecutive triples; 1-2 trailing black lines belong to the last segment
    but do not vote. ChangeSegments holds the index of the segment where each label starts.
    """
    count = max(1, len(heights) // SEGMENT_SIZE)
    labels = [segment_direction(*heights[SEGMENT_SIZE * k : SEGMENT_SIZE * k + 3]) for k in range(count)]
    sequence, changes = [labels[0]], [0]
    for k, label in enumerate(labels):
        if label is not sequence[-1]:
            sequence.append(label)
            changes.append(k)
    return tuple(sequence), tuple(changes)


def compress(labels: Sequence[Direction]) -> tuple[Direction, ...]:
    """Labels with consecutive repeats removed."""
    out: list[Direction] = []
    for label in labels:
        if not out or out[-1] is not label:
            out.append(label)
    return tuple(out)


def split_segment(sequence: tuple[Direction, ...], changes: tuple[int, ...]) -> int | None:
    """Index of the segment where an unacceptable sequence is split, or None when acceptable."""
    if sequence in SEQUENCES:
        return None
    # Rule 1: up and down cannot be consecutive (a corner).
    for i in range(len(sequence) - 1):
        if {sequence[i], sequence[i + 1]} == {U, D}:
            return changes[i + 1]
    # Rule 2: up, straight, up / down, straight, down (a side line added to a circle line).
    for i in range(len(sequence) - 2):
        if sequence[i + 1] is S and sequence[i] is sequence[i + 2]:
            return changes[i + 2]
    # Rule 3: a straight label before or after a circle's sequence is cut off.
    if sequence[0] is S and sequence[1:4] in CIRCLE_SEQUENCES:
        return changes[1]
    if sequence[-1] is S and sequence[-4:-1] in CIRCLE_SEQUENCES:
        return changes[-1]
    # Not covered by the thesis' three rules (e.g. straight, up, straight): we split at the
    # last change so that every line ends with a Table 4.2 sequence, as the thesis states.
    return changes[-1]


def split_line(line: list[int], heights: Sequence[float]) -> list[tuple[list[int], tuple[Direction, ...]]]:
    """Split: the pieces of a line (black-line indices) with their Table 4.2 sequences.

    ``heights`` are the midpoint rows of all black lines, indexed by the line's entries.
    Pieces of fewer than three black lines are dropped.
    """
    out = []
    todo = [line]
    while todo:
        piece = todo.pop()
        sequence, changes = direction_labels([heights[i] for i in piece])
        cut = split_segment(sequence, changes)
        if cut is None:
            out.append((piece, sequence))
            continue
        at = SEGMENT_SIZE * cut
        todo.extend(p for p in (piece[at:], piece[:at]) if len(p) >= MIN_BLACK_LINES)
    out.sort(key=lambda item: item[0][0])
    return out


def merge_lines(
    lines: list[tuple[list[int], tuple[Direction, ...]]], columns: Sequence[float], heights: Sequence[float]
) -> list[tuple[list[int], tuple[Direction, ...]]]:
    """Merge (thesis 4.5.3): join compatible, non-overlapping, continuous pairs, closest first."""
    lines = list(lines)
    while True:
        best = None
        names = [SEQUENCES[sequence] for _, sequence in lines]
        for i, (first, _) in enumerate(lines):
            for j, (second, _) in enumerate(lines):
                if i == j or (names[i], names[j]) not in MERGE_COMPATIBLE:
                    continue
                end, begin = first[-1], second[0]
                gap_w = columns[begin] - columns[end]
                if gap_w <= 0:  # criterion 2: they overlap in columns
                    continue
                gap_h = abs(heights[begin] - heights[end])
                if gap_w > MERGE_MAX_WIDTH_PX or gap_h > MERGE_MAX_HEIGHT_PX:  # criterion 3
                    continue
                if best is None or gap_w + gap_h < best[0]:
                    best = (gap_w + gap_h, i, j)
        if best is None:
            lines.sort(key=lambda item: item[0][0])
            return lines
        _, i, j = best
        merged = (lines[i][0] + lines[j][0], compress(lines[i][1] + lines[j][1]))
        lines = [line for k, line in enumerate(lines) if k not in (i, j)] + [merged]
