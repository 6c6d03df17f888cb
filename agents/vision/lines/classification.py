"""Line classification (thesis section 4.5.4): least-squares parabola, Table 4.3, ProcessLine.

A degree-2 polynomial ``h = a w^2 + b w + c`` (section 2.3.1) is fitted to the black-line
midpoints ``(w_i, h_i)`` of a line, in image pixels (``w`` column, ``h`` row, growing
down). ``a`` is scaled by 1000 and compared with Table 4.3's thresholds (ProcessLine). A
half-circle is verified by fitting each half of the line again: both ``|a1|, |a2| > 1``
keep the curve, both ``< 1`` make it a side line, anything else a corner.

Our reading of ``b``: Table 4.3 compares ``b`` with slopes (|b| > 0.07 is a side line with
a gradient), so we measure it at the line's own middle column, ``b_mid = 2 a w_mid + b``
(the same fit with ``w`` counted from the line's mean column). With raw columns ``b`` is
the slope at the image's left edge: a short, slightly bent piece of a rising line at
columns 75-85 gives raw ``b = +1.45``, "down gradient". ``a`` is the same either way, and
``coefficients`` keep the raw ``(a, b, c)`` for drawing.

Sign reading (rows grow down): ``a > 0`` is a parabola with its highest image point inside
("upper half-circle", an "up corner" when sharper), and ``b > 0`` a line whose row grows to
the right, i.e. drawn going down ("side line with down gradient").
"""

from __future__ import annotations

import enum
import functools
from dataclasses import dataclass

import numpy as np

from agents.vision.lines.split_merge import Direction

A_SCALE = 1000.0  # thesis 4.5.4: "Parameter a is scaled to 1000 times of its original value"
CIRCLE_A_MIN = 0.7  # thesis Table 4.3: half-circle when 0.7 < |a| < 5.2
CORNER_A_MIN = 5.2  # thesis Table 4.3: corner when |a| >= 5.2
CURVE_B_MAX = 0.6  # thesis Table 4.3: half-circles and corners need -0.6 < b < 0.6
SIDE_B_MIN = 0.07  # thesis Table 4.3: side line when |b| > 0.07, else straight
HALF_A_MIN = 1.0  # thesis 4.5.4: a curve is verified when |a1| > 1 and |a2| > 1
# Not in the thesis: a line of fewer than MIN_CURVE_BLACK_LINES black lines is classified by
# its gradient only (a taken as 0). Three to five midpoints 5 px apart, quantized to half
# pixels, give a parabola with |a| up to ~10 (scaled) on a perfectly straight line, beyond
# every threshold of Table 4.3; such short pieces come from Split cutting a line whose
# slope is near Algorithm 3's 2 px-per-segment threshold (about 0.2 rows per column).
MIN_CURVE_BLACK_LINES = 15


class LineKind(enum.Enum):
    """What ProcessLine concluded a line is (thesis Table 4.3)."""

    UPPER_HALF_CIRCLE = "upper_half_circle"
    DOWN_HALF_CIRCLE = "down_half_circle"
    UP_CORNER = "up_corner"
    DOWN_CORNER = "down_corner"
    SIDE_LINE_DOWN = "side_line_down"
    SIDE_LINE_UP = "side_line_up"
    STRAIGHT = "straight"

    @property
    def is_curve(self) -> bool:
        return self in (LineKind.UPPER_HALF_CIRCLE, LineKind.DOWN_HALF_CIRCLE)

    @property
    def is_corner(self) -> bool:
        return self in (LineKind.UP_CORNER, LineKind.DOWN_CORNER)

    @property
    def side_direction(self) -> Direction | None:
        """The direction of a side line (FindCorner compares them); None for other kinds."""
        return SIDE_DIRECTIONS.get(self)


SIDE_DIRECTIONS = {  # LineKind.side_direction
    LineKind.SIDE_LINE_UP: Direction.UP,
    LineKind.SIDE_LINE_DOWN: Direction.DOWN,
    LineKind.STRAIGHT: Direction.STRAIGHT,
}


@dataclass(frozen=True, eq=False)
class ClassifiedLine:
    """A line after split/merge and classification.

    ``u``, ``v``: its black lines' midpoints (column, row; pixels), left to right;
    ``directions``: its Table 4.2 label sequence; ``kind``: ProcessLine's conclusion after
    the curve verification; ``coefficients``: the fitted ``(a, b, c)`` of
    ``v = a u^2 + b u + c`` in pixels (``a`` not scaled); ``straight_fit``: the
    least-squares ``(slope, intercept)`` of ``v = slope u + intercept``, for corner pixels.
    """

    u: np.ndarray
    v: np.ndarray
    directions: tuple[Direction, ...]
    kind: LineKind
    coefficients: tuple[float, float, float]
    straight_fit: tuple[float, float]

    @functools.cached_property
    def start(self) -> tuple[float, float]:
        return float(self.u[0]), float(self.v[0])

    @functools.cached_property
    def end(self) -> tuple[float, float]:
        return float(self.u[-1]), float(self.v[-1])

    @property
    def a_scaled(self) -> float:
        return self.coefficients[0] * A_SCALE

    @property
    def b_mid(self) -> float:
        """Slope ``dv/du`` of the fitted parabola at the line's mean column (rows per column)."""
        a, b, _ = self.coefficients
        return 2.0 * a * float(self.u.mean()) + b


