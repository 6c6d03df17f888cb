"""``robotstadium perception``: the vision pipeline's landmark percepts scored against ground truth."""

from __future__ import annotations

import argparse
from pathlib import Path

from scenarios.cli.arguments import (
    EXIT_OK,
    add_no_progress,
    add_out_dir,
    camera_model_names,
    name_list,
    positive_float,
    positive_int,
)
from scenarios.perception.records import MAX_CROWD, PerceptionConfig

NAME = "perception"
HELP = "score the vision pipeline's landmark percepts against ground truth"
DESCRIPTION = (
    "Place a robot at seeded random poses in the thesis' scan posture, render its camera "
    "(empty field, or with --crowd other robots around), run the vision pipeline with each camera model "
    "and score every percept against the true landmarks; write summary.json, table.md, detections.csv, "
    "visible.csv, errors_vs_distance.png, examples/ (frames with errors, truth marked) and overlays/ "
    "(the same frames as the pipeline saw them) into --out."
)


def crowd_count(text: str) -> int:
    """argparse type: an integer 0 .. :data:`MAX_CROWD`."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer 0-{MAX_CROWD}, got {text!r}") from None
    if not 0 <= value <= MAX_CROWD:
        raise argparse.ArgumentTypeError(f"expected an integer 0-{MAX_CROWD}, got {value}")
    return value


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--frames", type=positive_int, required=True, metavar="N", help="frames to render")
    parser.add_argument("--seed", type=int, default=0, help="seed of the poses (default 0)")
    add_out_dir(parser)
    parser.add_argument("--crowd", type=crowd_count, default=0, metavar="K",
                        help=f"other robots standing on the field, 0-{MAX_CROWD} (default 0)")
    parser.add_argument("--models", type=name_list(camera_model_names), default=("exact", "thesis"), metavar="M1,M2",
                        help="camera models to score, comma-separated (default exact,thesis)")
    parser.add_argument("--max-range-m", type=positive_float, default=4.0, metavar="M",
                        help="landmarks farther than this are not expected and their errors not counted (default 4)")
    parser.add_argument("--examples", type=int, default=6, metavar="N",
                        help="annotated PNGs of frames with a false positive or a miss (default 6)")
    add_no_progress(parser)


def run(args: argparse.Namespace) -> int:
    from scenarios.perception.run import run_perception  # the pipeline, pybullet and matplotlib: only when run

    command = (f"robotstadium perception --frames {args.frames} --seed {args.seed} --out {args.out} "
               f"--crowd {args.crowd} --models {','.join(args.models)} --max-range-m {args.max_range_m:g}")
    config = PerceptionConfig(args.frames, args.seed, args.crowd, args.models, args.max_range_m,
                              args.progress, args.examples, command)
    summary = run_perception(args.out, config)
    print((Path(args.out) / "table.md").read_text())
    print(f"{summary['frames']} frames in {summary['wall_seconds']:.1f} s; "
          f"pipeline median {summary['ms_per_frame_median']:.2f} ms per frame")
    print(Path(args.out) / "summary.json")
    return EXIT_OK
