"""Field lines (thesis section 4.5): scan lines, line formation, split and merge, classification."""

# Placeholder until the line stage lands: no line landmarks.
from dataclasses import dataclass as _dataclass


@_dataclass(frozen=True)
class LineTrace:
    pass


def detect_line_landmarks(labels, border, frame, model):
    return (), LineTrace()
