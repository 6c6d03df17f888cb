"""What the field-line stage saw in one frame, for a debug overlay (thesis figures 4.7-4.11)."""

from __future__ import annotations

from dataclasses import dataclass

from agents.vision.lines.classification import ClassifiedLine
from agents.vision.lines.landmarks import CircleSighting, CornerSighting, JunctionSighting
from agents.vision.lines.scan_lines import BlackLines


@dataclass(frozen=True, eq=False)
class LineTrace:
    """The intermediate results of :func:`agents.vision.lines.detect_line_landmarks`.

    ``black_lines``: every white run of the scan columns with the criterion that rejected it
    (0 = kept; overlay colours in :data:`~agents.vision.lines.scan_lines.CRITERION_COLOR`);
    ``lines``: the lines after split and merge, with their midpoints (pixels), Table 4.2
    sequence, classification and fitted ``(a, b, c)``; ``corners``/``junctions``: the L
    corners and T junctions that passed the checks of
    :mod:`~agents.vision.lines.verification` (an L corner may have become a T junction);
    ``rejected``: the pixels (u, v) of the sightings those checks dropped; ``circle``: the
    located half-circle, if any (``circle.accepted`` False when it failed its sanity checks).
    """

    black_lines: BlackLines
    lines: tuple[ClassifiedLine, ...] = ()
    corners: tuple[CornerSighting, ...] = ()
    junctions: tuple[JunctionSighting, ...] = ()
    rejected: tuple[tuple[float, float], ...] = ()
    circle: CircleSighting | None = None

    @classmethod
    def empty(cls) -> LineTrace:
        return cls(BlackLines.empty())
