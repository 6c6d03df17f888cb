"""The particle filter's compiled arithmetic (agents.localization.kernels) gives, to the bit, what the
numpy expressions it replaced gave: those expressions are kept here as the references."""

from __future__ import annotations

import hashlib
import math

import numba
import numpy as np
import pytest

from agents.localization.constraint import wrap
from agents.localization.kernels import (
    moved_particles,
    near_seeds,
    percept_log_likelihoods,
    pose_residuals,
    wrap_angle,
)
from agents.localization.measurement import MeasurementConfig, ScanLikelihood
from agents.localization.particle import ParticleLocalizer
from agents.vision.percepts import LandmarkPercept
from match.protocol import Displacement
from world.field import FIELD, GoalColor, LandmarkKind, Pose2D


def _same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    return a.shape == b.shape and a.dtype == b.dtype and a.tobytes() == b.tobytes()


@numba.njit
def _wrapped(angles: np.ndarray) -> np.ndarray:
    out = np.empty_like(angles)
    for i in range(angles.size):
        out[i] = wrap_angle(angles[i])
    return out


def test_wrap_angle_is_numpys_wrap_to_the_bit() -> None:
    rng = np.random.default_rng(0)
    edges = [0.0, -0.0, math.pi, -math.pi, 3 * math.pi, -3 * math.pi, 2 * math.pi, np.nextafter(math.pi, 0.0),
             np.nextafter(-math.pi, 0.0), np.nextafter(3 * math.pi, 10.0), 1e-300, np.inf, -np.inf, np.nan]
    angles = np.concatenate([rng.uniform(-20.0, 20.0, 200_000), edges])
    with np.errstate(invalid="ignore"):
        assert _same_bits(_wrapped(angles), wrap(angles))


