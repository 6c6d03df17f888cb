"""The ``robotstadium`` command line.

Each subcommand is one ``_add_<name>(subparsers)`` function that declares its arguments
and sets ``handler``; register it in :data:`SUBCOMMANDS`. Handlers get the parsed
arguments and return an exit code. Errors of the library (a
:class:`~world.errors.WorldError` or a ``ValueError`` from a bad argument) end the
command with a one-line message on stderr and exit code 2, without a traceback; a file
that cannot be written ends it the same way with exit code 1.
"""

from __future__ import annotations

import argparse
import logging
import sys
from collections.abc import Callable, Sequence
from pathlib import Path

from scenarios.bench import DEFAULT_REPEATS, QUICK_REPEATS, format_table, run_bench
from scenarios.world_demo import run_world_demo
from match.errors import MatchError
from world.errors import WorldError

EXIT_OK = 0
EXIT_FAILED = 1
EXIT_USAGE = 2

Handler = Callable[[argparse.Namespace], int]


def positive_int(text: str) -> int:
    """argparse type: an integer >= 1."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {value}")
    return value


def _verbose_flag(parser: argparse.ArgumentParser, default: object) -> None:
    parser.add_argument("-v", "--verbose", action="store_true", default=default, help="log debug messages")


def _add_subparser(subparsers: argparse._SubParsersAction, name: str, **kwargs) -> argparse.ArgumentParser:
    """A subcommand's parser; it accepts ``--verbose`` after the subcommand name too."""
    common = argparse.ArgumentParser(add_help=False)
    _verbose_flag(common, argparse.SUPPRESS)  # do not overwrite a --verbose given before
    return subparsers.add_parser(name, parents=[common], **kwargs)


# ---- subcommands -------------------------------------------------------------------------


def _add_world_demo(subparsers: argparse._SubParsersAction) -> None:
    parser = _add_subparser(
        subparsers,
        "world-demo",
        help="write camera frames, overviews and a kick strip of the world as PNGs",
        description="Build one world with 4 blue and 4 red robots and write robot camera frames from "
        "known poses, a broadcast overview, a top view, a kick strip and an index.md into --out.",
    )
    parser.add_argument("--out", type=Path, required=True, metavar="DIR", help="output directory (created)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the motion noise (default 0)")

    def handler(args: argparse.Namespace) -> int:
        for path in run_world_demo(args.out, seed=args.seed):
            print(path)
        return EXIT_OK

    parser.set_defaults(handler=handler)


def _add_bench(subparsers: argparse._SubParsersAction) -> None:
    parser = _add_subparser(
        subparsers,
        "bench",
        help="measure rendering and physics costs, write bench.json",
        description="Time one 160x120 robot camera frame and one 40 ms control step of 8 walking robots; "
        "print a table and write DIR/bench.json (medians and 90th percentiles in ms, machine details).",
    )
    parser.add_argument("--out", type=Path, required=True, metavar="DIR", help="output directory (created)")
    repeats = parser.add_mutually_exclusive_group()
    repeats.add_argument(
        "--repeats",
        type=positive_int,
        default=DEFAULT_REPEATS,
        help=f"timed repeats per benchmark (default {DEFAULT_REPEATS})",
    )
    repeats.add_argument(
        "--quick",
        action="store_const",
        dest="repeats",
        const=QUICK_REPEATS,
        help=f"a quick run: {QUICK_REPEATS} repeats",
    )

    def handler(args: argparse.Namespace) -> int:
        results = run_bench(args.out, repeats=args.repeats)
        print(format_table(results))
        print(Path(args.out) / "bench.json")
        return EXIT_OK

    parser.set_defaults(handler=handler)


def positive_float(text: str) -> float:
    """argparse type: a finite number > 0."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive number, got {text!r}") from None
    if not (value > 0 and value < float("inf")):
        raise argparse.ArgumentTypeError(f"expected a positive number, got {value}")
    return value


def _add_match(subparsers: argparse._SubParsersAction) -> None:
    parser = _add_subparser(
        subparsers,
        "match",
        help="run a full match headless with the built-in agents",
        description="Play a match (two halves, kick-offs, goals, throw-ins, half-time, penalty shoot-out on a tie) "
        "with the built-in policies and write summary.json, events.jsonl and match_log.npz into --out.",
    )
    parser.add_argument("--home", type=positive_int, default=4, metavar="N", help="home players, 1-4 (default 4)")
    parser.add_argument("--away", type=positive_int, default=4, metavar="N", help="away players, 1-4 (default 4)")
    parser.add_argument("--half-seconds", type=positive_float, default=600.0, metavar="S",
                        help="playing time of each half in simulated seconds (default 600)")
    parser.add_argument("--seed", type=int, default=0, help="match seed (default 0)")
    parser.add_argument("--out", type=Path, default=Path("out/match"), metavar="DIR", help="output directory (default out/match)")
    parser.add_argument("--no-progress", dest="progress", action="store_false", help="no progress bar")
    parser.add_argument("--shootout", action=argparse.BooleanOptionalAction, default=True,
                        help="decide a tie by penalty shoot-out (default: yes)")

    def handler(args: argparse.Namespace) -> int:
        from scenarios.match_run import run_default_match

        summary = run_default_match(
            args.out, home=args.home, away=args.away, half_seconds=args.half_seconds, seed=args.seed,
            shootout=args.shootout, progress=args.progress,
        )
        score = summary.score
        result = f"home {score['home']} - {score['away']} away"
        if summary.shootout:
            result += f" (shoot-out {summary.shootout['home']}-{summary.shootout['away']})"
        print(f"{result}; {summary.sim_seconds:.0f} s simulated in {summary.wall_seconds:.0f} s "
              f"({summary.real_time_factor:.2f}x real time)")
        print(Path(args.out) / "summary.json")
        return EXIT_OK

    parser.set_defaults(handler=handler)


SUBCOMMANDS: tuple[Callable[[argparse._SubParsersAction], None], ...] = (_add_world_demo, _add_bench, _add_match)


# ---- entry point -------------------------------------------------------------------------


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="robotstadium", description="Simulate RobotStadium robot-soccer matches in PyBullet."
    )
    _verbose_flag(parser, False)
    subparsers = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for add in SUBCOMMANDS:
        add(subparsers)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; return the exit code (argparse exits with 2 on usage errors)."""
    args = build_parser().parse_args(argv)
    logging.basicConfig(
        level=logging.DEBUG if args.verbose else logging.INFO,
        format="%(levelname)s %(name)s: %(message)s",
        stream=sys.stderr,
    )
    handler: Handler = args.handler
    try:
        return handler(args)
    except (WorldError, MatchError, ValueError) as error:
        print(f"robotstadium {args.command}: error: {error}", file=sys.stderr)
        return EXIT_USAGE
    except OSError as error:
        print(f"robotstadium {args.command}: error: {error}", file=sys.stderr)
        return EXIT_FAILED


if __name__ == "__main__":
    raise SystemExit(main())
