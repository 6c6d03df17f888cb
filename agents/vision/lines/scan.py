"""Scan lines below the field border and the four rejection criteria (thesis section 4.5.1).

Every fifth column (``dist``), from the border down, each run of white pixels becomes a
"black line". Criterion 1: both ends must touch green. Criterion 2: the pixels beside its
interior must not be of another object's colour. Criterion 3: not longer than twice the
average length of the runs longer than three pixels. Criterion 4: it must be one of three
neighbouring runs close enough to each other (and not much shorter than the next).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from agents.vision.border import FieldBorder
from agents.vision.colors import ColorClass

DIST_PX = 5  # thesis 4.5.1: scan lines every fifth column ("dist")
LONG_RUN_PX = 3  # thesis 4.5.1 criterion 3: the average is over runs longer than three pixels
MAX_LENGTH_FACTOR = 2.0  # thesis 4.5.1 criterion 3: at most twice that average
MUCH_SHORTER = 1.0 / 3.0  # ours: criterion 4's "significantly smaller" than the next run
CRITERION_2_STRICT = False  # thesis: any non-white neighbour rejects; ours: only non-field colours,
# because a sloping line one or two pixels thick always has green beside its run's interior

GREEN, WHITE = int(ColorClass.GREEN), int(ColorClass.WHITE)


@dataclass(frozen=True)
class BlackLine:
    """One white run of a scan column: column ``u``, rows ``top``..``bottom`` (inclusive).

    ``rejected`` is the criterion (1-4) that discarded it, 0 when kept.
    """

    u: int
    top: int
    bottom: int
    rejected: int = 0

    @property
    def length(self) -> int:
        return self.bottom - self.top + 1

    @property
    def mid(self) -> float:
        return (self.top + self.bottom) / 2.0


def add_limit(a: BlackLine, b: BlackLine, dist: int = DIST_PX) -> float:
    """Thesis 4.5.2: AddLimit = (len1 + len2) / 2 + (w2 - w1) / dist - 1."""
    return (a.length + b.length) / 2.0 + abs(b.u - a.u) / dist - 1.0


def white_runs(labels: np.ndarray, border: FieldBorder, dist: int = DIST_PX) -> list[BlackLine]:
    """Every white run below the border in every ``dist``-th column, left to right, top to bottom."""
    height, width = labels.shape
    columns = np.arange(0, width, dist)
    start_rows = np.ceil(border.row_at(columns)).astype(int).clip(0, height)
    runs = []
    for u, start in zip(columns, start_rows):
        white = labels[start:, u] == WHITE
        if not white.any():
            continue
        edges = np.diff(np.concatenate([[0], white.astype(np.int8), [0]]))
        tops, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
        runs += [BlackLine(int(u), int(start + t), int(start + e - 1)) for t, e in zip(tops, ends)]
    return runs


def apply_criteria(labels: np.ndarray, runs: list[BlackLine], dist: int = DIST_PX) -> list[BlackLine]:
    """The runs with ``rejected`` set by the first criterion each one fails."""
    height, width = labels.shape
    allowed = (WHITE,) if CRITERION_2_STRICT else (GREEN, WHITE)
    long_lengths = [r.length for r in runs if r.length > LONG_RUN_PX]
    max_length = MAX_LENGTH_FACTOR * float(np.mean(long_lengths)) if long_lengths else np.inf
    judged = []
    for run in runs:
        criterion = 0
        if run.top == 0 or run.bottom == height - 1:
            criterion = 1
        elif labels[run.top - 1, run.u] != GREEN or labels[run.bottom + 1, run.u] != GREEN:
            criterion = 1
        elif run.length > 2:
            rows = slice(run.top + 1, run.bottom)
            sides = [labels[rows, c] for c in (run.u - 1, run.u + 1) if 0 <= c < width]
            if not all(np.isin(side, allowed).all() for side in sides):
                criterion = 2
        if criterion == 0 and run.length > max_length:
            criterion = 3
        judged.append(BlackLine(run.u, run.top, run.bottom, criterion))
    return _continuity(judged, dist)


def _close(a: BlackLine, b: BlackLine, dist: int) -> bool:
    return abs(b.u - a.u) == dist and abs(b.mid - a.mid) <= add_limit(a, b, dist)


def _continuity(runs: list[BlackLine], dist: int) -> list[BlackLine]:
    """Criterion 4: keep a run only inside a chain of three close runs in neighbouring columns."""
    kept = [r for r in runs if r.rejected == 0]
    by_column: dict[int, list[BlackLine]] = {}
    for r in kept:
        by_column.setdefault(r.u, []).append(r)

    def neighbours(r: BlackLine, step: int) -> list[BlackLine]:
        return [o for o in by_column.get(r.u + step, []) if _close(r, o, dist)]

    out = []
    for r in runs:
        if r.rejected:
            out.append(r)
            continue
        left, right = neighbours(r, -dist), neighbours(r, dist)
        chained = bool(left and right)
        chained |= any(neighbours(n, -dist) for n in left) or any(neighbours(n, dist) for n in right)
        much_shorter = any(r.length < MUCH_SHORTER * n.length for n in right)
        out.append(r if chained and not much_shorter else BlackLine(r.u, r.top, r.bottom, 4))
    return out
