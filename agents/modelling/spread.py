"""The spread of a 2-D Gaussian: the larger standard deviation of a position covariance, in closed form
(the models ask for it every step, where a general eigenvalue routine's call costs more than the sum)."""

from __future__ import annotations

import math


def largest_eigenvalue(a: float, b: float, c: float) -> float:
    """The larger eigenvalue of the symmetric 2x2 matrix [[a, b], [b, c]], at least 0."""
    a, b, c = float(a), float(b), float(c)
    return max(0.5 * (a + c) + math.sqrt(0.25 * (a - c) ** 2 + b * b), 0.0)
