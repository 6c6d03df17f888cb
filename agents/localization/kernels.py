"""The per-particle arithmetic of the particle filter in compiled code (numba).

Each function computes, element by element, what the numpy expression it replaces computed, in
the same order of operations and with the same C library functions (``hypot``, ``atan2``,
``exp``, ``log``, ``sin``, ``cos``, ``fmod``-based ``mod``), so the particles and estimates are
the same to the bit (tests compare them with the numpy formulations). Sums and products of
whole arrays stay in numpy, whose summation order they would otherwise change. ``python -m
agents.compile`` (run by ``make install``) puts their machine code in numba's cache.
"""

from __future__ import annotations

import numba
import numpy as np

TWO_PI = 2.0 * np.pi


@numba.njit(cache=True, nogil=True, inline="always")
def wrap_angle(angle: float) -> float:
    """``angle`` (rad) wrapped into (-pi, pi] as :func:`agents.localization.constraint.wrap` does it:
    pi - mod(pi - angle, 2 pi). Within one turn of the range, the modulo is what numpy's (the C
    library's ``fmod``, exact, then the divisor added to a negative remainder) gives, without the
    slow ``fmod``."""
    v = np.pi - angle
    if 0.0 < v < TWO_PI:
        return np.pi - v
    if -TWO_PI < v < 0.0:
        return np.pi - (v + TWO_PI)
    return np.pi - np.mod(v, TWO_PI)


@numba.njit(cache=True, nogil=True, inline="always")
def _pair_log_likelihood(x: float, y: float, theta: float, landmark_x: float, landmark_y: float, distance: float,
                         sigma_d: float, bearing: float, sigma_b: float) -> float:
    """The Gaussian log-likelihood (without constants) of a percept (``distance`` m, ``bearing`` rad) showing
    the landmark at (``landmark_x``, ``landmark_y``) m, seen from the pose (x, y m; theta rad)."""
    dx, dy = landmark_x - x, landmark_y - y
    e_d = (np.hypot(dx, dy) - distance) / sigma_d
    e_b = wrap_angle(np.arctan2(dy, dx) - theta - bearing) / sigma_b
    return -0.5 * (e_d * e_d + e_b * e_b)


@numba.njit(cache=True, nogil=True)
def pair_log_likelihoods(x: np.ndarray, y: np.ndarray, theta: np.ndarray, lx: np.ndarray, ly: np.ndarray,
                         owner: np.ndarray, distance: np.ndarray, sigma_d: np.ndarray, bearing: np.ndarray,
                         sigma_b: float) -> np.ndarray:
    """(N, P) :func:`_pair_log_likelihood` of each pair ``p`` (landmark at (``lx[p]``, ``ly[p]``) m, percept
    ``owner[p]``) at N poses (x, y m; theta rad)."""
    out = np.empty((x.shape[0], lx.shape[0]))
    for i in range(x.shape[0]):
        for p in range(lx.shape[0]):
            k = owner[p]
            out[i, p] = _pair_log_likelihood(x[i], y[i], theta[i], lx[p], ly[p], distance[k], sigma_d[k], bearing[k],
                                             sigma_b)
    return out


@numba.njit(cache=True, nogil=True)
def percept_log_likelihoods(x: np.ndarray, y: np.ndarray, theta: np.ndarray, lx: np.ndarray, ly: np.ndarray,
                            owner: np.ndarray, starts: np.ndarray, distance: np.ndarray, sigma_d: np.ndarray,
                            bearing: np.ndarray, sigma_b: float, outlier: float) -> np.ndarray:
    """(N, M) log-likelihood of each of M percepts at N poses (x, y m; theta rad): the best of its
    landmark pairs ``starts[m]`` up to the next start (pair ``p``: landmark at (``lx[p]``, ``ly[p]``) m,
    percept ``owner[p]``) of the Gaussian in distance and bearing, mixed with ``outlier`` (see
    :class:`agents.localization.measurement.ScanLikelihood`)."""
    n, pairs, percepts = x.shape[0], lx.shape[0], starts.shape[0]
    out = np.empty((n, percepts))
    keep = 1.0 - outlier
    for i in range(n):
        for m in range(percepts):
            stop = starts[m + 1] if m + 1 < percepts else pairs
            best = 0.0
            for p in range(starts[m], stop):
                k = owner[p]
                value = _pair_log_likelihood(x[i], y[i], theta[i], lx[p], ly[p], distance[k], sigma_d[k], bearing[k],
                                             sigma_b)
                # np.maximum's choice, NaN kept
                best = value if p == starts[m] or not (best >= value or best != best) else best
            out[i, m] = np.log(keep * np.exp(best) + outlier)
    return out


