"""Least-squares polish of a pose on one scan's percepts (Gauss-Newton), for the particle filters.

A particle cloud places the robot only as finely as its particles lie; this finds, near a
starting pose, the pose that best explains the scan (weighted distance and bearing
residuals, the measurement model's sigmas). Each percept is tied to its most likely
landmark at the start and used only when that pair is within ``GATE_SIGMA`` standard
deviations; at least two distinct landmarks are needed, and the result is discarded when it moved
farther than the trust region or did not lower the cost. With noise-free percepts this
returns the true pose. Its covariance is the least-squares one scaled by the a-posteriori
variance of unit weight (the residuals' own size): near zero when the percepts agree
perfectly, about the model's when they scatter as the sigmas say.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from agents.localization.estimate import Covariance
from agents.localization.kernels import pose_residuals
from agents.localization.measurement import ScanLikelihood
from world.field import Landmark, LandmarkId, Pose2D, normalize_angle

GATE_SIGMA = 3.0  # ours: a percept joins the fit when its pair's combined error is within this many sigmas
TRUST_RADIUS_M = 0.5  # ours: a polished pose farther than this from its start is discarded ...
TRUST_ANGLE_RAD = 0.5  # ... or turned more than this
ITERATIONS = 10
STEP_TOLERANCE = 1e-8  # m and rad: converged
MIN_EIGEN_RATIO = 1e-9  # smallest over largest eigenvalue of the normal matrix: below it the percepts do not fix the pose
MIN_LANDMARKS = 2


@dataclass(frozen=True)
class Refinement:
    """The polished pose, the landmarks it used and its covariance (x m, y m, theta rad)."""

    pose: Pose2D
    landmarks: tuple[LandmarkId, ...]
    covariance: Covariance


def _residuals(pose: np.ndarray, lx, ly, d, b, sd, sb) -> tuple[np.ndarray, np.ndarray]:
    """The weighted residuals and their Jacobian at ``pose`` (x m, y m, theta rad)
    (:func:`agents.localization.kernels.pose_residuals`)."""
    return pose_residuals(float(pose[0]), float(pose[1]), float(pose[2]), lx, ly, d, b, sd, float(sb))


def _well_posed(normal: np.ndarray) -> bool:
    """Whether the normal matrix fixes all three pose components (not near singular)."""
    eigen = np.linalg.eigvalsh(normal)
    return bool(np.isfinite(eigen).all() and eigen[0] > MIN_EIGEN_RATIO * eigen[-1] and eigen[0] > 0.0)


def refine(scan: ScanLikelihood, start: Pose2D) -> Refinement | None:
    """The least-squares pose near ``start`` (module docstring), or None."""
    chosen: list[tuple[int, Landmark]] = [
        (m, landmark) for m, landmark, ll in scan.associate(start.x, start.y, start.theta) if ll >= -0.5 * GATE_SIGMA**2
    ]
    if len({landmark.id for _, landmark in chosen}) < MIN_LANDMARKS:
        return None
    idx = np.array([m for m, _ in chosen])
    lx = np.array([lm.x for _, lm in chosen], float)
    ly = np.array([lm.y for _, lm in chosen], float)
    d, b, sd = scan.distance[idx], scan.bearing[idx], scan.sigma_d[idx]
    sb = scan.sigma_b
    pose = np.array([start.x, start.y, start.theta], float)
    res, jac = _residuals(pose, lx, ly, d, b, sd, sb)
    cost0 = cost = float(res @ res)
    for _ in range(ITERATIONS):
        normal = jac.T @ jac
        if not _well_posed(normal):
            return None
        step = -np.linalg.solve(normal, jac.T @ res)
        trial = pose + step
        trial_res, trial_jac = _residuals(trial, lx, ly, d, b, sd, sb)
        trial_cost = float(trial_res @ trial_res)
        if trial_cost > cost:
            break
        pose, res, jac, cost = trial, trial_res, trial_jac, trial_cost
        if np.abs(step).max() < STEP_TOLERANCE:
            break
    moved = math.hypot(pose[0] - start.x, pose[1] - start.y)
    turned = abs(normalize_angle(pose[2] - start.theta))
    normal = jac.T @ jac
    if cost > cost0 or moved > TRUST_RADIUS_M or turned > TRUST_ANGLE_RAD or not _well_posed(normal):
        return None
    variance_factor = cost / max(len(res) - 3, 1)  # a-posteriori variance of unit weight
    covariance = tuple(tuple(float(v) for v in row) for row in variance_factor * np.linalg.inv(normal))
    landmarks = tuple(lm.id for _, lm in chosen)
    polished = Pose2D(float(pose[0]), float(pose[1]), normalize_angle(float(pose[2])))
    return Refinement(polished, landmarks, covariance)  # type: ignore[arg-type]
