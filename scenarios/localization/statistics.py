"""Per-method error statistics of localization samples (thesis Tables 6.1 and 6.2).

One implementation for every consumer: the scenario report (:class:`ScenarioReport`,
written by :mod:`scenarios.localization.tables` and drawn by
:mod:`scenarios.localization.figures`) and the ``localize`` command (:func:`summarize`).
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
