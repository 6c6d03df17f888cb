"""``robotstadium world-demo``: camera frames, overviews and a kick strip of the world as PNGs."""

from __future__ import annotations

import argparse

from scenarios.cli.arguments import EXIT_OK, add_out_dir, add_seed
from scenarios.tools.world_demo import run_world_demo

NAME = "world-demo"
HELP = "write camera frames, overviews and a kick strip of the world as PNGs"
DESCRIPTION = (
    "Build one world with 4 blue and 4 red robots and write robot camera frames from "
    "known poses, a broadcast overview, a top view, a kick strip and an index.md into --out."
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_out_dir(parser)
    add_seed(parser, "seed of the motion noise")


def run(args: argparse.Namespace) -> int:
    for path in run_world_demo(args.out, seed=args.seed):
        print(path)
    return EXIT_OK
