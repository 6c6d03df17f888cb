"""``robotstadium bench``: rendering and physics costs, written to bench.json."""

from __future__ import annotations

import argparse
from pathlib import Path

from scenarios.cli.arguments import EXIT_OK, add_out_dir, input_path, int_in
from scenarios.tools.bench import (
    COMPARE_FILE,
    DEFAULT_REPEATS,
    QUICK_REPEATS,
    BenchFileError,
    compare_results,
    format_comparison,
    format_table,
    read_bench_file,
    run_bench,
    write_comparison,
)

NAME = "bench"
HELP = "measure rendering and physics costs, write bench.json"
DESCRIPTION = (
    "Time one 160x120 robot camera frame, one 40 ms control step of 8 walking robots, env.step (cameras on "
    "and off), env steps under SuperSuit's vector env in 2 processes (cameras on and off), the 640x480 "
    "broadcast render, a short match (its real-time factor and peak memory), the team agent's act and the "
    "resident memory over consecutive short matches in one process; print "
    "a table and write DIR/bench.json (medians and 90th percentiles in ms, rates, peak memory in MiB, machine "
    "details). With --compare OLD_JSON, also print and write (DIR/compare.json) each figure's ratio to OLD_JSON's."
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
    parser.add_argument(
        "--compare",
        type=input_path,
        default=None,
        metavar="OLD_JSON",
        help="an earlier bench.json: print each figure's ratio new/old, marking those more than 10%% worse or "
             f"better, and write DIR/{COMPARE_FILE}; refused before anything runs if it is not a bench.json",
    )


def run(args: argparse.Namespace) -> int:
    old = None
    if args.compare is not None:
        try:
            old = read_bench_file(args.compare)
        except BenchFileError as error:
            raise BenchFileError(f"--compare {error}") from None
    results = run_bench(args.out, repeats=args.repeats)
    print(format_table(results))
    print(Path(args.out) / "bench.json")
    if old is not None:
        rows = compare_results(results, old)
        print()
        print(format_comparison(rows, str(args.compare)))
        print(write_comparison(args.out, rows, args.compare))
    return EXIT_OK
