"""``robotstadium tournament``: many matches between policies, their statistics and a verdict."""

from __future__ import annotations

import argparse
import logging
import sys
from collections.abc import Iterable
from pathlib import Path

from scenarios.cli.arguments import (
    EXIT_INTERRUPTED,
    EXIT_OK,
    HALF_SECONDS_MAX,
    HALF_SECONDS_MIN,
    add_batch_arguments,
    add_camera_profile,
    add_controller_arguments,
    add_no_progress,
    add_out_dir,
    add_seed,
    batch_options,
    controller_limits,
    half_seconds,
    int_in,
    number_in,
    policy_name,
)
from scenarios.tournament.settings import MAX_PLAYERS

NAME = "tournament"
HELP = "play many matches between policies and say, with 95%% intervals, which is better"
DESCRIPTION = (
    "Play --matches matches between two policies (the same name twice: self-play), or per pair of a round robin "
    "between three or more, each pair half its matches with each policy at home; write matches/NNN/ (each match's "
    "outputs and its replay page replay.html, --no-replay: not that), results.csv, summary.json, table.md, "
    "standings.png and, for three or more policies, ratings.png into --out; --plots-for N also writes traces.png and "
    "localization.png of match N. A policy is a built-in name (team and its variants, scripted, scan_localize, "
    "stand) or package.module:ClassName; team:FILE.toml: a team agent with the parameters of FILE (self-play of two "
    "parameter sets: team team:FILE.toml). Finished matches are kept; --resume continues an interrupted tournament."
)

log = logging.getLogger(__name__)

MAX_MATCHES = 1_000  # per pair; a 4 v 4 match of 600 s halves takes minutes of wall time
MAX_PAUSE_S = 60.0


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("policies", nargs="+", metavar="POLICY", help="two or more policies")
    parser.add_argument("--matches", type=int_in(1, MAX_MATCHES), default=10, metavar="N",
                        help=f"matches per pair, 1-{MAX_MATCHES} (default 10), half with each policy at home")
    parser.add_argument("--half-seconds", type=half_seconds, default=600.0, metavar="S",
                        help="playing time of each half in simulated seconds, "
                             f"{HALF_SECONDS_MIN:g}-{HALF_SECONDS_MAX:g} (default 600)")
    parser.add_argument("--players", type=int_in(1, MAX_PLAYERS), default=MAX_PLAYERS, metavar="K",
                        help=f"robots per side, 1-{MAX_PLAYERS} (default {MAX_PLAYERS})")
    add_seed(parser, "tournament seed; each match's is drawn from it")
    add_batch_arguments(parser, "matches")
    add_out_dir(parser, "out/tournament")
    add_no_progress(parser)
    parser.add_argument("--shootout", action=argparse.BooleanOptionalAction, default=True,
                        help="decide a tie by penalty shoot-out (default: yes)")
    parser.add_argument("--no-replay", dest="replay", action="store_false",
                        help="do not write each match's replay page (matches/NNN/replay.html)")
    parser.add_argument("--plots-for", type=int, action="append", default=[], metavar="N",
                        help="after the tournament, write traces.png and localization.png of match N (as in "
                             "matches/NNN, 0 to the number of matches - 1) into its directory (repeatable)")
    # testing: shorter INITIAL, READY and SET pauses, "I,R,S" seconds, each 0-60 (part of the settings)
    parser.add_argument("--pauses", type=_pauses, default=None, help=argparse.SUPPRESS)
    add_controller_arguments(parser)
    add_camera_profile(parser)


def run(args: argparse.Namespace) -> int:
    from scenarios.replay import write_replay
    from scenarios.tournament.report import table_markdown
    from scenarios.tournament.run import check_match_index, run_tournament
    from scenarios.tournament.settings import TournamentError, TournamentSettings
    from world.camera_profiles import DEFAULT_CAMERA_PROFILE

    for name in args.policies:  # as the match command names them (modules in the current directory too)
        try:
            policy_name(name)
        except argparse.ArgumentTypeError as error:
            raise TournamentError(f"POLICY: {error}") from None
    options = batch_options(args)
    settings = TournamentSettings(tuple(args.policies), args.matches, args.half_seconds, args.players, args.seed,
                                  args.shootout, args.pauses, controller_limits(args),
                                  args.camera_profile or DEFAULT_CAMERA_PROFILE)
    plots_for = sorted({check_match_index(settings, index, "--plots-for") for index in args.plots_for})
    try:
        report = run_tournament(settings, args.out, options, page=write_replay if args.replay else None)
    except KeyboardInterrupt:
        print(f"robotstadium tournament: interrupted; finished matches are kept in {args.out}: "
              "run again with --resume to continue", file=sys.stderr)
        return EXIT_INTERRUPTED
    print(table_markdown(report))
    played = len(report.records) - len(report.failed)
    print(f"{played} matches played, {len(report.failed)} failed, {report.wall_seconds:.0f} s wall; "
          f"written to {args.out}")
    for path in _write_plots(args.out, report.records, plots_for):
        print(path)
    return EXIT_OK


def _write_plots(out: Path, records: Iterable[dict], indices: Iterable[int]) -> list[Path]:
    """traces.png and localization.png of each match in ``indices``; a failed match has none (a warning)."""
    from scenarios.replay import ReplayInputError, write_replay
    from scenarios.tournament.run import match_dir

    status = {record["match"]: record["status"] for record in records}
    written: list[Path] = []
    for index in indices:
        if status[index] != "ok":
            log.warning("--plots-for %d: match %d failed, it has no figures", index, index)
            continue
        try:
            written += write_replay(match_dir(out, index), write_page=False, plots=True)
        except ReplayInputError as error:
            log.warning("--plots-for %d: no figures: %s", index, error)
    return written


def _pauses(text: str) -> tuple[float, ...]:
    """argparse type of ``--pauses``: three numbers of seconds in [0, :data:`MAX_PAUSE_S`], e.g. 0.2,0.4,0.2."""
    parts = text.split(",")
    if len(parts) != 3:
        raise argparse.ArgumentTypeError(f"expected three numbers of seconds, e.g. 0.2,0.4,0.2; got {text[:40]!r}")
    return tuple(number_in(0.0, MAX_PAUSE_S)(part) for part in parts)
