"""``robotstadium match``: a full match, headless, between policies chosen by name."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import TYPE_CHECKING

from agents.policies import DEFAULT_POLICY
from match.protocol.ids import MAX_PLAYERS_PER_TEAM
from scenarios.cli.arguments import (
    EXIT_INTERRUPTED,
    EXIT_OK,
    HALF_SECONDS_MAX,
    HALF_SECONDS_MIN,
    add_camera_profile,
    add_controller_arguments,
    add_out_dir,
    add_seed,
    controller_limits,
    half_seconds,
    int_in,
    policy_name,
    policy_override,
    robot_or_all,
)

if TYPE_CHECKING:
    from match.runner import MatchSummary

NAME = "match"
HELP = "run a full match headless between policies chosen by name"
DESCRIPTION = (
    "Play a match (two halves, kick-offs, goals, throw-ins, half-time, penalty shoot-out on a tie) "
    "and write summary.json, events.jsonl and match_log.npz into --out, then the replay page replay.html "
    "and the figures traces.png and localization.png (--no-replay: not those); --video ROBOT also writes "
    "video_ROBOT.mp4, that robot's camera with its vision overlay and a field map. A policy is a built-in name "
    "(team, its variants, scripted, scan_localize, stand: see the README) or a class of yours as "
    "package.module:ClassName; a team agent with other parameters as team:FILE.toml (agents/team/params.toml)."
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--home", type=policy_name, default=DEFAULT_POLICY, metavar="POLICY",
                        help=f"the home team's policy (default {DEFAULT_POLICY})")
    parser.add_argument("--away", type=policy_name, default=DEFAULT_POLICY, metavar="POLICY",
                        help=f"the away team's policy (default {DEFAULT_POLICY})")
    parser.add_argument("--policy", type=policy_override, action="append", default=[], metavar="AGENT=POLICY",
                        help="one robot's policy, e.g. home_2=mypkg.mod:Striker (repeatable)")
    players = int_in(1, MAX_PLAYERS_PER_TEAM)
    parser.add_argument("--home-players", type=players, default=MAX_PLAYERS_PER_TEAM, metavar="N",
                        help=f"home players, 1-{MAX_PLAYERS_PER_TEAM} (default {MAX_PLAYERS_PER_TEAM})")
    parser.add_argument("--away-players", type=players, default=MAX_PLAYERS_PER_TEAM, metavar="N",
                        help=f"away players, 1-{MAX_PLAYERS_PER_TEAM} (default {MAX_PLAYERS_PER_TEAM})")
    parser.add_argument("--half-seconds", type=half_seconds, default=600.0, metavar="S",
                        help="playing time of each half in simulated seconds, "
                             f"{HALF_SECONDS_MIN:g}-{HALF_SECONDS_MAX:g} (default 600)")
    add_seed(parser, "match seed")
    add_out_dir(parser, "out/match")
    parser.add_argument("--no-progress", dest="progress", action="store_false", help="no progress bar")
    parser.add_argument("--shootout", action=argparse.BooleanOptionalAction, default=True,
                        help="decide a tie by penalty shoot-out (default: yes)")
    parser.add_argument("--no-replay", dest="replay", action="store_false",
                        help="do not write the replay page and figures (replay.html, traces.png, localization.png)")
    parser.add_argument("--video", type=robot_or_all, action="append", default=[], metavar="ROBOT",
                        help="write video_ROBOT.mp4: the robot's camera frames beside its vision debug overlay and a "
                             "field map with its estimate and true pose (repeatable; all: every robot)")
    parser.add_argument("--state-hashes", action="store_true",
                        help="also write state_hashes.txt: each step's number and a hash of the world's state, to "
                             "find the first step at which two runs of the same match differ (on two machines)")
    add_camera_profile(parser)
    add_controller_arguments(parser)


def run(args: argparse.Namespace) -> int:
    from scenarios.matches.play import Lineup, run_lineup_match
    from world.camera_profiles import DEFAULT_CAMERA_PROFILE

    robots = [robot for robot, _ in args.policy]
    twice = sorted({robot for robot in robots if robots.count(robot) > 1})
    if twice:
        raise ValueError(f"--policy names {', '.join(twice)} more than once")
    lineup = Lineup(args.home, args.away, dict(args.policy))
    started = time.time()
    try:
        summary = run_lineup_match(
            args.out, lineup, home=args.home_players, away=args.away_players, half_seconds=args.half_seconds,
            seed=args.seed, shootout=args.shootout, progress=args.progress, videos=args.video,
            controllers=controller_limits(args), state_hashes=args.state_hashes,
            camera_profile=args.camera_profile or DEFAULT_CAMERA_PROFILE,
        )
    except KeyboardInterrupt:
        written = Path(args.out) / "summary.json"
        if written.exists() and written.stat().st_mtime >= started:
            print(f"robotstadium match: interrupted; what was played is in {args.out} "
                  "(summary.json: completed false)", file=sys.stderr)
        else:
            print("robotstadium match: interrupted before the match began; nothing was written", file=sys.stderr)
        return EXIT_INTERRUPTED
    try:
        _report(args, summary)
    except KeyboardInterrupt:  # the match is played and recorded: only the lines below or its page are missing
        page = f" (robotstadium replay {args.out} writes its replay page)" if args.replay else ""
        print(f"robotstadium match: interrupted after the match; the match is in {args.out}{page}", file=sys.stderr)
        return EXIT_INTERRUPTED
    return EXIT_OK


def _report(args: argparse.Namespace, summary: MatchSummary) -> None:
    """Print the result and the files written, and write the replay page unless ``--no-replay``."""
    from match.protocol.ids import roster
    from match.runner import STATE_HASHES
    from scenarios.matches.play import video_robots
    from scenarios.matches.video import video_name
    from scenarios.replay.data import teams_by_policy

    score = summary.score
    teams = teams_by_policy({"played_by": summary.played_by})  # "team vs scripted"
    result = f"{teams + ': ' if teams else ''}home {score['home']} - {score['away']} away"
    if summary.shootout:
        result += f" (shoot-out {summary.shootout['home']}-{summary.shootout['away']})"
    print(f"{result}; {summary.sim_seconds:.0f} s simulated in {summary.wall_seconds:.0f} s "
          f"({summary.real_time_factor:.2f}x real time)")
    print(Path(args.out) / "summary.json")
    if args.state_hashes:
        print(Path(args.out) / STATE_HASHES)
    for agent in video_robots(args.video, roster(args.home_players, args.away_players)):
        if (Path(args.out) / video_name(agent)).exists():  # none for a robot whose camera gave no frame
            print(Path(args.out) / video_name(agent))
    if args.replay:
        from scenarios.replay import write_replay

        for path in write_replay(args.out, plots=True):
            print(path)