@numba.njit(cache=True, nogil=True)
def near_seeds(x: np.ndarray, y: np.ndarray, theta: np.ndarray, seeds: np.ndarray, radius_m: float,
               angle_rad: float) -> np.ndarray:
    """(S, N) whether each of N particles lies within ``radius_m`` and ``angle_rad`` of each seed particle
    (indices ``seeds``).

    The distance is ``np.hypot``'s, as the numpy formulation has it; where the squared distance is farther
    from the squared radius than both roundings together could move it (a relative 1e-9, against some
    1e-15), its comparison says the same and the hypotenuse is not needed."""
    out = np.empty((seeds.shape[0], x.shape[0]), np.bool_)
    squared = radius_m * radius_m
    surely_in, surely_out = (squared * (1.0 - 1e-9), squared * (1.0 + 1e-9)) if radius_m > 0.0 else (-1.0, np.inf)
    for s in range(seeds.shape[0]):
        sx, sy, st = x[seeds[s]], y[seeds[s]], theta[seeds[s]]
        for i in range(x.shape[0]):
            dx, dy = x[i] - sx, y[i] - sy
            d2 = dx * dx + dy * dy
            if d2 < surely_in:
                inside = True
            elif d2 > surely_out:
                inside = False
            else:
                inside = np.hypot(dx, dy) <= radius_m
            out[s, i] = inside and abs(wrap_angle(theta[i] - st)) <= angle_rad
    return out


@numba.njit(cache=True, nogil=True)
def moved_particles(x: np.ndarray, y: np.ndarray, theta: np.ndarray, forward: np.ndarray, left: np.ndarray,
                    turn: np.ndarray, half_length_m: float, half_width_m: float
                    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """New particles (x, y m; theta rad) moved by each one's ``forward``, ``left`` (m, robot frame) and
    ``turn`` (rad), clipped to the carpet (|x| <= ``half_length_m``, |y| <= ``half_width_m``)."""
    n = x.shape[0]
    new_x, new_y, new_theta = np.empty(n), np.empty(n), np.empty(n)
    for i in range(n):
        c, s = np.cos(theta[i]), np.sin(theta[i])
        new_x[i] = min(max(x[i] + c * forward[i] - s * left[i], -half_length_m), half_length_m)
        new_y[i] = min(max(y[i] + s * forward[i] + c * left[i], -half_width_m), half_width_m)
        new_theta[i] = wrap_angle(theta[i] + turn[i])
    return new_x, new_y, new_theta


@numba.njit(cache=True, nogil=True)
def pose_residuals(x: float, y: float, theta: float, lx: np.ndarray, ly: np.ndarray, distance: np.ndarray,
                   bearing: np.ndarray, sigma_d: np.ndarray, sigma_b: float) -> tuple[np.ndarray, np.ndarray]:
    """The weighted residuals (2K,) of K percepts (``distance`` m, ``bearing`` rad, sigmas) of the landmarks
    at (``lx``, ``ly``) m at the pose (x, y m; theta rad), distances first, and their Jacobian (2K, 3) in
    (x, y, theta) (see :mod:`agents.localization.refine`)."""
    k = lx.shape[0]
    residuals = np.empty(2 * k)
    jacobian = np.empty((2 * k, 3))
    for i in range(k):
        dx, dy = lx[i] - x, ly[i] - y
        squared = dx * dx + dy * dy
        r2 = squared if squared >= 1e-12 or squared != squared else 1e-12  # np.maximum, NaN kept
        r = np.sqrt(r2)
        residuals[i] = (r - distance[i]) / sigma_d[i]
        residuals[k + i] = wrap_angle(np.arctan2(dy, dx) - theta - bearing[i]) / sigma_b
        jacobian[i, 0], jacobian[i, 1], jacobian[i, 2] = (-dx / r) / sigma_d[i], (-dy / r) / sigma_d[i], 0.0 / sigma_d[i]
        jacobian[k + i, 0], jacobian[k + i, 1] = (dy / r2) / sigma_b, (-dx / r2) / sigma_b
        jacobian[k + i, 2] = -1.0 / sigma_b
    return residuals, jacobian
