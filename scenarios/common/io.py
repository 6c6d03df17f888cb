"""Writing result files: text, JSON, CSV, and replacing a file atomically.

Every writer creates missing parent directories, writes UTF-8 and returns the path it
wrote. JSON is indented by 2 and ends with a newline; NaN and infinities are refused
unless ``allow_nan`` (:func:`json_safe` turns them into ``None`` first).
"""

from __future__ import annotations

import csv
import json
import math
import os
from collections.abc import Iterable, Sequence
from pathlib import Path


def write_text(path: Path, text: str) -> Path:
    """``text`` into ``path``."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    return path


def write_text_atomic(path: Path, text: str) -> Path:
    """``text`` into ``path`` through a ``.tmp`` file beside it: a reader never finds half a file."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    temporary = path.with_suffix(".tmp")
    temporary.write_text(text, encoding="utf-8")
    os.replace(temporary, path)
    return path


def write_json(path: Path, data: object, *, allow_nan: bool = False) -> Path:
    """``data`` as indented JSON into ``path``."""
    return write_text(path, json.dumps(data, indent=2, allow_nan=allow_nan) + "\n")


def write_csv(path: Path, header: Sequence[str], rows: Iterable[Sequence[object]]) -> Path:
    """A CSV file: the ``header`` row, then ``rows``."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="", encoding="utf-8") as handle:
        writer = csv.writer(handle)
        writer.writerow(header)
        writer.writerows(rows)
    return path


def json_number(value: float) -> float | None:
    """``value``, or ``None`` for a NaN or infinite float (JSON has neither)."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def json_safe(value: object) -> object:
    """``value`` with every non-finite float replaced by ``None``, tuples as lists."""
    if isinstance(value, float):
        return json_number(value)
    if isinstance(value, dict):
        return {k: json_safe(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [json_safe(v) for v in value]
    return value
