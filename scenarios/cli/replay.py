"""``robotstadium replay``: the replay page (and figures) of a match directory."""

from __future__ import annotations

import argparse
from pathlib import Path

from scenarios.cli.arguments import EXIT_OK, positive_int

NAME = "replay"
HELP = "write a match's replay page (one self-contained HTML file) and its figures"
DESCRIPTION = (
    "Read MATCH_DIR (match_log.npz, events.jsonl, summary.json, as robotstadium match writes them) and write "
    "a self-contained HTML page that plays the match (opens from disk, no network); with --plots also "
    "traces.png and localization.png beside the page. A corrupted or truncated log is refused (exit 2) "
    "and nothing is written."
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("match_dir", type=Path, metavar="MATCH_DIR", help="a match's output directory")
    parser.add_argument("--out", type=Path, default=None, metavar="FILE",
                        help="the page to write (default MATCH_DIR/replay.html)")
    parser.add_argument("--plots", action="store_true",
                        help="also write traces.png and localization.png beside the page")
    parser.add_argument("--stride", type=positive_int, default=None, metavar="N",
                        help="keep every N-th logged step in the page (default: at most 8000 frames)")


def run(args: argparse.Namespace) -> int:
    from scenarios.replay import write_replay

    for path in write_replay(args.match_dir, args.out, plots=args.plots, stride=args.stride):
        print(path)
    return EXIT_OK
