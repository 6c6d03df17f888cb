"""The ``robotstadium`` command line.

Each subcommand is one module of this package: its ``NAME``, ``HELP`` and ``DESCRIPTION``,
``add_arguments(parser)``, which declares its arguments, and ``run(args)``, which runs it
and returns an exit code; register the module in :data:`SUBCOMMANDS`. Argument types,
common arguments and exit codes shared by subcommands are in :mod:`scenarios.cli.arguments`.
Every number and path on the command line is checked when it is parsed, against the bounds
its help states, and a bad one ends the command with a one-line message naming the flag and
exit code 2 before anything runs or is written. Errors of the library (a
:class:`~world.errors.WorldError`, a :class:`~match.errors.MatchError` or a ``ValueError``
from a bad argument or input file) end it the same way, also before anything is written; a
file that cannot be written while the command runs ends it the same way with exit code 1.
A SIGTERM is a Ctrl-C (``KeyboardInterrupt``): a tournament, a drill or a scenario batch stops its
workers and keeps its finished tasks for ``--resume``; every command ends with exit code 130
and one line that names only what exists.
"""

from __future__ import annotations

import argparse
import logging
import sys
from collections.abc import Sequence
from types import ModuleType

from match.errors import MatchError
from scenarios.cli import (
    bench,
    calibrate_colors,
    drill,
    localize,
    match,
    perception,
    replay,
    rerun,
    scenario,
    tournament,
    world_demo,
)
from scenarios.cli.arguments import (
    EXIT_FAILED,
    EXIT_INTERRUPTED,
    EXIT_OK,
    EXIT_USAGE,
    Handler,
    Parser,
    add_subparser,
    one_line,
    verbose_flag,
)
from scenarios.common.termination import terminate_as_interrupt
from world.errors import WorldError

__all__ = ["EXIT_FAILED", "EXIT_INTERRUPTED", "EXIT_OK", "EXIT_USAGE", "SUBCOMMANDS", "build_parser", "main"]

SUBCOMMANDS: tuple[ModuleType, ...] = (
    world_demo, bench, match, calibrate_colors, perception, localize, scenario, tournament, drill, replay, rerun,
)


def build_parser() -> argparse.ArgumentParser:
    parser = Parser(
        prog="robotstadium", description="Simulate RobotStadium robot-soccer matches in PyBullet."
    )
    verbose_flag(parser, False)
    subparsers = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for command in SUBCOMMANDS:
        sub = add_subparser(subparsers, command.NAME, help=command.HELP, description=command.DESCRIPTION)
        command.add_arguments(sub)
        sub.set_defaults(handler=command.run)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; return the exit code (a usage error raises ``SystemExit(2)`` while parsing)."""
    args = build_parser().parse_args(argv)
    logging.basicConfig(
        level=logging.DEBUG if args.verbose else logging.INFO,
        format="%(levelname)s %(name)s: %(message)s",
        stream=sys.stderr,
    )
    handler: Handler = args.handler
    try:
        with terminate_as_interrupt():  # ``kill PID`` stops a command as Ctrl-C does
            return handler(args)
    except KeyboardInterrupt:  # one its command did not handle itself: nothing it names was finished
        print(f"robotstadium {args.command}: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except (WorldError, MatchError, ValueError) as error:
        print(f"robotstadium {args.command}: error: {one_line(error)}", file=sys.stderr)
        return EXIT_USAGE
    except OSError as error:
        print(f"robotstadium {args.command}: error: {one_line(error)}", file=sys.stderr)
        return EXIT_FAILED
