"""``robotstadium localize``: scenario 1 of thesis chapter 6 in one run, a table of errors per method."""

from __future__ import annotations

import argparse

from scenarios.cli.arguments import EXIT_OK, add_seed, int_in, localizer_names, name_list

NAME = "localize"
HELP = "scenario 1 of thesis chapter 6: one robot alone, move, scan, localize with every method"
DESCRIPTION = (
    "One robot alone on the field repeats a random motion, a five-frame head scan and a "
    "localization with each method side by side on the same percepts; each estimate is compared with "
    "the robot's true pose. Prints mean and median errors and the median localize() time per method."
)
MAX_SAMPLES = 10_000  # one run in one process: about 100 minutes here (50 samples: 29 s)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--samples", type=int_in(1, MAX_SAMPLES), default=50, metavar="N",
                        help=f"localizations, 1-{MAX_SAMPLES} (default 50)")
    add_seed(parser, "seed")
    parser.add_argument("--methods", type=name_list(localizer_names), default=("thesis", "particle", "hybrid", "odometry"),
                        metavar="M1,M2", help="localization methods, comma-separated (default thesis,particle,hybrid,odometry)")


def run(args: argparse.Namespace) -> int:
    from scenarios.localization.run import run_alone  # the simulation: only when run
    from scenarios.localization.statistics import summarize

    result = run_alone(args.samples, args.seed, args.methods)
    print("| method | samples | position mean / median (cm) | orientation mean / median (deg) | localize ms (median) |")
    print("|---|---|---|---|---|")
    for method, s in summarize(result.samples).items():
        print(f"| {method} | {s['with_estimate']}/{s['samples']} | {s['position_mean_cm']:.1f} / {s['position_median_cm']:.1f} "
              f"| {s['orientation_mean_deg']:.1f} / {s['orientation_median_deg']:.1f} | {s['localize_ms_median']:.2f} |")
    print(f"{args.samples} samples, {result.sim_seconds:.0f} s simulated in {result.wall_seconds:.1f} s")
    return EXIT_OK
