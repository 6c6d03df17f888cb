"""Likelihood of a scan's percepts at many poses, without disambiguation (for the particle filter).

Each percept may be any of a set of landmarks: itself when it names one (posts of known
side, goal centres, the circle); either post of its goal for a post of unknown side; any
L corner for a corner; either T junction for a junction. Its likelihood at a pose is the
best over that set of a Gaussian in distance (sigma ``distance_sigma_m + distance_sigma_rel
* distance``) and in bearing (``bearing_sigma_rad``), mixed with a constant
``outlier_probability`` so that one false percept cannot rule out the true pose (ours).
The percepts count as independent: the scan's log-likelihood is the sum over percepts.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from agents.localization.disambiguation import unique_landmark
from agents.localization.kernels import pair_log_likelihoods, percept_log_likelihoods
from agents.vision.percepts import LandmarkPercept
from world.field import FIELD, FieldGeometry, Landmark, LandmarkKind


@dataclass(frozen=True)
class MeasurementConfig:
    """Noise of the percepts as the likelihood assumes it (ours: a little above the oracle's 5% / 2 deg)."""

    distance_sigma_rel: float = 0.08
    distance_sigma_m: float = 0.05
    bearing_sigma_rad: float = math.radians(4.0)
    outlier_probability: float = 0.05


def possible_landmarks(percept: LandmarkPercept, field: FieldGeometry = FIELD) -> tuple[Landmark, ...]:
    """The landmarks ``percept`` may show (module docstring)."""
    unique = unique_landmark(percept, field)
    if unique is not None:
        return (unique,)
    same_kind = [lm for lm in field.landmarks if lm.kind is percept.kind]
    if percept.kind in (LandmarkKind.GOAL_POST, LandmarkKind.GOAL_CENTER) and percept.goal is not None:
        same_kind = [lm for lm in same_kind if lm.goal is percept.goal]
    return tuple(same_kind)


class ScanLikelihood:
    """The percepts of one scan, ready to be scored at (N,) poses at once."""

    def __init__(self, percepts: Sequence[LandmarkPercept], config: MeasurementConfig, field: FieldGeometry = FIELD):
        self.percepts = tuple(percepts)
        self.config = config
        self.options = [possible_landmarks(p, field) for p in self.percepts]
        keep = [i for i, options in enumerate(self.options) if options]
        self.percepts = tuple(self.percepts[i] for i in keep)
        self.options = [self.options[i] for i in keep]
        sizes = np.array([len(o) for o in self.options], dtype=int)
        self.starts = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(int) if len(sizes) else np.zeros(0, int)
        self.owner = np.repeat(np.arange(len(self.options)), sizes)
        self.lx = np.array([lm.x for options in self.options for lm in options], float)
        self.ly = np.array([lm.y for options in self.options for lm in options], float)
        self.distance = np.array([p.distance_m for p in self.percepts], float)
        self.bearing = np.array([p.bearing_rad for p in self.percepts], float)
        self.sigma_d = config.distance_sigma_m + config.distance_sigma_rel * self.distance
        self.sigma_b = config.bearing_sigma_rad

    def __len__(self) -> int:
        return len(self.percepts)

    def pair_log_likelihood(self, x: np.ndarray, y: np.ndarray, theta: np.ndarray) -> np.ndarray:
        """(N, P) Gaussian log-likelihood (without constants) of each (percept, possible landmark) pair."""
        x, y, theta = _poses(x, y, theta)
        return pair_log_likelihoods(x, y, theta, self.lx, self.ly, self.owner, self.distance, self.sigma_d,
                                    self.bearing, float(self.sigma_b))

    def percept_log_likelihood(self, x: np.ndarray, y: np.ndarray, theta: np.ndarray) -> np.ndarray:
        """(N, M) log-likelihood of each percept: best landmark of its set, mixed with outliers."""
        x, y, theta = _poses(x, y, theta)
        return percept_log_likelihoods(x, y, theta, self.lx, self.ly, self.owner, self.starts, self.distance,
                                       self.sigma_d, self.bearing, float(self.sigma_b),
                                       float(self.config.outlier_probability))

    def log_likelihood(self, x: np.ndarray, y: np.ndarray, theta: np.ndarray) -> np.ndarray:
        """(N,) log-likelihood of the whole scan at each pose; zeros when the scan is empty."""
        if not len(self):
            return np.zeros(np.atleast_1d(x).shape)
        return self.percept_log_likelihood(x, y, theta).sum(axis=1)

    def associate(self, x: float, y: float, theta: float) -> list[tuple[int, Landmark, float]]:
        """For one pose: each percept's index, its most likely landmark and that pair's log-likelihood."""
        pairs = self.pair_log_likelihood(np.array([x]), np.array([y]), np.array([theta]))[0]
        found = []
        for m, start in enumerate(self.starts):
            k = int(np.argmax(pairs[start : start + len(self.options[m])]))
            found.append((m, self.options[m][k], float(pairs[start + k])))
        return found


def _poses(*coordinates: np.ndarray) -> tuple[np.ndarray, ...]:
    """Pose coordinates (x, y m; theta rad) as the kernels take them: contiguous float64 arrays, at least 1-D."""
    return tuple(np.ascontiguousarray(np.atleast_1d(v), float) for v in coordinates)
