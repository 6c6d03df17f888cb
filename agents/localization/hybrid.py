"""A particle filter corrected by the constraint solver (thesis 5.2-5.4).

As :class:`~agents.localization.particle.ParticleLocalizer`, and in each scan the thesis'
disambiguation and Algorithm 4 give candidate poses (each candidate position with the
orientation its landmarks imply). The best few join the poses injected particles are drawn
from; when one explains the scan far better than every particle (the robot was moved),
``max_injection`` of the cloud is drawn from the scan at once; and the estimate's polish starts from the best
candidate when that explains the scan at least as well as the cloud's own estimate.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from agents.localization.constraint import solve
from agents.localization.disambiguation import disambiguate
from agents.localization.measurement import ScanLikelihood
from agents.localization.particle import ParticleLocalizer
from agents.vision.percepts import LandmarkPercept
from world.field import Pose2D

CANDIDATES_USED = 4  # ours: how many of the best-ranked candidates join the injection samples


class HybridLocalizer(ParticleLocalizer):
    """Particle filter seeded and corrected with the constraint solver's candidates."""

    name = "hybrid"
    _candidate: Pose2D | None = None  # the scan's best constraint candidate

    def _extra_samples(self, scan: ScanLikelihood, percepts: Sequence[LandmarkPercept]) -> np.ndarray:
        observations = disambiguate(percepts, self.field)
        self._candidate = None
        if len(observations) < 2:
            return np.zeros((0, 3))
        best = solve(observations, self.field, self.config.field_margin_m, "mean").candidates[:CANDIDATES_USED]
        if not best:
            return np.zeros((0, 3))
        self._candidate = Pose2D(best[0].x_m, best[0].y_m, best[0].theta_rad)
        return np.array([[c.x_m, c.y_m, c.theta_rad] for c in best])

    def _prefer(self, scan: ScanLikelihood, percepts: Sequence[LandmarkPercept], seed: Pose2D) -> Pose2D:
        candidate = self._candidate
        if candidate is None:
            return seed
        xs, ys, ths = (np.array(pair) for pair in zip((candidate.x, candidate.y, candidate.theta), (seed.x, seed.y, seed.theta)))
        scores = scan.log_likelihood(xs, ys, ths)
        return candidate if scores[0] >= scores[1] else seed
