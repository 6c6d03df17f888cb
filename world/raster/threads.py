"""Whether the cameras of a step are drawn on numba's threads, and on which threading layer.

Only numba's TBB layer is used: it starts a parallel loop cheaply and a process that used it
may still fork (GNU OpenMP's layer kills such a child, which breaks vector envs that fork
their workers; the ``workqueue`` layer's start costs a large share of a frame).
TBB comes from the ``tbb`` wheel, whose library lies in the environment's ``lib`` folder,
outside the loader's path: it is loaded here by its path before numba looks for it. Without
it, or with one thread (``NUMBA_NUM_THREADS=1``, as the batch engine's workers are started
when they share the cores), the cameras are drawn one after another. The images are the same
either way.
"""

from __future__ import annotations

import ctypes
import functools
import logging
import os
import sys
from pathlib import Path

import numba

log = logging.getLogger(__name__)

TBB_LIBRARY = "libtbb.so.12"


def _load_tbb() -> bool:
    """Load the ``tbb`` wheel's library so numba's TBB layer finds it; whether it loaded."""
    for prefix in dict.fromkeys((sys.prefix, sys.base_prefix)):
        path = Path(prefix) / "lib" / TBB_LIBRARY
        if path.exists():
            try:
                ctypes.CDLL(str(path), mode=ctypes.RTLD_GLOBAL)
                return True
            except OSError as error:
                log.debug("could not load %s: %s", path, error)
    return False


@functools.cache
def parallel_cameras() -> bool:
    """True when the cameras of a step may be drawn in parallel: TBB's layer can be had and numba has more
    than one thread. Decided once per process."""
    if numba.config.NUMBA_NUM_THREADS < 2 or os.environ.get("NUMBA_THREADING_LAYER", "tbb") != "tbb":
        return False
    if not _load_tbb():
        log.debug("numba's TBB threading layer is not available: cameras are drawn one after another")
        return False
    try:
        from numba.np.ufunc import tbbpool  # noqa: F401  (fails when numba cannot use this TBB)
    except ImportError as error:
        log.debug("numba's TBB threading layer failed to load (%s): cameras are drawn one after another", error)
        return False
    numba.config.THREADING_LAYER = "tbb"
    return True
