"""What one episode of the env is: match length, pauses, shoot-out, start and step limit.

:class:`Episode` holds the settings; ``None`` in a field keeps what the env's
:class:`~match.game.MatchConfig` says (its referee). The env takes them as keyword arguments
(``parallel_env(half_seconds=60, shootout=False)``), as a preset (``parallel_env(preset="learning")``,
:data:`PRESETS`) and per episode as ``reset(options={...})`` with the same names. Simulated
seconds throughout; a control step is 40 ms.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, fields, replace

from match.errors import MatchConfigError, shown
from match.referee import RefereeConfig
from match.starts import Start

log = logging.getLogger(__name__)

DEFAULT_MAX_CYCLES = 100_000  # 4000 s of simulated time: a full match with its pauses fits
LEGACY_OPTIONS = ("random_start",)  # reset(options=) keys kept from before these settings


@dataclass(frozen=True)
class Episode:
    """One episode's settings.

    - ``half_seconds``: playing time of a half, s (None: the referee's, 600 s by default).
    - ``halves``: 1 or 2 (None: the referee's, 2 by default).
    - ``pauses``: False skips the referee's INITIAL, READY and SET pauses (each lasts one step);
      None or True keeps the referee's.
    - ``shootout``: whether a draw goes to a penalty shoot-out (None: the referee's, on by default).
    - ``start``: a :class:`~match.starts.Start` or its name: ``"kickoff"``, ``"random"``, ``"penalty"``.
    - ``max_cycles``: steps after which every agent is truncated.
    """

    half_seconds: float | None = None
    halves: int | None = None
    pauses: bool | None = None
    shootout: bool | None = None
    start: Start = Start.KICKOFF
    max_cycles: int = DEFAULT_MAX_CYCLES

    def __post_init__(self) -> None:
        if self.half_seconds is not None and (isinstance(self.half_seconds, bool)
                                              or not isinstance(self.half_seconds, (int, float))
                                              or not math.isfinite(self.half_seconds) or self.half_seconds <= 0):
            raise MatchConfigError(f"half_seconds = {shown(self.half_seconds)} is invalid; expected None or a "
                                   "finite number of seconds > 0")
        if self.halves is not None and (isinstance(self.halves, bool) or self.halves not in (1, 2)):
            raise MatchConfigError(f"halves = {shown(self.halves)} is invalid; expected None, 1 or 2")
        for name in ("pauses", "shootout"):
            if getattr(self, name) is not None and not isinstance(getattr(self, name), bool):
                raise MatchConfigError(f"{name} = {shown(getattr(self, name))} is invalid; expected None, True or False")
        object.__setattr__(self, "start", Start.of(self.start))
        if isinstance(self.max_cycles, bool) or not isinstance(self.max_cycles, int) or self.max_cycles < 1:
            raise MatchConfigError(f"max_cycles = {shown(self.max_cycles)} is invalid; expected an integer >= 1")

    def referee(self, base: RefereeConfig) -> RefereeConfig:
        """``base`` with this episode's length, halves, pauses and shoot-out."""
        changes: dict[str, object] = {}
        if self.half_seconds is not None:
            changes["half_seconds"] = float(self.half_seconds)
        if self.halves is not None:
            changes["halves"] = self.halves
        if self.pauses is False:
            changes.update(initial_seconds=0.0, ready_seconds=0.0, set_seconds=0.0)
        if self.shootout is not None:
            changes["shootout"] = self.shootout
        return replace(base, **changes) if changes else base

    def with_options(self, options: object) -> Episode:
        """These settings changed by ``reset(options=...)``: a dict of :class:`Episode` field names (and the
        older ``random_start``, read by the env); other keys are ignored with a warning. A
        :class:`MatchConfigError` for options that are not a dict or a bad value."""
        if options is None:
            return self
        if not isinstance(options, dict):
            raise MatchConfigError(f"reset options = {shown(options)} are invalid; expected None or a dict with "
                                   f"keys {OPTION_NAMES}")
        known = {name: value for name, value in options.items() if name in EPISODE_FIELDS}
        unknown = sorted(map(shown, set(options) - set(OPTION_NAMES)))
        if unknown:  # PettingZoo's api_test passes options of its own: ignored, as gymnasium envs do
            log.warning("reset options %s are not this env's (%s): ignored", ", ".join(unknown), ", ".join(OPTION_NAMES))
        return replace(self, **known) if known else self


EPISODE_FIELDS = tuple(f.name for f in fields(Episode))
OPTION_NAMES = EPISODE_FIELDS + LEGACY_OPTIONS

MATCH = Episode()
LEARNING = Episode(half_seconds=60.0, halves=1, pauses=False, shootout=False, start=Start.KICKOFF, max_cycles=2_000)
PRESETS: dict[str, Episode] = {"match": MATCH, "learning": LEARNING}
"""``"match"``: the referee's full match (the default). ``"learning"``: one 60 s half, no pauses, no shoot-out,
from the kick-off; at most 2,000 steps (80 s), though the half ends it first (about 1,500 steps)."""


def episode_of(preset: object, **overrides: object) -> Episode:
    """The preset named ``preset`` (None: ``"match"``) with the ``overrides`` that are not None."""
    if preset is None:
        base = MATCH
    elif isinstance(preset, Episode):
        base = preset
    elif isinstance(preset, str) and preset in PRESETS:
        base = PRESETS[preset]
    else:
        raise MatchConfigError(f"preset = {shown(preset)} is invalid; expected None, an Episode or one of "
                               f"{sorted(PRESETS)}")
    changes = {name: value for name, value in overrides.items() if value is not None}
    return replace(base, **changes) if changes else base