def fit_polynomial(w: np.ndarray, h: np.ndarray, degree: int = 2) -> tuple[float, ...]:
    """Least-squares ``h = sum c_k w^k`` coefficients, highest power first (thesis 2.3.1).

    Solved in closed form on centred columns ``x = w - mean(w)`` with polynomials orthogonal
    over them (1, x, x^2 - (S3 / S2) x - S2 / n, where ``Sk = sum x^k``), then mapped back:
    the same minimizer as the thesis' normal equations, without their ill-conditioning
    (sums of ``w^4`` reach 1e9 px^4). Needs at least ``degree + 1`` distinct columns.
    """
    if degree not in (1, 2):
        raise ValueError(f"degree must be 1 or 2; got {degree}")
    line, parabola = _least_squares(np.asarray(w, float).tolist(), np.asarray(h, float).tolist(), degree == 2)
    return parabola if degree == 2 else line


def _least_squares(
    ws: list[float], hs: list[float], parabola: bool
) -> tuple[tuple[float, float], tuple[float, float, float] | None]:
    """The straight line (slope, intercept) and, if ``parabola``, the parabola (a, b, c) of :func:`fit_polynomial`.

    Plain floats: a line has a few dozen midpoints, fewer than numpy calls would cost.
    """
    n = len(ws)
    m = sum(ws) / n
    x = [wi - m for wi in ws]
    s2 = sum([xi * xi for xi in x])
    if s2 == 0.0:
        raise ValueError("a fit needs at least two distinct columns")
    slope = sum([xi * hi for xi, hi in zip(x, hs)]) / s2
    mean_h = sum(hs) / n
    line = (slope, mean_h - slope * m)
    if not parabola:
        return line, None
    ratio = sum([xi * xi * xi for xi in x]) / s2
    offset = s2 / n
    p2 = [xi * xi - ratio * xi - offset for xi in x]  # orthogonal to 1 and x over the columns
    p2_norm = sum([p * p for p in p2])
    if p2_norm <= 1e-12 * s2 * offset:
        raise ValueError("a parabola needs at least three distinct columns")
    a = sum([p * hi for p, hi in zip(p2, hs)]) / p2_norm
    b = slope - a * ratio  # the parabola a p2 + slope x + mean_h in powers of x ...
    c = mean_h - a * offset
    return line, (a, b - 2.0 * a * m, a * m * m - b * m + c)  # ... and in powers of w


def process_line(a_scaled: float, b: float) -> LineKind:
    """ProcessLine: thesis Table 4.3 on the scaled ``a`` and on ``b``."""
    b_small = -CURVE_B_MAX < b < CURVE_B_MAX
    if CIRCLE_A_MIN < a_scaled < CORNER_A_MIN and b_small:
        return LineKind.UPPER_HALF_CIRCLE
    if -CORNER_A_MIN < a_scaled < -CIRCLE_A_MIN and b_small:
        return LineKind.DOWN_HALF_CIRCLE
    if a_scaled >= CORNER_A_MIN and b_small:
        return LineKind.UP_CORNER
    if a_scaled <= -CORNER_A_MIN and b_small:
        return LineKind.DOWN_CORNER
    if b > SIDE_B_MIN:
        return LineKind.SIDE_LINE_DOWN
    if b < -SIDE_B_MIN:
        return LineKind.SIDE_LINE_UP
    return LineKind.STRAIGHT


def verify_curve(w: np.ndarray, h: np.ndarray, kind: LineKind, a_scaled: float, slope: float) -> LineKind:
    """The thesis' curve check: refit both halves; keep the curve, or call it a side line or a corner."""
    n = len(w)
    halves = [(w[: (n + 1) // 2], h[: (n + 1) // 2]), (w[n // 2 :], h[n // 2 :])]
    # A half of fewer than three points has no parabola: it counts as flat (a = 0).
    a_half = [abs(fit_polynomial(hw, hh)[0]) * A_SCALE if len(hw) >= 3 else 0.0 for hw, hh in halves]
    if all(a > HALF_A_MIN for a in a_half):
        return kind
    if all(a < HALF_A_MIN for a in a_half):
        return process_line(0.0, slope)  # a side line: its gradient from the straight fit
    return LineKind.UP_CORNER if a_scaled > 0 else LineKind.DOWN_CORNER


def classify_line(w: np.ndarray, h: np.ndarray, directions: tuple[Direction, ...]) -> ClassifiedLine:
    """Fit, ProcessLine and (for half-circles) the curve verification of one line's midpoints."""
    w = np.asarray(w, float)
    h = np.asarray(h, float)
    columns = w.tolist()
    straight, (a, b, c) = _least_squares(columns, h.tolist(), parabola=True)
    if len(w) < MIN_CURVE_BLACK_LINES:
        kind = process_line(0.0, straight[0])
    else:
        kind = process_line(a * A_SCALE, 2.0 * a * (sum(columns) / len(columns)) + b)
    if kind.is_curve:
        kind = verify_curve(w, h, kind, a * A_SCALE, straight[0])
    return ClassifiedLine(w, h, directions, kind, (a, b, c), straight)