def _reference_pair_log_likelihood(scan: ScanLikelihood, x: np.ndarray, y: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """The numpy formulation the kernel replaced."""
    dx = scan.lx[None, :] - x[:, None]
    dy = scan.ly[None, :] - y[:, None]
    e_d = (np.hypot(dx, dy) - scan.distance[scan.owner]) / scan.sigma_d[scan.owner]
    e_b = wrap(np.arctan2(dy, dx) - theta[:, None] - scan.bearing[scan.owner]) / scan.sigma_b
    return -0.5 * (e_d * e_d + e_b * e_b)


def _reference_percept_log_likelihood(scan: ScanLikelihood, x: np.ndarray, y: np.ndarray,
                                      theta: np.ndarray) -> np.ndarray:
    """The numpy formulation the kernel replaced."""
    pairs = _reference_pair_log_likelihood(scan, x, y, theta)
    best = np.maximum.reduceat(pairs, scan.starts, axis=1)
    eps = scan.config.outlier_probability
    return np.log((1.0 - eps) * np.exp(best) + eps)


def _percept(kind: LandmarkKind, bearing_rad: float, distance_m: float, **kwargs) -> LandmarkPercept:
    return LandmarkPercept(kind, (80.0, 90.0), bearing_rad, distance_m, "exact", **kwargs)


SCANS = {
    "one corner (four landmarks)": [_percept(LandmarkKind.L_CORNER, 0.3, 1.5)],
    "corners, junction, post, circle": [
        _percept(LandmarkKind.L_CORNER, 0.3, 1.5), _percept(LandmarkKind.L_CORNER, -0.8, 2.5),
        _percept(LandmarkKind.T_JUNCTION, 1.2, 0.9), _percept(LandmarkKind.GOAL_POST, -0.1, 3.0, goal=GoalColor.BLUE),
        _percept(LandmarkKind.CENTER_CIRCLE, 2.9, 0.4),
    ],
    "a percept far off the field": [_percept(LandmarkKind.L_CORNER, -3.1, 40.0),
                                    _percept(LandmarkKind.GOAL_POST, 0.0, 1e-9)],
}


@pytest.mark.parametrize("name", sorted(SCANS))
def test_percept_log_likelihoods_are_the_numpy_ones(name: str) -> None:
    rng = np.random.default_rng(len(name))
    scan = ScanLikelihood(SCANS[name], MeasurementConfig(), FIELD)
    n = 3000
    x = rng.uniform(-6.0, 6.0, n)
    y = rng.uniform(-4.0, 4.0, n)
    theta = rng.uniform(-4.0 * math.pi, 4.0 * math.pi, n)  # also angles far outside (-pi, pi]
    x[:3], y[:3] = scan.lx[:3], scan.ly[:3]  # standing on a landmark: distance 0, bearing atan2(0, 0)
    assert _same_bits(scan.pair_log_likelihood(x, y, theta), _reference_pair_log_likelihood(scan, x, y, theta))
    got = scan.percept_log_likelihood(x, y, theta)
    assert _same_bits(got, _reference_percept_log_likelihood(scan, x, y, theta))
    expected = _reference_percept_log_likelihood(scan, x, y, theta).sum(axis=1)
    assert _same_bits(scan.log_likelihood(x, y, theta), expected)


def test_a_nan_pose_scores_nan_as_numpy_did() -> None:
    scan = ScanLikelihood(SCANS["corners, junction, post, circle"], MeasurementConfig(), FIELD)
    x, y, theta = np.array([0.5, np.nan]), np.array([0.2, 0.1]), np.array([np.nan, 0.3])
    got = percept_log_likelihoods(x, y, theta, scan.lx, scan.ly, scan.owner, scan.starts, scan.distance,
                                  scan.sigma_d, scan.bearing, float(scan.sigma_b), scan.config.outlier_probability)
    assert _same_bits(got, _reference_percept_log_likelihood(scan, x, y, theta))
    assert np.isnan(got).all()


def test_near_seeds_is_the_numpy_mask() -> None:
    rng = np.random.default_rng(7)
    n = 2000
    x, y = rng.normal(0.0, 0.6, n), rng.normal(0.0, 0.6, n)
    theta = rng.uniform(-math.pi, math.pi, n)
    x[1], y[1], theta[1] = x[0] + 0.5, y[0], theta[0] + 0.5  # exactly on both limits of seed 0
    seeds = np.array([0, 5, 17, 1999])
    reference = (np.hypot(x[None, :] - x[seeds, None], y[None, :] - y[seeds, None]) <= 0.5) & (
        np.abs(wrap(theta[None, :] - theta[seeds, None])) <= 0.5)
    assert np.array_equal(near_seeds(x, y, theta, seeds, 0.5, 0.5), reference)


@pytest.mark.parametrize("radius", [0.5, 1e-3, 0.0, -0.1])
def test_near_seeds_on_the_circle_is_the_numpy_mask(radius: float) -> None:
    """Particles on the circle in every direction (their distance rounded either way), NaN and infinite
    coordinates, a zero and a negative radius: the hypotenuse decides where the squares cannot."""
    rng = np.random.default_rng(8)
    n = 1000
    x, y, theta = rng.normal(0.0, 0.3, n), rng.normal(0.0, 0.3, n), rng.uniform(-0.2, 0.2, n)
    angles = np.linspace(0.0, 2.0 * math.pi, 600)
    x[:600], y[:600] = x[999] + radius * np.cos(angles), y[999] + radius * np.sin(angles)
    x[600:700] = np.nextafter(x[600:700], np.inf)
    x[700], y[701], x[702] = np.nan, np.inf, -np.inf
    seeds = np.array([999, 3])
    reference = (np.hypot(x[None, :] - x[seeds, None], y[None, :] - y[seeds, None]) <= radius) & (
        np.abs(wrap(theta[None, :] - theta[seeds, None])) <= 0.5)
    assert np.array_equal(near_seeds(x, y, theta, seeds, radius, 0.5), reference)


def test_moved_particles_are_the_numpy_ones() -> None:
    rng = np.random.default_rng(3)
    n = 2000
    x, y = rng.uniform(-5.0, 5.0, n), rng.uniform(-3.5, 3.5, n)
    theta = rng.uniform(-math.pi, math.pi, n)
    forward, left, turn = rng.normal(0.3, 0.5, n), rng.normal(0.0, 0.5, n), rng.normal(0.0, 3.0, n)
    half_length, half_width = FIELD.carpet_half_length, FIELD.carpet_half_width
    c, s = np.cos(theta), np.sin(theta)
    reference = (np.clip(x + c * forward - s * left, -half_length, half_length),
                 np.clip(y + s * forward + c * left, -half_width, half_width), wrap(theta + turn))
    got = moved_particles(x, y, theta, forward, left, turn, half_length, half_width)
    assert all(_same_bits(a, b) for a, b in zip(got, reference))
    assert (np.abs(reference[0]) == half_length).any()  # some were clipped


def _reference_residuals(pose, lx, ly, d, b, sd, sb):
    """The numpy formulation :func:`pose_residuals` replaced."""
    dx, dy = lx - pose[0], ly - pose[1]
    r2 = np.maximum(dx * dx + dy * dy, 1e-12)
    r = np.sqrt(r2)
    res = np.concatenate([(r - d) / sd, wrap(np.arctan2(dy, dx) - pose[2] - b) / sb])
    jac_d = np.stack([-dx / r, -dy / r, np.zeros_like(r)], axis=1) / sd[:, None]
    jac_b = np.stack([dy / r2, -dx / r2, -np.ones_like(r)], axis=1) / sb
    return res, np.concatenate([jac_d, jac_b])


@pytest.mark.parametrize("seed", range(5))
def test_pose_residuals_are_the_numpy_ones(seed: int) -> None:
    rng = np.random.default_rng(seed)
    k = 1 + seed * 3
    lx, ly = rng.uniform(-4.5, 4.5, k), rng.uniform(-3.0, 3.0, k)
    d, b = rng.uniform(0.2, 6.0, k), rng.uniform(-math.pi, math.pi, k)
    sd, sb = 0.05 + 0.08 * d, math.radians(4.0)
    pose = np.array([rng.uniform(-4.5, 4.5), rng.uniform(-3.0, 3.0), rng.uniform(-7.0, 7.0)])
    lx[0], ly[0] = pose[0], pose[1]  # a landmark under the robot: the 1e-12 floor of r^2
    got = pose_residuals(*pose.tolist(), lx, ly, d, b, sd, sb)
    assert all(_same_bits(a, e) for a, e in zip(got, _reference_residuals(pose, lx, ly, d, b, sd, sb)))


PINNED_ESTIMATES = ((0.9237712211132788, 0.859635503576071, -0.13188407215438938),
                    (-0.5856688375631048, -1.3145994734276427, -2.06449471965601))
PINNED_PARTICLES_SHA256 = "18bac278b942478fdf8d424db2d27ac142ac6c4d26eedf56a24e9d89407058b8"


def test_a_filter_moves_and_localizes_as_before() -> None:
    """A whole update path through the kernels: a cloud at a known pose, moved, then two scans of three
    ambiguous landmarks; the estimates and particles the numpy formulations gave (commit 727f3d4)."""
    localizer = ParticleLocalizer(seed=11, initial_pose=Pose2D(-1.0, 0.5, 0.3))
    localizer.move(Displacement(0.2, 0.05, 0.1))
    scan = SCANS["corners, junction, post, circle"][:3]
    estimates = [localizer.localize(scan) for _ in range(2)]
    assert [(e.x_m, e.y_m, e.theta_rad) for e in estimates] == list(PINNED_ESTIMATES)
    assert hashlib.sha256(localizer.particles.tobytes()).hexdigest() == PINNED_PARTICLES_SHA256
