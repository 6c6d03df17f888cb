"""``robotstadium rerun``: play a recorded match again from its summary and compare the two."""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys
from pathlib import Path

from scenarios.cli.arguments import EXIT_FAILED, EXIT_OK, add_no_progress, add_out_dir, input_path

NAME = "rerun"
HELP = "play a recorded match again from its summary.json and say whether it came out the same"
DESCRIPTION = (
    "Read MATCH_DIR/summary.json (as robotstadium match or a tournament's matches/NNN write it), play the same "
    "match (policies, seeds, referee, controllers) into --out, compare its events.jsonl and match_log.npz with "
    "the original's and write --out/rerun.json. Refused (exit 2, nothing written) when the record would not play "
    "the same here: a policy file whose content changed, other package versions, other world settings; --force "
    "plays it anyway. Exit 0 when the two are the same byte for byte, 1 when they differ (the first difference "
    "is printed: the event line, or the log's step, robot and field)."
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("match_dir", type=input_path, metavar="MATCH_DIR", help="a match's output directory")
    add_out_dir(parser)
    parser.add_argument("--force", action="store_true",
                        help="play it even where the record says it would not play the same here")
    add_no_progress(parser)


def run(args: argparse.Namespace) -> int:
    from scenarios.matches.play import run_lineup_match
    from scenarios.matches.rerun import RerunError, compare_matches, import_roots, read_summary, rerun_plan

    original, out = Path(args.match_dir), Path(args.out)
    summary = read_summary(original)
    for root in import_roots(summary):  # users' modules are imported from where they played
        if str(root) not in sys.path:
            sys.path.insert(0, str(root))
    plan = rerun_plan(summary, force=args.force, origin=str(original / "summary.json"))
    if out.exists() and (out.resolve() == original.resolve() or (out / "summary.json").exists()):
        raise RerunError(f"--out {out}: holds a match already; give a new directory")
    run_lineup_match(out, plan.lineup, home=plan.home, away=plan.away, half_seconds=plan.half_seconds, seed=plan.seed,
                     shootout=plan.shootout, progress=args.progress, referee=plan.referee,
                     controllers=plan.controllers, camera_profile=plan.camera_profile)
    difference = compare_matches(original, out)
    record = {"original": str(original), "identical": difference is None, "forced_over": list(plan.warnings),
              "first_difference": dataclasses.asdict(difference) if difference else None}
    (out / "rerun.json").write_text(json.dumps(record, indent=2) + "\n", encoding="utf-8")
    if difference is None:
        print(f"identical: {out} played {original} again, byte for byte (events.jsonl, match_log.npz)")
        return EXIT_OK
    print(f"differs: {difference.text}")
    return EXIT_FAILED
