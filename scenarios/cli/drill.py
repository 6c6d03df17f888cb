"""``robotstadium drill NAME``: one situation played many times, its outcomes with 95% intervals."""

from __future__ import annotations

import argparse
import sys
from typing import TYPE_CHECKING

from scenarios.cli.arguments import (
    EXIT_INTERRUPTED,
    EXIT_OK,
    add_batch_arguments,
    add_no_progress,
    add_out_dir,
    add_seed,
    add_subparser,
    batch_options,
    int_in,
    number_in,
    policy_name,
)

if TYPE_CHECKING:
    from scenarios.drills.base import Drill

NAME = "drill"
HELP = "play one situation many times (throw-in, shooting, duel, goal-line) and count its outcomes"
DESCRIPTION = (
    "Play --trials trials of a drill, each a short match cut off once its question is answered, trial k with the "
    "seed --seed + k, and write results.csv (a row per trial), summary.json (the drill's figures with 95% "
    "intervals, who played, the seeds, the command line and the versions) and table.md into --out. A policy is a "
    "built-in name (team and its variants, scripted, scan_localize, stand), team:FILE.toml or "
    "package.module:ClassName. Finished trials are kept; --resume continues an interrupted drill. "
    "robotstadium drill NAME --help tells a drill's roles and parameters."
)

def add_arguments(parser: argparse.ArgumentParser) -> None:
    from scenarios.drills.registry import DRILLS

    drills = parser.add_subparsers(dest="drill", required=True, metavar="DRILL",
                                   help=f"one of {', '.join(DRILLS)}")
    for drill in DRILLS.values():
        sub = add_subparser(drills, drill.NAME, help=_text(drill.HELP),
                            description=f"{drill.HELP[:1].upper()}{drill.HELP[1:]}. {DESCRIPTION}")
        _add_drill_arguments(sub, drill)
        sub.set_defaults(drill_class=drill)


def _add_drill_arguments(parser: argparse.ArgumentParser, drill: type[Drill]) -> None:
    """A flag per role and per parameter of ``drill``, then the trials, the seed, the batch and the output."""
    from agents.policies import DEFAULT_POLICY
    from scenarios.drills.base import flag_of
    from scenarios.drills.settings import DEFAULT_TRIALS, MAX_TRIALS

    for role in drill.ROLES:
        parser.add_argument(f"--{flag_of(role.name)}", dest=role.name, type=policy_name, default=DEFAULT_POLICY,
                            metavar="POLICY", help=f"{_text(role.help)} (default {DEFAULT_POLICY})")
    for name, bounds, default in drill.parameters():
        integer = isinstance(default, int)
        kind = int_in(int(bounds.low), int(bounds.high)) if integer else number_in(bounds.low, bounds.high)
        unit = f" {bounds.unit}" if bounds.unit else ""
        parser.add_argument(f"--{flag_of(name)}", dest=name, type=kind, default=default,
                            metavar=(bounds.unit or "N").upper(),
                            help=f"{_text(bounds.help)}, {bounds.low:g}-{bounds.high:g}{unit} (default {default:g})")
    parser.add_argument("--trials", type=int_in(1, MAX_TRIALS), default=DEFAULT_TRIALS, metavar="N",
                        help=f"trials, 1-{MAX_TRIALS} (default {DEFAULT_TRIALS})")
    add_seed(parser, "the first trial's seed; trial k has seed + k")
    add_batch_arguments(parser, "trials")
    add_out_dir(parser, f"out/drills/{drill.NAME}")
    add_no_progress(parser)


def run(args: argparse.Namespace) -> int:
    from scenarios.drills.report import table_markdown
    from scenarios.drills.run import run_drill
    from scenarios.drills.settings import DrillSettings

    drill_class = args.drill_class
    drill = drill_class(**{name: getattr(args, name) for name, _, _ in drill_class.parameters()})
    policies = tuple((role.name, getattr(args, role.name)) for role in drill_class.ROLES)
    settings = DrillSettings(drill, policies, args.trials, args.seed)
    try:
        report = run_drill(settings, args.out, batch_options(args))
    except KeyboardInterrupt:
        print(f"robotstadium drill: interrupted; finished trials are kept in {args.out}: "
              "run again with --resume to continue", file=sys.stderr)
        return EXIT_INTERRUPTED
    print(table_markdown(report))
    print(f"{len(report.played)} trials played, {len(report.failed)} failed, {report.wall_seconds:.0f} s wall; "
          f"written to {args.out}")
    return EXIT_OK


def _text(help_text: str) -> str:
    """A help text as argparse shows it: its ``%`` signs escaped."""
    return help_text.replace("%", "%%")
