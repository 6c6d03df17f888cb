"""``robotstadium replay``: the replay page (and figures) of a match directory."""

from __future__ import annotations

import argparse
from pathlib import Path

from scenarios.cli.arguments import EXIT_OK, input_path, int_in, output_file
from scenarios.cli.outputs import output_problem

NAME = "replay"
HELP = "write a match's replay page (one self-contained HTML file) and its figures"
DESCRIPTION = (
    "Read MATCH_DIR (match_log.npz, events.jsonl, summary.json, as robotstadium match writes them) and write "
    "a self-contained HTML page that plays the match (opens from disk, no network); with --plots also "
    "traces.png and localization.png beside the page. A corrupted or truncated log is refused (exit 2) "
    "and nothing is written."
)
MAX_STRIDE = 100_000  # a full match logs about 32 000 steps


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("match_dir", type=input_path, metavar="MATCH_DIR", help="a match's output directory")
    parser.add_argument("--out", type=output_file, default=None, metavar="FILE",
                        help="the page to write, refused before anything is read if it cannot be written "
                             "(default MATCH_DIR/replay.html)")
    parser.add_argument("--plots", action="store_true",
                        help="also write traces.png and localization.png beside the page")
    parser.add_argument("--stride", type=int_in(1, MAX_STRIDE), default=None, metavar="N",
                        help=f"keep every N-th logged step in the page, 1-{MAX_STRIDE} (default: at most 8000 frames)")


def run(args: argparse.Namespace) -> int:
    from scenarios.replay import PAGE_FILE, write_replay

    default_page = Path(args.match_dir) / PAGE_FILE
    if args.out is None and Path(args.match_dir).is_dir():  # the default page, checked as --out is
        problem = output_problem(str(default_page), directory=False)
        if problem is not None:
            raise ValueError(f"MATCH_DIR {args.match_dir}: cannot write its replay page: {problem}")
    for path in write_replay(args.match_dir, args.out, plots=args.plots, stride=args.stride):
        print(path)
    return EXIT_OK
