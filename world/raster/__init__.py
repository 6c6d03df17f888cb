"""The compiled renderer: TinyRenderer's pipeline and the analytic hall, in numba.

Numba keeps each compiled function on disk (``cache=True``) and checks only the file that
defines it, not the functions it calls from the other files here: a change to one file would
leave its callers' old machine code in use. So the compiled files of this package are
dropped whenever any of its sources differs from the ones they were compiled from.
"""

from __future__ import annotations

import hashlib
import logging
from pathlib import Path

log = logging.getLogger(__name__)


def _drop_stale_machine_code() -> None:
    here = Path(__file__).parent
    digest = hashlib.sha256(b"".join(path.read_bytes() for path in sorted(here.glob("*.py")))).hexdigest()
    cache = here / "__pycache__"
    stamp = cache / "raster-sources.sha256"
    try:
        if stamp.exists() and stamp.read_text() == digest:
            return
        for path in [*cache.glob("*.nbi"), *cache.glob("*.nbc")]:
            path.unlink(missing_ok=True)
        cache.mkdir(exist_ok=True)
        stamp.write_text(digest)
    except OSError as error:  # a read-only install: numba keeps its cache elsewhere, rebuilt on reinstall
        log.debug("could not check the compiled renderer's cache in %s: %s", cache, error)


_drop_stale_machine_code()
