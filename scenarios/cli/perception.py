"""``robotstadium perception``: the vision pipeline's landmark percepts scored against ground truth."""

from __future__ import annotations

import argparse
from pathlib import Path

from scenarios.cli.arguments import (
    EXIT_OK,
    add_camera_profile,
    add_no_progress,
    add_out_dir,
    add_seed,
    camera_model_names,
    int_in,
    name_list,
    number_in,
)
from scenarios.perception.records import MAX_CROWD, MAX_HEAD_RATE_RADPS, PerceptionConfig
from world.camera_profiles import DEFAULT_CAMERA_PROFILE

NAME = "perception"
HELP = "score the vision pipeline's landmark percepts against ground truth"
DESCRIPTION = (
    "Place a robot at seeded random poses in the thesis' scan posture, render its camera "
    "(empty field, or with --crowd other robots around), run the vision pipeline with each camera model "
    "and score every percept against the true landmarks; write summary.json, table.md, detections.csv, "
    "visible.csv, errors_vs_distance.png, examples/ (frames with errors, truth marked) and overlays/ "
    "(the same frames as the pipeline saw them) into --out."
)
MAX_FRAMES = 20_000  # about half an hour on a small machine (1000 frames: 78 s), every record held in memory
MAX_EXAMPLES = 1_000  # each held in memory as a camera image until written
MAX_RANGE_M = (0.1, 20.0)  # metres; the field is 6 m x 4 m


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--frames", type=int_in(1, MAX_FRAMES), required=True, metavar="N",
                        help=f"frames to render, 1-{MAX_FRAMES}")
    add_seed(parser, "seed of the poses")
    add_out_dir(parser)
    parser.add_argument("--crowd", type=int_in(0, MAX_CROWD), default=0, metavar="K",
                        help=f"other robots standing on the field, 0-{MAX_CROWD} (default 0)")
    parser.add_argument("--models", type=name_list(camera_model_names), default=("exact", "thesis"), metavar="M1,M2",
                        help="camera models to score, comma-separated (default exact,thesis)")
    parser.add_argument("--max-range-m", type=number_in(*MAX_RANGE_M), default=4.0, metavar="M",
                        help="landmarks farther than this are not expected and their errors not counted, "
                             f"{MAX_RANGE_M[0]:g}-{MAX_RANGE_M[1]:g} m (default 4)")
    parser.add_argument("--examples", type=int_in(0, MAX_EXAMPLES), default=6, metavar="N",
                        help=f"annotated PNGs of frames with a false positive or a miss, 0-{MAX_EXAMPLES} (default 6)")
    add_camera_profile(parser)
    parser.add_argument("--head-rate", type=number_in(0.0, MAX_HEAD_RATE_RADPS), default=0.0, metavar="RADPS",
                        help="the head turns at this rate (rad/s) through each frame's control step, so the camera "
                             f"profile blurs and shears the frame as in a head scan, 0-{MAX_HEAD_RATE_RADPS:g} "
                             "(default 0: the head is still)")
    add_no_progress(parser)


def run(args: argparse.Namespace) -> int:
    from scenarios.perception.run import run_perception  # the pipeline, pybullet and matplotlib: only when run

    profile = args.camera_profile or DEFAULT_CAMERA_PROFILE
    command = (f"robotstadium perception --frames {args.frames} --seed {args.seed} --out {args.out} "
               f"--crowd {args.crowd} --models {','.join(args.models)} --max-range-m {args.max_range_m:g} "
               f"--camera-profile {profile} --head-rate {args.head_rate:g}")
    config = PerceptionConfig(args.frames, args.seed, args.crowd, args.models, args.max_range_m,
                              args.progress, args.examples, command, profile, args.head_rate)
    summary = run_perception(args.out, config)
    print((Path(args.out) / "table.md").read_text())
    print(f"{summary['frames']} frames in {summary['wall_seconds']:.1f} s; "
          f"pipeline median {summary['ms_per_frame_median']:.2f} ms per frame")
    print(Path(args.out) / "summary.json")
    return EXIT_OK
