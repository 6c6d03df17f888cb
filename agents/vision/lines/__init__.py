"""Field lines (thesis section 4.5): scan lines, line formation, split and merge, classification.

:func:`detect_line_landmarks` runs the stage on a segmented frame and returns the L corners,
T junctions and centre circle it found, with a :class:`LineTrace` of what it saw.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from agents.vision.border import FieldBorder
from agents.vision.camera_models import CameraModel
from agents.vision.frame import CameraFrame
from agents.vision.lines.line_landmarks import line_landmarks
from agents.vision.lines.scan import BlackLine, apply_criteria, white_runs
from agents.vision.lines.shapes import FieldLine, form_lines, merge_lines, process_line, split_line
from agents.vision.percepts import LandmarkPercept


@dataclass(frozen=True)
class LineTrace:
    """What the line stage saw: every black line (with its rejecting criterion), the
    classified lines, and the (name, pixel) of each landmark found."""

    black_lines: tuple[BlackLine, ...] = ()
    lines: tuple[FieldLine, ...] = ()
    marks: tuple[tuple[str, tuple[float, float]], ...] = ()


def detect_line_landmarks(
    labels: np.ndarray, border: FieldBorder, frame: CameraFrame, model: CameraModel
) -> tuple[tuple[LandmarkPercept, ...], LineTrace]:
    """L corners, T junctions and the centre circle of a segmented frame."""
    if not border.found:
        return (), LineTrace()
    runs = apply_criteria(labels, white_runs(labels, border))
    formed = [piece for line in form_lines(runs) for piece in split_line(line)]
    lines = [process_line(line) for line in merge_lines(formed)]
    percepts, marks = line_landmarks(lines, frame, model)
    return tuple(percepts), LineTrace(tuple(runs), tuple(lines), tuple(marks))
