"""Watching a match: a self-contained replay page and the match's localization figures.

:func:`write_replay` reads a match directory (``match_log.npz``, ``events.jsonl``,
``summary.json``; :mod:`scenarios.replay.record` checks them), and writes ``replay.html``
(:mod:`scenarios.replay.page`, data format in :mod:`scenarios.replay.data`), ``traces.png``
and ``localization.png`` (:mod:`scenarios.replay.plots`). A corrupted or truncated log is a
:class:`ReplayInputError` (a ``ValueError``) raised before anything is written.
"""

from __future__ import annotations

import logging
from pathlib import Path

from scenarios.replay.record import ReplayInputError, load_match

__all__ = ["PAGE_FILE", "LOCALIZATION_FILE", "TRACES_FILE", "ReplayInputError", "load_match", "write_replay"]

PAGE_FILE = "replay.html"
TRACES_FILE = "traces.png"
LOCALIZATION_FILE = "localization.png"

log = logging.getLogger(__name__)


def write_replay(
    match_dir: Path,
    page: Path | None = None,
    *,
    write_page: bool = True,
    plots: bool = False,
    stride: int | None = None,
) -> list[Path]:
    """Write the replay page (default ``match_dir/replay.html``) and, with ``plots``, the figures beside it.

    Everything is read, checked and drawn before the first file is written. Returns the paths written.
    """
    from scenarios.common.io import write_text_atomic
    from scenarios.replay.data import replay_data
    from scenarios.replay.page import render_page

    record = load_match(Path(match_dir))
    page = Path(page) if page is not None else Path(match_dir) / PAGE_FILE
    html = render_page(replay_data(record, stride)) if write_page else None
    figures = {}
    if plots:
        from scenarios.replay.plots import DPI, plot_localization, plot_traces

        figures = {page.parent / TRACES_FILE: plot_traces(record), page.parent / LOCALIZATION_FILE: plot_localization(record)}
    written = []
    if html is not None:
        written.append(write_text_atomic(page, html))
        log.info("wrote %s (%.1f MB)", page, page.stat().st_size / 1e6)
    if figures:
        from scenarios.common.plotting import save_figure

        for path, figure in figures.items():
            written.append(save_figure(figure, path, DPI))
    return written
