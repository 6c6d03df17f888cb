"""Bounds shared by the command line and the scenario files, so that a flag accepts what a file does.

A half of a match lasts :data:`HALF_SECONDS_MIN` .. :data:`HALF_SECONDS_MAX` seconds of
simulated time (1 s .. 1 day); a scenario takes at most :data:`MAX_SAMPLES` samples per method.
"""

from __future__ import annotations

HALF_SECONDS_MIN = 1.0
HALF_SECONDS_MAX = 86_400.0
MAX_SAMPLES = 100_000  # about a day of simulation on two cores at the thesis' pace (50 samples: 29 s)
