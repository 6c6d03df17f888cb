"""Whether the cameras of a step are drawn on numba's threads or on one."""

from __future__ import annotations


def parallel_cameras() -> bool:
    return False
