"""Compile the vision's machine code (:mod:`agents.vision.kernels`) into numba's cache once:
``python -m agents.vision.compile``.

``make install`` runs it, so that no controller process, test or benchmark pays for the
compilation (once per install or change of the kernels; later processes load the cached code).
"""

from __future__ import annotations

import time

import numpy as np


def compile_vision() -> float:
    """Run every kernel of the vision once, on a frame of field and line; return the seconds it took."""
    from agents.vision.border import find_border
    from agents.vision.colors import ColorClass
    from agents.vision.lines.scan_lines import scan_black_lines
    from agents.vision.segmentation import ColorTable, load_thresholds

    started = time.perf_counter()
    table = ColorTable(load_thresholds())
    image = np.zeros((120, 160, 3), np.uint8)
    labels = table.segment(image)
    labels[:] = int(ColorClass.GREEN)
    labels[60:63, :] = int(ColorClass.WHITE)
    scan_black_lines(labels, find_border(labels))
    return time.perf_counter() - started


def main() -> None:
    seconds = compile_vision()
    print(f"compiled vision ready ({seconds:.1f} s)")


if __name__ == "__main__":
    main()
