"""Summary statistics of a sample (NaN where one is undefined) and Wilson's interval of a proportion."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from scipy import stats

Z95 = 1.959963984540054  # the standard normal's 97.5th percentile

Interval = tuple[float, float]


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


def wilson_interval(successes: float, n: int, z: float = Z95) -> Interval:
    """Wilson's score interval of a proportion ``successes / n``; (NaN, NaN) for n = 0."""
    if n <= 0:
        return (math.nan, math.nan)
    p = successes / n
    denominator = 1.0 + z * z / n
    centre = (p + z * z / (2.0 * n)) / denominator
    half = z * math.sqrt(p * (1.0 - p) / n + z * z / (4.0 * n * n)) / denominator
    return (max(0.0, centre - half), min(1.0, centre + half))
