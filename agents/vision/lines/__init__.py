"""Field lines (thesis section 4.5): scan lines, line formation, split and merge, classification.

:func:`detect_line_landmarks` runs the stage on a segmented frame and returns the L corners,
T junctions and centre circle it found, with a :class:`LineTrace` of what it saw.
"""

from agents.vision.lines.detect import detect_line_landmarks, find_lines
from agents.vision.lines.trace import LineTrace

__all__ = ["LineTrace", "detect_line_landmarks", "find_lines"]
