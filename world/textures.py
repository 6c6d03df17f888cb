"""The carpet texture: green with the white field lines painted from :mod:`world.field`.

Texel ``(row, col)`` covers field point ``x = -carpet_half_length + (col + 0.5) * res``,
``y = carpet_half_width - (row + 0.5) * res``: row 0 is the +y edge of the carpet.
"""

from __future__ import annotations

import hashlib
import logging
import tempfile
from pathlib import Path

import cv2
import numpy as np

from world.field import FieldGeometry

log = logging.getLogger(__name__)

CARPET_RGB = (38, 128, 45)
LINE_RGB = (245, 245, 245)
TEXEL_M = 0.01


def carpet_texture(field: FieldGeometry, texel_m: float = TEXEL_M) -> np.ndarray:
    """RGB uint8 image of the carpet with its lines, one texel per ``texel_m`` metres."""
    cols = int(round(2 * field.carpet_half_length / texel_m))
    rows = int(round(2 * field.carpet_half_width / texel_m))
    image = np.empty((rows, cols, 3), np.uint8)
    image[:] = CARPET_RGB
    half_line = field.line_width / 2.0

    def to_texel(x: float, y: float) -> tuple[float, float]:
        return (x + field.carpet_half_length) / texel_m, (field.carpet_half_width - y) / texel_m

    for seg in field.line_segments:
        x_lo, x_hi = sorted((seg.x0, seg.x1))
        y_lo, y_hi = sorted((seg.y0, seg.y1))
        c0, r1 = to_texel(x_lo - half_line, y_lo - half_line)
        c1, r0 = to_texel(x_hi + half_line, y_hi + half_line)
        image[int(round(r0)) : int(round(r1)), int(round(c0)) : int(round(c1))] = LINE_RGB
    circle = field.center_circle
    cc, cr = to_texel(circle.cx, circle.cy)
    yy, xx = np.mgrid[0:rows, 0:cols]
    dist = np.hypot((xx + 0.5 - cc) * texel_m, (yy + 0.5 - cr) * texel_m)
    image[np.abs(dist - circle.radius) <= half_line] = LINE_RGB
    return image


def carpet_texture_file(field: FieldGeometry, texel_m: float = TEXEL_M) -> Path:
    """Write the carpet texture once per field and resolution; return the PNG path."""
    key = hashlib.sha1(repr((field, texel_m, CARPET_RGB, LINE_RGB)).encode()).hexdigest()[:16]
    path = Path(tempfile.gettempdir()) / f"robotstadium-carpet-{key}.png"
    if not path.exists():
        image = carpet_texture(field, texel_m)
        tmp = path.with_suffix(f".{id(image)}.tmp.png")
        cv2.imwrite(str(tmp), cv2.cvtColor(image, cv2.COLOR_RGB2BGR))
        tmp.replace(path)
        log.debug("wrote carpet texture %s", path)
    return path
