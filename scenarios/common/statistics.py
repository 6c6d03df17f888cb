"""Summary statistics of a sample of numbers, NaN where a statistic is undefined."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from scipy import stats


def mean(values: Sequence[float] | np.ndarray) -> float:
    """The mean of ``values``; NaN when there are none."""
    data = np.asarray(values, dtype=float)
    return float(np.mean(data)) if data.size else math.nan


def median(values: Sequence[float] | np.ndarray) -> float:
    """The median of ``values``; NaN when there are none."""
    data = np.asarray(values, dtype=float)
    return float(np.median(data)) if data.size else math.nan


def ci95_half_width(values: Sequence[float] | np.ndarray) -> float:
    """Half-width of the Student t 95% interval of the mean of ``values`` (same unit); NaN when n < 2."""
    data = np.asarray(values, dtype=float)
    n = data.size
    if n < 2:
        return math.nan
    return float(stats.t.ppf(0.975, n - 1) * np.std(data, ddof=1) / math.sqrt(n))
