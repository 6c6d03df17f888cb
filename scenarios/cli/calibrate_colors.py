"""``robotstadium calibrate-colors``: fit the colour-segmentation thresholds on rendered frames."""

from __future__ import annotations

import argparse
from pathlib import Path

import agents.vision
from scenarios.cli.arguments import EXIT_OK, add_camera_profile, add_seed, int_in, output_file
from scenarios.cli.outputs import output_problem
from scenarios.tools.color_calibration import (
    CALIBRATION_PROFILE,
    DEFAULT_FRAMES,
    calibrate_colors,
    format_scores,
    report_path,
    write_calibration,
)

NAME = "calibrate-colors"
HELP = "fit the colour-segmentation thresholds on rendered frames"
DESCRIPTION = (
    "Render robot camera frames at seeded random poses, fit one RGB range per colour class "
    "from the pixels' true classes, print the per-class accuracy and write the thresholds to --out "
    "with a <name>_report.json beside them."
)
MAX_FRAMES = 2_000  # every frame and its labels are held in memory, 77 kB each, and a third as many held out


def add_arguments(parser: argparse.ArgumentParser) -> None:
    default_out = Path(agents.vision.__file__).parent / "data" / "color_thresholds.json"
    parser.add_argument("--frames", type=int_in(1, MAX_FRAMES), default=DEFAULT_FRAMES, metavar="N",
                        help=f"calibration frames, 1-{MAX_FRAMES} (default {DEFAULT_FRAMES}); a third as many more "
                             "are held out")
    add_seed(parser, "seed of the poses")
    parser.add_argument("--out", type=output_file, default=str(default_out), metavar="PATH",
                        help="threshold file to write, refused before anything runs if it cannot be written "
                             "(default: the one shipped in agents/vision/data)")
    add_camera_profile(parser, default_text=CALIBRATION_PROFILE)


def run(args: argparse.Namespace) -> int:
    problem = output_problem(str(report_path(args.out)), directory=False)
    if problem is not None:  # the report beside the thresholds, refused before the frames are rendered
        raise ValueError(f"--out {args.out}: its report: {problem}")
    result = calibrate_colors(args.frames, args.seed, camera_profile=args.camera_profile or CALIBRATION_PROFILE)
    print(format_scores(result))
    print(f"{result.frames} + {result.holdout_frames} held-out frames in {result.seconds:.1f} s")
    for path in write_calibration(result, args.out):
        print(path)
    return EXIT_OK
