"""``robotstadium scenario``: thesis chapter 6's scenarios (or a scenario file), their statistics and figures."""

from __future__ import annotations

import argparse
import sys

from scenarios.cli.arguments import (
    EXIT_INTERRUPTED,
    EXIT_OK,
    add_batch_arguments,
    add_camera_profile,
    add_no_progress,
    add_out_dir,
    add_seed,
    batch_options,
    half_seconds,
    int_in,
    localizer_names,
    name_list,
)
from scenarios.common.limits import HALF_SECONDS_MAX, HALF_SECONDS_MIN, MAX_SAMPLES

NAME = "scenario"
HELP = "thesis chapter 6: run scenarios 1-3 (or a scenario file) and write their localization statistics"
DESCRIPTION = (
    "Run a scenario's independent runs (built-in 1, 2, 3, 3-match, 'all', or a path to a TOML scenario "
    "file) and write results.csv, summary.json, table.md (thesis Tables 6.1/6.2 with the thesis' values), "
    "errors.png (thesis figure 6.15) and traces.png into --out. Every method of the scenario localizes on the "
    "same percepts and motions; 3-match measures team agents while they play a refereed game, every second "
    "of PLAYING time. Finished runs are kept in --out/runs; --resume continues an interrupted batch."
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("scenarios", nargs="+", metavar="SCENARIO", help="1, 2, 3, 3-match, all, or a scenario file")
    parser.add_argument("--samples", type=int_in(1, MAX_SAMPLES), default=None, metavar="N",
                        help=f"localization events per method, 1-{MAX_SAMPLES} (default: the scenario file's; not used "
                             "by 3-match, whose runs last a match: see --half-seconds)")
    add_seed(parser, "seed of the runs", default=None, default_text="the scenario file's")
    parser.add_argument("--methods", type=name_list(localizer_names), default=None, metavar="M1,M2",
                        help="localization methods, comma-separated (default: the scenario file's)")
    parser.add_argument("--half-seconds", type=half_seconds, default=None, metavar="S",
                        help=f"length of a half of the refereed scenarios, {HALF_SECONDS_MIN:g}-{HALF_SECONDS_MAX:g} "
                             "seconds (default: the scenario file's)")
    add_camera_profile(parser)
    add_batch_arguments(parser, "runs")
    add_out_dir(parser, "out/scenarios")
    add_no_progress(parser)


def run(args: argparse.Namespace) -> int:
    # the simulation, the report's matplotlib and scipy: only when run
    from scenarios.localization.batch import run_named
    from scenarios.localization.tables import table_markdown

    options = batch_options(args)
    try:
        reports = run_named(args.scenarios, args.out, options, samples=args.samples, seed=args.seed,
                            methods=args.methods, half_seconds=args.half_seconds,
                            camera_profile=args.camera_profile)
    except KeyboardInterrupt:
        print(f"robotstadium scenario: interrupted; finished runs are kept in {args.out}: "
              "run again with --resume to continue", file=sys.stderr)
        return EXIT_INTERRUPTED
    print(table_markdown(reports))
    wall = max(r.wall_seconds for r in reports)  # the scenarios ran side by side
    print(f"{sum(len(r.samples) for r in reports)} result rows, {wall:.0f} s wall; written to {args.out}")
    return EXIT_OK
