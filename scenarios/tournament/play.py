"""One match of a tournament, as a worker plays it: the match command's glue, its files returned.

:func:`play_match` runs in a worker process (a local one or a Ray task, maybe on another
machine): it plays the match with :func:`scenarios.matches.play.run_lineup_match` (the one
game loop) into a scratch directory and returns the outputs' bytes with the summary, so
that only the driver writes into the tournament's directory.
"""

from __future__ import annotations

import json
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from scenarios.matches.play import Lineup, run_lineup_match
from scenarios.tournament.settings import MatchTask

MATCH_FILES = ("summary.json", "events.jsonl", "match_log.npz")


@dataclass(frozen=True)
class PlayedMatch:
    """A match played: its summary (``summary.json`` as written, with the match statistics) and its files."""

    index: int
    summary: dict
    files: dict[str, bytes]
    wall_seconds: float


def play_match(task: MatchTask, tick: Callable[..., None] | None = None) -> PlayedMatch:
    """Play ``task``'s match headless; a policy's failures are in the summary's faults, not raised.

    ``tick``: the batch engine's progress counter, unused (the tournament counts whole matches).
    """
    started = time.perf_counter()
    settings = task.settings
    with tempfile.TemporaryDirectory(prefix=f"robotstadium_match_{task.index:03d}_") as scratch:
        out = Path(scratch)
        run_lineup_match(out, Lineup(task.home, task.away), home=settings.players, away=settings.players,
                         half_seconds=settings.half_seconds, seed=task.seed, shootout=settings.shootout,
                         progress=False, referee=settings.referee())
        files = {name: (out / name).read_bytes() for name in MATCH_FILES}
    summary = json.loads(files["summary.json"])
    return PlayedMatch(task.index, summary, files, time.perf_counter() - started)
