"""The physical world of a match: field, robots, ball, cameras and sensors (no rules, no agents).

Importing it first caps numpy's CPU-dispatched kernels at AVX2 (``NPY_DISABLE_CPU_FEATURES``,
unless set already and unless numpy was imported before): numpy's AVX-512 kernels of the
transcendental functions are other implementations than the AVX2 ones and may differ in the
last bit, which a match, chaotic as it is, can turn into another game. Machines with and
without AVX-512 then take the same numpy paths. For the same reason it pins the kernels of
numpy's BLAS (OpenBLAS, which picks them by processor model: SkylakeX with AVX-512, Haswell or Zen
without) at Haswell's (``OPENBLAS_CORETYPE``) on x86-64 processors with AVX2 and FMA, unless set
already and unless numpy was imported before. :mod:`match` and :mod:`scenarios` import this
package first.
"""

from __future__ import annotations

import os
import platform
import sys
from importlib import metadata

# numpy 2 groups the x86 extensions in levels (X86_V4: AVX-512); numpy 1 names each one.
_AVX512 = {2: "X86_V4 AVX512_ICL AVX512_SPR",
           1: "AVX512F AVX512CD AVX512_KNL AVX512_KNM AVX512_SKX AVX512_CLX AVX512_CNL AVX512_ICL AVX512_SPR"}


def _numpy_cap() -> str:
    """The value of ``NPY_DISABLE_CPU_FEATURES`` that caps the installed numpy at AVX2."""
    try:
        major = int(metadata.version("numpy").split(".")[0])
    except (metadata.PackageNotFoundError, ValueError):
        major = 2
    return _AVX512[2 if major >= 2 else 1]


NUMPY_CAP = _numpy_cap()


def _cap_numpy_simd() -> None:
    if "numpy" in sys.modules or "NPY_DISABLE_CPU_FEATURES" in os.environ:
        return
    os.environ["NPY_DISABLE_CPU_FEATURES"] = NUMPY_CAP


BLAS_CORE = "Haswell"  # OpenBLAS's AVX2 + FMA kernels


def _has_avx2_fma() -> bool:
    """Whether this is an x86-64 processor with AVX2 and FMA (Linux: read from /proc/cpuinfo)."""
    if platform.machine().lower() not in ("x86_64", "amd64"):
        return False
    try:
        with open("/proc/cpuinfo", encoding="ascii", errors="replace") as cpuinfo:
            for line in cpuinfo:
                if line.startswith("flags"):
                    return {"avx2", "fma"} <= set(line.split(":", 1)[1].split())
    except OSError:
        pass
    return False


def _pin_blas_kernels() -> None:
    if "numpy" in sys.modules or "OPENBLAS_CORETYPE" in os.environ or not _has_avx2_fma():
        return
    os.environ["OPENBLAS_CORETYPE"] = BLAS_CORE


_cap_numpy_simd()
_pin_blas_kernels()
