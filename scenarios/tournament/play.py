"""One match of a tournament, as a worker plays it: the match command's glue, its files returned.

:func:`play_match` runs in a worker process (a local one or a Ray task, maybe on another
machine): it plays the match with :func:`scenarios.matches.play.run_lineup_match` (the one
game loop) into a scratch directory, writes the match's replay page there when the task has
a page writer, and returns the outputs' bytes with the summary, so that only the driver
writes into the tournament's directory. A page that cannot be written does not fail the
match: its error comes back with the match.
"""

from __future__ import annotations

import json
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from scenarios.common.batch import describe_error
from scenarios.matches.play import Lineup, run_lineup_match
from scenarios.tournament.settings import MatchTask

MATCH_FILES = ("summary.json", "events.jsonl", "match_log.npz")


@dataclass(frozen=True)
class PlayedMatch:
    """A match played: its summary (``summary.json`` as written, with the match statistics) and its files
    (with its replay page's); ``page_error``: why its page was not written (one line), if it was not."""

    index: int
    summary: dict
    files: dict[str, bytes]
    wall_seconds: float
    page_error: str | None = None


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
                         progress=False, referee=settings.referee(), controllers=settings.controllers,
                         camera_profile=settings.camera_profile)
        files = {name: (out / name).read_bytes() for name in MATCH_FILES}
        wall_seconds = time.perf_counter() - started
        page_files, page_error = _write_page(task, out)
    summary = json.loads(files["summary.json"])
    return PlayedMatch(task.index, summary, {**page_files, **files}, wall_seconds, page_error)


def _write_page(task: MatchTask, out: Path) -> tuple[dict[str, bytes], str | None]:
    """The files ``task.page`` wrote into ``out`` (none without a writer), or its error: never raised."""
    if task.page is None:
        return {}, None
    try:
        return {Path(path).name: Path(path).read_bytes() for path in task.page(out)}, None
    except Exception as error:  # the page is an extra: the match stands without it
        return {}, describe_error(error)
