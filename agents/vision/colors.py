"""The colour classes of the segmented image (thesis section 4.1, Table 4.1).

The thesis fits each pixel to green, white, blue, yellow, orange or cyan, in that priority
order, and a pixel that fits none becomes white. Our robots wear cyan (blue team) or
magenta (red team) waistbands, the SPL 2011 team markers, so magenta is a class too; it
comes last in the order. Black, red and the other colours of Table 4.1 are only used to
draw debug overlays (:mod:`agents.vision.overlay`).
"""

from __future__ import annotations

import enum


class ColorClass(enum.IntEnum):
    """Label of a pixel in the segmented image (``uint8`` values)."""

    GREEN = 0
    WHITE = 1
    BLUE = 2
    YELLOW = 3
    ORANGE = 4
    CYAN = 5
    MAGENTA = 6


PRIORITY = (
    ColorClass.GREEN,
    ColorClass.WHITE,
    ColorClass.BLUE,
    ColorClass.YELLOW,
    ColorClass.ORANGE,
    ColorClass.CYAN,
    ColorClass.MAGENTA,
)
"""Order in which a pixel is tried against the classes' thresholds (thesis 4.1)."""

UNFITTED = ColorClass.WHITE
"""What a pixel that fits no class becomes (thesis 4.1: "the pixel becomes white")."""

DISPLAY_RGB = {
    ColorClass.GREEN: (0, 255, 0),
    ColorClass.WHITE: (255, 255, 255),
    ColorClass.BLUE: (0, 0, 255),
    ColorClass.YELLOW: (255, 255, 0),
    ColorClass.ORANGE: (255, 140, 0),
    ColorClass.CYAN: (0, 255, 255),
    ColorClass.MAGENTA: (255, 0, 255),
}
"""Table 4.1 colours used to draw a segmented image."""
