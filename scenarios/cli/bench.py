"""``robotstadium bench``: rendering and physics costs, written to bench.json."""

from __future__ import annotations

import argparse
from pathlib import Path

from scenarios.cli.arguments import EXIT_OK, add_out_dir, int_in
from scenarios.tools.bench import DEFAULT_REPEATS, QUICK_REPEATS, format_table, run_bench

NAME = "bench"
HELP = "measure rendering and physics costs, write bench.json"
DESCRIPTION = (
    "Time one 160x120 robot camera frame, one 40 ms control step of 8 walking robots, env.step (cameras on "
    "and off), env steps under SuperSuit's vector env in 2 processes (cameras on and off), the 640x480 "
    "broadcast render, a short match (its real-time factor and peak memory) and the team agent's act; print "
    "a table and write DIR/bench.json (medians and 90th percentiles in ms, rates, peak memory in MiB, machine "
    "details)."
)
MAX_REPEATS = 5_000  # the agent benchmark alone plays up to 40 steps a repeat: hours beyond this


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_out_dir(parser)
    repeats = parser.add_mutually_exclusive_group()
    repeats.add_argument(
        "--repeats",
        type=int_in(1, MAX_REPEATS),
        default=DEFAULT_REPEATS,
        metavar="N",
        help=f"timed repeats per benchmark, 1-{MAX_REPEATS} (default {DEFAULT_REPEATS})",
    )
    repeats.add_argument(
        "--quick",
        action="store_const",
        dest="repeats",
        const=QUICK_REPEATS,
        help=f"a quick run: {QUICK_REPEATS} repeats",
    )


def run(args: argparse.Namespace) -> int:
    results = run_bench(args.out, repeats=args.repeats)
    print(format_table(results))
    print(Path(args.out) / "bench.json")
    return EXIT_OK
