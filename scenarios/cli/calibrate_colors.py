"""``robotstadium calibrate-colors``: fit the colour-segmentation thresholds on rendered frames."""

from __future__ import annotations

import argparse
from pathlib import Path

import agents.vision
from scenarios.cli.arguments import EXIT_OK, positive_int
from scenarios.tools.color_calibration import DEFAULT_FRAMES, calibrate_colors, format_scores, write_calibration

NAME = "calibrate-colors"
HELP = "fit the colour-segmentation thresholds on rendered frames"
DESCRIPTION = (
    "Render robot camera frames at seeded random poses, fit one RGB range per colour class "
    "from the pixels' true classes, print the per-class accuracy and write the thresholds to --out "
    "with a <name>_report.json beside them."
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    default_out = Path(agents.vision.__file__).parent / "data" / "color_thresholds.json"
    parser.add_argument("--frames", type=positive_int, default=DEFAULT_FRAMES, metavar="N",
                        help=f"calibration frames (default {DEFAULT_FRAMES}); a third as many more are held out")
    parser.add_argument("--seed", type=int, default=0, help="seed of the poses (default 0)")
    parser.add_argument("--out", type=Path, default=default_out, metavar="PATH",
                        help="threshold file to write (default: the one shipped in agents/vision/data)")


def run(args: argparse.Namespace) -> int:
    result = calibrate_colors(args.frames, args.seed)
    print(format_scores(result))
    print(f"{result.frames} + {result.holdout_frames} held-out frames in {result.seconds:.1f} s")
    for path in write_calibration(result, args.out):
        print(path)
    return EXIT_OK
