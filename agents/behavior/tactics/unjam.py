"""Getting free when a commanded turn does not turn: two robots that turn in place against each
other can lock together and stand for good, both commanding a turn while their gyros read nothing.

The robot compares the turn it commands with the turn its gyro measures over the last
:data:`WINDOW_S`; when it commanded at least :data:`MIN_COMMANDED_RAD` and turned less than
:data:`TURNED_SHARE` of it, it is jammed, and for :data:`ESCAPE_S` it steps back and aside
(away from the nearer sonar echo) instead. Walk commands are (vx m/s, vy m/s, omega rad/s) in
the torso frame, as in :mod:`agents.behavior.skills`.
"""

from __future__ import annotations

from collections import deque

from agents.behavior.skills import walk_command

WINDOW_S = 1.5  # ours: the stretch of turning compared with the gyro
MIN_COMMANDED_RAD = 0.8  # ours: at least this much turn commanded in the window ...
TURNED_SHARE = 0.2  # ... and less than this share of it measured: jammed
ESCAPE_S = 1.2  # ours: then this long stepping back and aside
ESCAPE_BACK_MPS = 0.08
ESCAPE_SIDE_MPS = 0.08


class Unjammer:
    """Watches commanded against measured turns (one call a control step) and, once jammed, gives
    the escape walk for a while."""

    def __init__(self, step_s: float):
        self._step_s = step_s
        self._window: deque[tuple[float, float]] = deque(maxlen=max(1, round(WINDOW_S / step_s)))
        self._escape_steps = 0
        self._side = 1.0
        self.escapes = 0  # times it got jammed (statistics)

    def reset(self) -> None:
        self._window.clear()
        self._escape_steps = 0

    def observe(self, commanded_omega: float, measured_omega: float) -> None:
        """The last step's commanded turn rate and the gyro's (rad/s)."""
        self._window.append((commanded_omega * self._step_s, measured_omega * self._step_s))

    def escape(self, sonar_m: tuple[float, ...]) -> tuple[float, float, float] | None:
        """The escape walk while jammed (None: not jammed, play on). ``sonar_m``: upper-left,
        upper-right, lower-left, lower-right echoes (m); it steps toward the side with the farther one."""
        if self._escape_steps == 0 and self._jammed():
            self._escape_steps = max(1, round(ESCAPE_S / self._step_s))
            self._side = 1.0 if len(sonar_m) < 4 or min(sonar_m[0], sonar_m[2]) >= min(sonar_m[1], sonar_m[3]) else -1.0
            self._window.clear()
            self.escapes += 1
        if self._escape_steps == 0:
            return None
        self._escape_steps -= 1
        return walk_command(-ESCAPE_BACK_MPS, self._side * ESCAPE_SIDE_MPS, 0.0)

    def _jammed(self) -> bool:
        if len(self._window) < (self._window.maxlen or 0):
            return False
        commanded = sum([c for c, _ in self._window])
        if abs(commanded) < MIN_COMMANDED_RAD:
            return False
        turned = sum([m for _, m in self._window])
        return turned * commanded < TURNED_SHARE * commanded * commanded  # turned less than the share, same sense
