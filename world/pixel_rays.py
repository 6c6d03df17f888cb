"""The rays through the points at which TinyRenderer samples its pixels.

TinyRenderer decides whether a triangle covers pixel column ``i``, row ``r`` at the integer
screen point ``(i, h - 1 - r)`` (rows counted from the bottom, the image is flipped
afterwards). In the pixel convention of :mod:`world.camera_model` (pixel ``(i, r)`` covers
``[i, i+1) x [r, r+1)``) that is the continuous image point ``(i, r + 1)``: the pixel's
lower-left corner, not its centre. Drawing the same points keeps analytic surfaces
pixel-identical to TinyRenderer's.

A ray's world direction, scaled to unit depth along the optical axis, is the sum of a
term of its column and a term of its row, so whole-image quantities that are linear in it
are built by broadcasting a row vector against a column vector.
"""

from __future__ import annotations

import functools

import numpy as np


@functools.lru_cache(maxsize=8)
def sample_points(width_px: int, height_px: int, focal_px: float) -> tuple[np.ndarray, np.ndarray]:
    """Camera-frame slopes x/z (w,) of the columns and y/z (h,) of the rows (x right, y down) through
    TinyRenderer's sample points; read-only."""
    columns = (np.arange(width_px) - width_px / 2) / focal_px
    rows = (np.arange(height_px) + 1 - height_px / 2) / focal_px
    columns.flags.writeable = rows.flags.writeable = False
    return columns, rows


def separable_rays(
    rotation: np.ndarray, width_px: int, height_px: int, focal_px: float
) -> tuple[np.ndarray, np.ndarray]:
    """Column terms (3, w) and row terms (3, h) of the pixel rays' world directions at unit depth.

    ``rotation`` is camera->world (columns: right, down, forward). The ray of pixel
    ``(i, r)`` is ``columns[:, i] + rows[:, r]``.
    """
    x, y = sample_points(width_px, height_px, focal_px)
    return rotation[:, 0:1] * x + rotation[:, 2:3], rotation[:, 1:2] * y
