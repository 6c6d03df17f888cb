"""``python -m agents.compile`` (run by ``make install``) compiles every kernel of the agents, so that no
controller process spends its first steps compiling one."""

from __future__ import annotations

import numba

import agents.localization.kernels as localization_kernels
import agents.vision.kernels as vision_kernels
from agents.compile import compile_agents


def test_compile_agents_runs_every_kernel() -> None:
    compile_agents()
    kernels = {f"{module.__name__}.{name}": value for module in (vision_kernels, localization_kernels)
               for name, value in vars(module).items()
               if isinstance(value, numba.core.registry.CPUDispatcher) and value.__module__ == module.__name__
               and value.targetoptions.get("inline") != "always"}  # helpers compiled into their callers
    assert len(kernels) >= 9
    assert [name for name, kernel in kernels.items() if not kernel.signatures] == []
