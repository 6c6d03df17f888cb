"""What drills' summaries share: outcome counts, a column's values, medians, and their one-line text."""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence

import numpy as np

from scenarios.drills.base import Value
from scenarios.drills.records import TrialRecord


def counts(records: Sequence[TrialRecord], outcomes: Iterable[str]) -> dict[str, int]:
    """How many trials came to each outcome, in the drill's order."""
    found = [r.outcome for r in records]
    return {name: found.count(name) for name in outcomes}


def values(records: Sequence[TrialRecord], column: str, outcome: str | None = None) -> list[Value]:
    """A column's values (None left out), of the trials with ``outcome`` (None: of all)."""
    return [r.values[column] for r in records
            if r.values[column] is not None and (outcome is None or r.outcome == outcome)]


def median(numbers: Sequence[float]) -> float | None:
    """Their median; None when there are none."""
    return float(np.median(numbers)) if numbers else None


def percent(share: float | None) -> str:
    """A share as a whole percentage, ``none`` when there is none."""
    return "none" if share is None or math.isnan(share) else f"{share:.0%}"


def interval(bounds: Sequence[float | None]) -> str:
    """A 95% interval of a share, ``low-high`` in whole percentages."""
    return f"{percent(bounds[0])}-{percent(bounds[1])}"


def seconds(value: float | None) -> str:
    """Seconds to a tenth, ``none`` when there are none."""
    return "none" if value is None else f"{value:.1f} s"
