"""The compiled pass of a camera profile (:mod:`world.camera_profiles`): one pass over the rows of a
160x120 RGB frame that blurs, shears, shades, subsamples chroma and adds sensor noise.

Numba keeps the compiled function on disk (``cache=True``), like the renderer (:mod:`world.raster`).
The noise is a counter-based hash of the pixel pair's index and a 64-bit key drawn per frame from the
world's camera stream, so one key gives one image; each 12-bit piece of a hash picks a quantile of the
standard normal distribution from :data:`NORMAL_QUANTILES`.
"""

from __future__ import annotations

from statistics import NormalDist

import numpy as np
from numba import njit

QUANTILE_BITS = 12
NORMAL_QUANTILES = np.array([NormalDist().inv_cdf((i + 0.5) / 2**QUANTILE_BITS) for i in range(2**QUANTILE_BITS)],
                            np.float32)
"""The standard normal distribution's quantiles at the centres of 4096 equal steps of probability: a
uniform 12-bit draw indexes a normal variate (variance 0.9994, tails cut at 3.5 sigma)."""


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
def _add_taps(row, top, bottom, w00, w01, w10, w11):
    """Add to every value of ``row`` its bilinear tap: ``top`` and ``bottom`` start at the tap's columns."""
    for j in range(row.shape[0]):
        row[j] += w00 * top[j] + w01 * top[j + 3] + w10 * bottom[j] + w11 * bottom[j + 3]


@njit(cache=True, error_model="numpy")
def apply_effects(src, out, blur_u, blur_v, taps, shear_u, shear_v, shade, gains, shot, read_sigma,
                  chroma_sigma, yuv422, key, quantiles):
    """Write into ``out`` (uint8, like ``src``, (H, W, 3), W even) the frame ``src`` as the sensor records it.

    Per pixel (u, v): the mean of ``taps`` bilinear samples of ``src`` (edges repeated) at the midpoints of
    equal parts of
    the blur vector (``blur_u``, ``blur_v``) px centred on (u, v), the rolling shutter displacing the
    content of row v by (``shear_u``, ``shear_v``) px per row times the row's distance from the centre row
    (the rows are read one after another while the image moves); times
    ``shade[v, u]`` (vignetting) and ``gains`` (per channel: exposure and colour cast); then, with
    ``yuv422``, converted to YUV (BT.601, full range), U and V averaged over each horizontal pair of
    pixels, noise added (Y: variance ``shot`` * Y + ``read_sigma`` ** 2 levels^2; U and V: ``chroma_sigma``
    levels, one draw per pair) and converted back; without it, noise of variance ``shot`` * value +
    ``read_sigma`` ** 2 on each RGB channel. Rounded and clipped to 0-255.
    """
    h, w = src.shape[0], src.shape[1]
    n = 3 * w
    centre = (h - 1) * 0.5
    still = taps <= 1 and shear_u == 0.0 and shear_v == 0.0
    flat = src.reshape(h, n)
    image = np.empty((h, n), np.float32)  # float samples vectorise better than uint8 ones
    if not still:
        for v in range(h):
            for j in range(n):
                image[v, j] = flat[v, j]
    row = np.empty(n, np.float32)
    acc = row.reshape(w, 3)
    read2 = np.float32(read_sigma * read_sigma)
    shot32 = np.float32(shot)
    chroma32 = np.float32(chroma_sigma)
    mask = np.uint64(2**12 - 1)
    for v in range(h):
        # ---- blur and rolling shutter: every tap of a row has the same offset, so the same weights
        if still:
            for j in range(n):
                row[j] = flat[v, j]
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
        for u in range(w):
            s = shade[v, u]
            for c in range(3):
                acc[u, c] *= s * gains[c]
        # ---- chroma subsampling and noise, a pair of pixels at a time
        for u0 in range(0, w, 2):
            bits = _hash(key + np.uint64(v * w + u0) * np.uint64(0x9E3779B97F4A7C15))
            if yuv422:
                r0, g0, b0 = acc[u0, 0], acc[u0, 1], acc[u0, 2]
                r1, g1, b1 = acc[u0 + 1, 0], acc[u0 + 1, 1], acc[u0 + 1, 2]
                cu = np.float32(0.5) * (np.float32(-0.168736) * (r0 + r1) - np.float32(0.331264) * (g0 + g1)
                                        + np.float32(0.5) * (b0 + b1))
                cv = np.float32(0.5) * (np.float32(0.5) * (r0 + r1) - np.float32(0.418688) * (g0 + g1)
                                        - np.float32(0.081312) * (b0 + b1))
                cu += chroma32 * quantiles[(bits >> np.uint64(24)) & mask]
                cv += chroma32 * quantiles[(bits >> np.uint64(36)) & mask]
                for p in range(2):
                    u = u0 + p
                    y = np.float32(0.299) * acc[u, 0] + np.float32(0.587) * acc[u, 1] + np.float32(0.114) * acc[u, 2]
                    y += np.sqrt(max(shot32 * y, np.float32(0.0)) + read2) * quantiles[(bits >> np.uint64(12 * p)) & mask]
                    acc[u, 0] = y + np.float32(1.402) * cv
                    acc[u, 1] = y - np.float32(0.344136) * cu - np.float32(0.714136) * cv
                    acc[u, 2] = y + np.float32(1.772) * cu
            else:
                more = _hash(bits)
                for p in range(2):
                    for c in range(3):
                        i = 3 * p + c
                        piece = (bits >> np.uint64(12 * i)) & mask if i < 5 else (more & mask)
                        x = acc[u0 + p, c]
                        acc[u0 + p, c] = x + np.sqrt(max(shot32 * x, np.float32(0.0)) + read2) * quantiles[piece]
        for u in range(w):
            for c in range(3):
                out[v, u, c] = np.uint8(min(max(acc[u, c] + np.float32(0.5), np.float32(0.0)), np.float32(255.0)))
