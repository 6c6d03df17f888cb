"""Per-method error statistics of localization samples (thesis Tables 6.1 and 6.2).

One implementation for every consumer: the scenario report (:class:`ScenarioReport`,
written by :mod:`scenarios.localization.tables` and drawn by
:mod:`scenarios.localization.figures`) and the ``localize`` command (:func:`summarize`).
Samples taken periodically while the robots play (:mod:`scenarios.localization.periodic`)
also get :class:`PlayingStatistics`: 95th percentiles and the share of samples "lost".
Units: position errors in centimetres, orientation errors in degrees.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from scenarios.common.io import json_number
from scenarios.common.statistics import ci95_half_width, mean, median
from scenarios.localization.samples import LocalizationSample
from scenarios.localization.spec import ScenarioSpec


@dataclass(frozen=True)
class MethodStatistics:
    """One method's errors over a scenario: position in cm, orientation in degrees.

    ``samples``: samples with an estimate (the n of the means and intervals);
    ``missing``: samples of the method without an estimate, left out of everything else.
    ``*_ci95_*``: half-width of the Student t 95% interval of the mean, NaN when n < 2.
    ``localize_ms_median``: median wall time of the method's ``localize`` per scan (ms), a
    figure of the machine that ran it, not of the scenario.
    """

    samples: int
    missing: int
    position_mean_cm: float
    position_ci95_cm: float
    position_median_cm: float
    orientation_mean_deg: float
    orientation_ci95_deg: float
    orientation_median_deg: float
    localize_ms_median: float = math.nan

    def to_json(self) -> dict[str, float | int | None]:
        """The statistics as a JSON-ready dict, NaN as ``None``."""
        keys = (
            "position_mean_cm",
            "position_ci95_cm",
            "orientation_mean_deg",
            "orientation_ci95_deg",
            "samples",
            "missing",
            "position_median_cm",
            "orientation_median_deg",
            "localize_ms_median",
        )
        return {key: json_number(getattr(self, key)) for key in keys}


def _statistics(rows: Sequence[LocalizationSample]) -> MethodStatistics:
    position_cm = np.array([s.position_error_m for s in rows], dtype=float) * 100.0
    orientation_deg = np.array([s.orientation_error_deg for s in rows], dtype=float)
    ok = np.isfinite(position_cm) & np.isfinite(orientation_deg)
    pos, ori = position_cm[ok], orientation_deg[ok]
    return MethodStatistics(
        samples=int(ok.sum()),
        missing=int((~ok).sum()),
        position_mean_cm=mean(pos),
        position_ci95_cm=ci95_half_width(pos),
        position_median_cm=median(pos),
        orientation_mean_deg=mean(ori),
        orientation_ci95_deg=ci95_half_width(ori),
        orientation_median_deg=median(ori),
        localize_ms_median=median(np.array([s.compute_ms for s in rows if math.isfinite(s.compute_ms)])),
    )


def method_order(samples: Sequence[LocalizationSample]) -> tuple[str, ...]:
    """The methods of ``samples`` in order of first appearance."""
    return tuple(dict.fromkeys(s.method for s in samples))


def method_statistics(samples: Sequence[LocalizationSample]) -> dict[str, MethodStatistics]:
    """Per method (first-appearance order): its :class:`MethodStatistics`."""
    return {m: _statistics([s for s in samples if s.method == m]) for m in method_order(samples)}


def summarize(samples: Sequence[LocalizationSample]) -> dict[str, dict[str, float]]:
    """Per method: mean and median position (cm) and orientation (deg) errors, counts, median localize() ms.

    ``samples`` counts all of the method's samples, ``with_estimate`` those with an estimate
    (the ones the errors are taken over); the numbers are those of :func:`method_statistics`.
    """
    return {
        method: {
            "samples": st.samples + st.missing,
            "with_estimate": st.samples,
            "position_mean_cm": st.position_mean_cm,
            "position_median_cm": st.position_median_cm,
            "orientation_mean_deg": st.orientation_mean_deg,
            "orientation_median_deg": st.orientation_median_deg,
            "localize_ms_median": st.localize_ms_median,
        }
        for method, st in method_statistics(samples).items()
    }


LOST_M = 0.5  # a position error beyond this (m), or no estimate at all: the robot is lost


@dataclass(frozen=True)
class PlayingStatistics:
    """One policy's errors over the samples taken while its robots played (periodic sampling).

    ``samples``: all its samples; ``missing``: those without an estimate; ``robots``: the
    measured robots that gave them. Position in cm, orientation in degrees, over the samples
    with an estimate: means, 95th percentiles (linear interpolation). ``lost_percent``: the
    share of all samples, in percent, whose position error is over :data:`LOST_M` or that
    have no estimate. NaN where there is nothing to take a statistic of.
    """

    samples: int
    missing: int
    robots: int
    position_mean_cm: float
    position_p95_cm: float
    orientation_mean_deg: float
    orientation_p95_deg: float
    lost_percent: float

    def to_json(self) -> dict[str, float | int | None]:
        """The statistics as a JSON-ready dict, NaN as ``None``."""
        keys = ("samples", "missing", "robots", "position_mean_cm", "position_p95_cm", "orientation_mean_deg",
                "orientation_p95_deg", "lost_percent")
        return {key: json_number(getattr(self, key)) for key in keys}


def _p95(values: np.ndarray) -> float:
    return float(np.percentile(values, 95.0)) if values.size else math.nan


def _playing(rows: Sequence[LocalizationSample]) -> PlayingStatistics:
    position_cm = np.array([s.position_error_m for s in rows], dtype=float) * 100.0
    orientation_deg = np.array([s.orientation_error_deg for s in rows], dtype=float)
    ok = np.isfinite(position_cm) & np.isfinite(orientation_deg)
    pos, ori = position_cm[ok], orientation_deg[ok]
    lost = int((pos > LOST_M * 100.0).sum()) + int((~ok).sum())
    return PlayingStatistics(
        samples=len(rows),
        missing=int((~ok).sum()),
        robots=len({s.robot for s in rows}),
        position_mean_cm=mean(pos),
        position_p95_cm=_p95(pos),
        orientation_mean_deg=mean(ori),
        orientation_p95_deg=_p95(ori),
        lost_percent=100.0 * lost / len(rows) if rows else math.nan,
    )


def playing_statistics(samples: Sequence[LocalizationSample]) -> dict[str, PlayingStatistics]:
    """Per label (the policy's name, first-appearance order): its :class:`PlayingStatistics`."""
    return {m: _playing([s for s in samples if s.method == m]) for m in method_order(samples)}


@dataclass(frozen=True)
class Quantity:
    """Position or orientation: which statistics and which thesis fields, the thesis table, the unit."""

    title: str
    thesis_table: str
    mean: str
    ci95: str
    median: str
    unit: str


POSITION = Quantity("Position error (cm)", "6.1", "position_mean_cm", "position_ci95_cm", "position_median_cm", "cm")
ORIENTATION = Quantity(
    "Orientation error (degrees)", "6.2", "orientation_mean_deg", "orientation_ci95_deg", "orientation_median_deg", "deg"
)


@dataclass(frozen=True)
class ScenarioReport:
    """Everything one scenario produced.

    ``key``: short name for file names and table rows (``"1"``, a file stem);
    ``samples``: sorted by run, robot, event, then method; ``run_seeds``: one per run;
    ``wall_seconds`` / ``sim_seconds``: real and simulated time over all runs, seconds;
    ``versions``: package name -> version.
    """

    key: str
    spec: ScenarioSpec
    samples: tuple[LocalizationSample, ...]
    run_seeds: tuple[int, ...]
    wall_seconds: float
    sim_seconds: float
    versions: dict

    @cached_property
    def statistics(self) -> dict[str, MethodStatistics]:
        return method_statistics(self.samples)

    @cached_property
    def playing(self) -> dict[str, PlayingStatistics]:
        """Per policy, the statistics of play (empty unless the scenario samples periodically)."""
        return playing_statistics(self.samples) if self.spec.periodic else {}
