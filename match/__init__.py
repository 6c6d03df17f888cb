"""The rules of a match and its interface: protocol, referee, radio, env and runner.

``from match import parallel_env`` gives the PettingZoo environment, ``from match import raw_env``
its AEC version; the order-enforced AEC factory is ``match.env.env`` (``match.env`` names the
module). They are loaded on first use, so that importing :mod:`match.protocol` (what agents
may use) stays free of pybullet.
"""

from __future__ import annotations

import world  # noqa: F401 - first: it caps numpy's SIMD kernels before numpy is imported

__all__ = ["RobotStadiumEnv", "parallel_env", "raw_env"]


def __getattr__(name: str):
    if name in __all__:
        from match import env

        return getattr(env, name)
    raise AttributeError(f"module 'match' has no attribute {name!r}")
