"""What a tournament plays: its settings (frozen, checked) and the schedule of its matches.

Two policies play ``matches`` matches against each other (the same name twice is
self-play); three or more play a round robin, ``matches`` per pair. Each pair plays its
matches alternately with one and the other policy as the home team (home starts blue,
defends the blue goal and kicks off first), so colours, first kick-offs and ends are
balanced. Match ``i`` of pair ``p`` has its own seed, drawn from the tournament's seed: the
schedule does not depend on how or where the matches run.
"""

from __future__ import annotations

import dataclasses
import hashlib
import itertools
import json
import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from match.controllers import ControllerLimits
from world.camera_profiles import CAMERA_PROFILES, DEFAULT_CAMERA_PROFILE

MAX_PLAYERS = 4
PAUSE_NAMES = ("initial_seconds", "ready_seconds", "set_seconds")  # the referee's pauses before a kick-off

# Writes a match's replay page into the match directory it is given; returns the paths written.
PageWriter = Callable[[Path], Iterable[Path]]


class TournamentError(ValueError):
    """Settings a tournament cannot be played with; the message names the flag and the value."""


@dataclass(frozen=True)
class TournamentSettings:
    """``policies``: policy names (built in or ``package.module:ClassName``); ``matches``: per pair;
    ``half_seconds``, ``players`` (per side), ``shootout``: every match's; ``seed``: the
    tournament's. ``pauses``: the INITIAL, READY and SET seconds before each kick-off (None:
    the rules' 2, 15 and 3 s; shorter ones make quick test tournaments). ``controllers``: the
    limits of the policies' controller processes (None: in the match's process); they change
    no result of policies that keep to them. ``camera_profile``: every match's cameras' image
    profile (:mod:`world.camera_profiles`)."""

    policies: tuple[str, ...]
    matches: int = 10
    half_seconds: float = 600.0
    players: int = MAX_PLAYERS
    seed: int = 0
    shootout: bool = True
    pauses: tuple[float, float, float] | None = None
    controllers: ControllerLimits | None = ControllerLimits()
    camera_profile: str = DEFAULT_CAMERA_PROFILE

    def __post_init__(self) -> None:
        object.__setattr__(self, "policies", tuple(self.policies))
        if len(self.policies) < 2:
            given = ", ".join(repr(p) for p in self.policies) or "none"
            raise TournamentError(f"POLICY: {len(self.policies)} policy given ({given}); expected two or more "
                                  "(the same name twice for self-play)")
        if len(self.policies) > 2 and len(set(self.policies)) != len(self.policies):
            twice = sorted({p for p in self.policies if self.policies.count(p) > 1})
            raise TournamentError(f"POLICY: {', '.join(twice)} named twice; a round robin needs distinct policies "
                                  "(the same name twice is self-play, with two policies only)")
        if not _is_int(self.matches) or self.matches < 1:
            raise TournamentError(f"--matches {self.matches}: expected a positive integer")
        if not _is_number(self.half_seconds) or self.half_seconds <= 0:
            raise TournamentError(f"--half-seconds {self.half_seconds:g}: expected a positive number of seconds"
                                  if _is_number(self.half_seconds) else
                                  f"--half-seconds {self.half_seconds!r}: expected a positive number of seconds")
        if not _is_int(self.players) or not 1 <= self.players <= MAX_PLAYERS:
            raise TournamentError(f"--players {self.players}: expected 1 to {MAX_PLAYERS} robots per side")
        if not _is_int(self.seed):
            raise TournamentError(f"--seed {self.seed!r}: expected an integer")
        if self.pauses is not None:
            pauses = tuple(self.pauses)
            if len(pauses) != len(PAUSE_NAMES) or not all(_is_number(p) and p >= 0 for p in pauses):
                raise TournamentError(f"--pauses {self.pauses!r}: expected three numbers of seconds >= 0 "
                                      "(INITIAL, READY, SET)")
            object.__setattr__(self, "pauses", tuple(float(p) for p in pauses))
        if not isinstance(self.camera_profile, str) or self.camera_profile not in CAMERA_PROFILES:
            raise TournamentError(f"--camera-profile {self.camera_profile!r}: expected one of {sorted(CAMERA_PROFILES)}")

    @property
    def self_play(self) -> bool:
        return len(self.policies) == 2 and self.policies[0] == self.policies[1]

    def pairs(self) -> tuple[tuple[str, str], ...]:
        """Who plays whom: the two policies, or every pair of a round robin (in the order named)."""
        if len(self.policies) == 2:
            return (self.policies,)
        return tuple(itertools.combinations(self.policies, 2))

    def entrants(self) -> tuple[str, ...]:
        """The names standings are kept for: the policies, or ``NAME (home)`` and ``NAME (away)`` in self-play."""
        if self.self_play:
            return tuple(f"{self.policies[0]} ({side})" for side in ("home", "away"))
        return self.policies

    def match_count(self) -> int:
        """How many matches the tournament plays (``matches/000`` to ``matches/<count - 1>``)."""
        return len(self.pairs()) * self.matches

    def referee(self) -> dict[str, float]:
        """Referee settings of every match besides the half's length and the shoot-out."""
        return dict(zip(PAUSE_NAMES, self.pauses)) if self.pauses is not None else {}

    def tasks(self) -> tuple[MatchTask, ...]:
        """Every match, pair by pair; match ``i`` of a pair has the first policy at home when ``i`` is even."""
        pairs = self.pairs()
        pair_seeds = np.random.SeedSequence(self.seed).spawn(len(pairs))
        tasks = []
        for p, ((first, second), pair_seed) in enumerate(zip(pairs, pair_seeds)):
            for i, match_seed in enumerate(pair_seed.spawn(self.matches)):
                home, away = (first, second) if i % 2 == 0 else (second, first)
                seed = int(match_seed.generate_state(1)[0])
                tasks.append(MatchTask(p * self.matches + i, p, i, home, away, seed, self))
        return tuple(tasks)

    def to_json(self) -> dict:
        return {
            "policies": list(self.policies),
            "matches": self.matches,
            "half_seconds": self.half_seconds,
            "players": self.players,
            "seed": self.seed,
            "shootout": self.shootout,
            "pauses": list(self.pauses) if self.pauses is not None else None,
            "controllers": dataclasses.asdict(self.controllers) if self.controllers is not None else None,
            "camera_profile": self.camera_profile,
        }

    def fingerprint(self) -> str:
        """A hash of everything that changes the results (for ``--resume``): sha256 hex, 16 digits."""
        results = {key: value for key, value in self.to_json().items() if key != "controllers"}
        return hashlib.sha256(json.dumps(results, sort_keys=True).encode("utf-8")).hexdigest()[:16]


@dataclass(frozen=True)
class MatchTask:
    """One match of the schedule: its index, its pair and place in the pair, who is home, its seed.

    ``page``: what writes the match's replay page after it, in the worker (an output, not a
    setting: it is no part of the fingerprint; None: no page).
    """

    index: int
    pair: int
    game: int
    home: str
    away: str
    seed: int
    settings: TournamentSettings
    page: PageWriter | None = field(default=None, compare=False, repr=False)

    @property
    def label(self) -> str:
        return f"match {self.index} ({self.home} v {self.away})"

    def entrant(self, side: str) -> str:
        """The standings name of the team on ``side``."""
        if self.settings.self_play:
            return f"{self.home} ({side})"
        return self.home if side == "home" else self.away


def _is_int(value: object) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _is_number(value: object) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)

