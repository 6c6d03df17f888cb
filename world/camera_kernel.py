"""The compiled pass of a camera profile (:mod:`world.camera_profiles`): one pass over the rows of a
160x120 RGB frame that blurs, shears, shades, subsamples chroma and adds sensor noise.

Numba keeps the compiled function on disk (``cache=True``), like the renderer (:mod:`world.raster`).
The noise of a row is the sum of two runs of :data:`NORMAL_BANK`, a fixed table of standard normal
variates, at offsets hashed from the row and a 64-bit key drawn per frame from the world's camera
stream, over the square root of 2: one key gives one image, the noise is Gaussian, and a row's noise
repeats only if both offsets do (one chance in about a billion). Reading runs of a table vectorises;
a draw per value would cost most of the frame's budget.

The frames of several cameras go through in one call: one after another (:func:`apply_effects_serial`)
or shared among numba's threads (:func:`apply_effects_parallel`), with the same images.
"""

from __future__ import annotations

from statistics import NormalDist

import numpy as np
from numba import njit, prange

BANK_SIZE = 2**15
"""Normal variates in the table (128 kB, cache resident)."""


def _normal_bank(size: int) -> np.ndarray:
    """The standard normal quantiles at the centres of ``size`` equal steps of probability (variance 0.9999,
    tails cut at 4.2 sigma), in an order fixed by a hash of their index: a table of normal variates that
    is the same on every machine."""
    quantiles = np.array([NormalDist().inv_cdf((i + 0.5) / size) for i in range(size)])
    x = np.arange(size, dtype=np.uint64) * np.uint64(0x9E3779B97F4A7C15)
    x = (x ^ (x >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    x = (x ^ (x >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    x ^= x >> np.uint64(31)
    return quantiles[np.argsort(x, kind="stable")].astype(np.float32)


NORMAL_BANK = _normal_bank(BANK_SIZE)


@njit(cache=True, inline="always")
def _hash(x: np.uint64) -> np.uint64:
    """SplitMix64's finaliser: 64 well-mixed bits from a counter."""
    x = (x ^ (x >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    x = (x ^ (x >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    return x ^ (x >> np.uint64(31))


@njit(cache=True, inline="always")
def _add_clamped(row, top, bottom, u, ix, w, w00, w01, w10, w11):
    """Add to pixel ``u`` of ``row`` its bilinear tap ``ix`` columns away, the image's edge repeated."""
    xa = 3 * min(max(u + ix, 0), w - 1)
    xb = 3 * min(max(u + ix + 1, 0), w - 1)
    for c in range(3):
        row[3 * u + c] += w00 * top[xa + c] + w01 * top[xb + c] + w10 * bottom[xa + c] + w11 * bottom[xb + c]


@njit(cache=True, inline="always")
def _level(x: np.float32) -> np.uint8:
    """``x`` rounded to the nearest level and clipped to 0-255."""
    return np.uint8(min(max(x + np.float32(0.5), np.float32(0.0)), np.float32(255.0)))


@njit(cache=True, inline="always")
def _mix_runs(noise, first, second, scale):
    """``noise`` = (``first`` + ``second``) * ``scale``, value by value from the runs' starts."""
    for j in range(noise.shape[0]):
        noise[j] = (first[j] + second[j]) * scale


@njit(cache=True, inline="always")
def _add_taps(row, top, bottom, w00, w01, w10, w11):
    """Add to every value of ``row`` its bilinear tap: ``top`` and ``bottom`` start at the tap's columns."""
    for j in range(row.shape[0]):
        row[j] += w00 * top[j] + w01 * top[j + 3] + w10 * bottom[j] + w11 * bottom[j + 3]


@njit(cache=True, error_model="numpy")
def apply_effects(src, out, blur_u, blur_v, taps, shear_u, shear_v, shade, vignetting, gains, sigma_by_level,
                  chroma_sigma, yuv422, key, bank):
    """Write into ``out`` (uint8, like ``src``, (H, W, 3), W even) the frame ``src`` as the sensor records it.

    Per pixel (u, v): the mean of ``taps`` bilinear samples of ``src`` (edges repeated) at the midpoints of
    equal parts of the blur vector (``blur_u``, ``blur_v``) px centred on (u, v), the rolling shutter
    displacing the content of row v by (``shear_u``, ``shear_v``) px per row times the row's distance from
    the centre row (the rows are read one after another while the image moves); times ``shade[v, u]``
    (vignetting; with ``vignetting`` False, ``shade`` is all ones) and ``gains`` (per channel: exposure
    and colour cast); then, with ``yuv422``, converted to YUV (BT.601, full range), U and V averaged over
    each horizontal pair of pixels, noise added (Y: standard deviation ``sigma_by_level`` at Y rounded,
    levels 0-255; U and V: ``chroma_sigma`` levels, one draw per pair) and converted back; without it,
    noise of ``sigma_by_level`` at each RGB channel's rounded value. Rounded and clipped to 0-255. The
    normal variates come from ``bank`` (see the module).

    A profile without vignetting, gains of 1 or noise independent of the level skips that work (the
    same values: a product by 1 is exact).
    """
    h, w = src.shape[0], src.shape[1]
    shaded = vignetting or not (gains[0] == 1.0 and gains[1] == 1.0 and gains[2] == 1.0)
    level_free = sigma_by_level.min() == sigma_by_level.max()
    sigma0 = sigma_by_level[0]
    n = 3 * w
    centre = (h - 1) * 0.5
    still = taps <= 1 and shear_u == 0.0 and shear_v == 0.0
    flat = src.reshape(h, n)
    result = out.reshape(h, n)
    # float64 samples: the taps' weights are float64, and a sample needs no conversion per tap (the values,
    # whole levels, are the same in any float type)
    image = np.empty((h, n), np.float64)
    if not still:
        for v in range(h):
            source, target = flat[v], image[v]
            for j in range(n):
                target[j] = source[j]
    row = np.empty(n, np.float32)
    noise = np.empty(n, np.float32)
    chroma32 = np.float32(chroma_sigma)
    span = np.uint64(bank.shape[0] - n)
    low = np.uint64(0xFFFFFFFF)
    root_half = np.float32(np.sqrt(0.5))
    for v in range(h):
        # ---- blur and rolling shutter: every tap of a row has the same offset, so the same weights
        if still:
            source = flat[v]
            for j in range(n):
                row[j] = source[j]
        else:
            row[:] = 0.0
            weight = np.float32(1.0 / taps)
            for k in range(taps):
                t = (k + 0.5) / taps - 0.5  # the midpoints of equal parts of the exposure
                dx = t * blur_u - shear_u * (v - centre)  # row v shows what lay shear * (v - centre) back
                y = min(max(v + t * blur_v - shear_v * (v - centre), 0.0), h - 1.0)
                ix = int(np.floor(dx))
                fx = np.float32(dx - ix)
                y0 = int(y)
                fy = np.float32(y - y0)
                y1 = min(y0 + 1, h - 1)
                w00 = weight * (1 - fx) * (1 - fy)
                w01 = weight * fx * (1 - fy)
                w10 = weight * (1 - fx) * fy
                w11 = weight * fx * fy
                top, bottom = image[y0], image[y1]
                lo, hi = min(max(-ix, 0), w), max(min(w - 1 - ix, w), 0)  # columns whose samples need no clamping
                for u in range(0, lo):
                    _add_clamped(row, top, bottom, u, ix, w, w00, w01, w10, w11)
                for u in range(max(hi, lo), w):
                    _add_clamped(row, top, bottom, u, ix, w, w00, w01, w10, w11)
                if hi > lo:  # views from the first column, so the loop indexes from 0 and vectorises
                    _add_taps(row[3 * lo:3 * hi], top[3 * (lo + ix):3 * (hi + ix) + 3],
                              bottom[3 * (lo + ix):3 * (hi + ix) + 3], w00, w01, w10, w11)
        # ---- shading, exposure, cast
        if shaded:
            shade_row = shade[v]
            for u in range(w):
                for c in range(3):
                    row[3 * u + c] *= shade_row[u] * gains[c]
        # ---- the row's normal variates: two runs of the bank
        bits = _hash(key + np.uint64(v + 1) * np.uint64(0x9E3779B97F4A7C15))
        _mix_runs(noise, bank[(bits & low) % span:], bank[(bits >> np.uint64(32)) % span:], root_half)
        # ---- chroma subsampling and noise, a pair of pixels at a time
        if yuv422:
            for j in range(0, n, 6):
                r0, g0, b0, r1, g1, b1 = row[j], row[j + 1], row[j + 2], row[j + 3], row[j + 4], row[j + 5]
                cu = np.float32(0.5) * (np.float32(-0.168736) * (r0 + r1) - np.float32(0.331264) * (g0 + g1)
                                        + np.float32(0.5) * (b0 + b1)) + chroma32 * noise[j + 1]
                cv = np.float32(0.5) * (np.float32(0.5) * (r0 + r1) - np.float32(0.418688) * (g0 + g1)
                                        - np.float32(0.081312) * (b0 + b1)) + chroma32 * noise[j + 2]
                for q in range(j, j + 6, 3):
                    y = np.float32(0.299) * row[q] + np.float32(0.587) * row[q + 1] + np.float32(0.114) * row[q + 2]
                    y += sigma_by_level[_level(y)] * noise[q]
                    result[v, q] = _level(y + np.float32(1.402) * cv)
                    result[v, q + 1] = _level(y - np.float32(0.344136) * cu - np.float32(0.714136) * cv)
                    result[v, q + 2] = _level(y + np.float32(1.772) * cu)
        else:
            target = result[v]
            if level_free:
                for j in range(n):
                    target[j] = _level(row[j] + sigma0 * noise[j])
            else:
                for j in range(n):
                    x = row[j]
                    target[j] = _level(x + sigma_by_level[_level(x)] * noise[j])


@njit(cache=True, error_model="numpy")
def _apply_one(i, srcs, outs, blurs, taps, shears, shade, vignetting, gains, sigma_by_level, chroma_sigma, yuv422,
               keys, bank):
    apply_effects(srcs[i], outs[i], blurs[i, 0], blurs[i, 1], taps[i], shears[i, 0], shears[i, 1], shade, vignetting,
                  gains[i], sigma_by_level, chroma_sigma, yuv422, keys[i], bank)


@njit(cache=True, error_model="numpy")
def apply_effects_serial(srcs, outs, blurs, taps, shears, shade, vignetting, gains, sigma_by_level, chroma_sigma,
                         yuv422, keys, bank):
    """:func:`apply_effects` of frame ``i`` of ``srcs`` (n, H, W, 3) into ``outs[i]`` for each ``i``, with
    its own blur and shear (``blurs``, ``shears`` (n, 2) px and px per row), ``taps`` (n,), ``gains``
    (n, 3) and ``keys`` (n,) uint64; the profile's ``shade``, ``sigma_by_level`` and ``chroma_sigma`` shared."""
    for i in range(srcs.shape[0]):
        _apply_one(i, srcs, outs, blurs, taps, shears, shade, vignetting, gains, sigma_by_level, chroma_sigma, yuv422,
                   keys, bank)


@njit(cache=True, error_model="numpy", parallel=True)
def apply_effects_parallel(srcs, outs, blurs, taps, shears, shade, vignetting, gains, sigma_by_level, chroma_sigma,
                           yuv422, keys, bank):
    """:func:`apply_effects_serial`, the frames shared among numba's threads (the same images)."""
    for i in prange(srcs.shape[0]):
        _apply_one(i, srcs, outs, blurs, taps, shears, shade, vignetting, gains, sigma_by_level, chroma_sigma, yuv422,
                   keys, bank)
