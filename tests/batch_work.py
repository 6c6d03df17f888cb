"""Work functions for the batch engine's tests, importable by spawned worker processes."""

from __future__ import annotations

import os
import time


def square(task: int, tick=None) -> int:
    if tick is not None:
        tick()
    return task * task


def dies_on_three(task: int, tick=None) -> int:
    """Kills its process on task 3 (after its neighbours started), squares the others."""
    if task == 3:
        time.sleep(0.3)
        os._exit(3)
    time.sleep(0.6)
    return task * task


def raises_on_two(task: int, tick=None) -> int:
    if task == 2:
        raise RuntimeError("task two fails")
    return task * task
