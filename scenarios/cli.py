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
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path

from scenarios.bench import DEFAULT_REPEATS, QUICK_REPEATS, format_table, run_bench
from scenarios.world_demo import run_world_demo
from match.errors import MatchError
from world.errors import WorldError

EXIT_OK = 0
EXIT_FAILED = 1
EXIT_USAGE = 2
EXIT_INTERRUPTED = 130  # Ctrl-C, as shells report it

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


def name_list(choices: Callable[[], Iterable[str]]) -> Callable[[str], tuple[str, ...]]:
    """An argument type: comma-separated distinct names, each one of ``choices()`` (loaded when parsing)."""

    def parse(text: str) -> tuple[str, ...]:
        allowed = sorted(choices())
        names = tuple(name.strip() for name in text.split(",") if name.strip())
        if not names or any(n not in allowed for n in names) or len(set(names)) != len(names):
            raise argparse.ArgumentTypeError(f"expected distinct names among {allowed}, got {text!r}")
        return names

    return parse


def _localizer_names() -> Iterable[str]:
    """The localization methods' names (loaded when an argument names them)."""
    from agents.localization import LOCALIZERS

    return LOCALIZERS


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


def _add_calibrate_colors(subparsers: argparse._SubParsersAction) -> None:
    import agents.vision
    from scenarios.color_calibration import DEFAULT_FRAMES

    default_out = Path(agents.vision.__file__).parent / "data" / "color_thresholds.json"
    parser = _add_subparser(
        subparsers,
        "calibrate-colors",
        help="fit the colour-segmentation thresholds on rendered frames",
        description="Render robot camera frames at seeded random poses, fit one RGB range per colour class "
        "from the pixels' true classes, print the per-class accuracy and write the thresholds to --out "
        "with a <name>_report.json beside them.",
    )
    parser.add_argument("--frames", type=positive_int, default=DEFAULT_FRAMES, metavar="N",
                        help=f"calibration frames (default {DEFAULT_FRAMES}); a third as many more are held out")
    parser.add_argument("--seed", type=int, default=0, help="seed of the poses (default 0)")
    parser.add_argument("--out", type=Path, default=default_out, metavar="PATH",
                        help="threshold file to write (default: the one shipped in agents/vision/data)")

    def handler(args: argparse.Namespace) -> int:
        from scenarios.color_calibration import calibrate_colors, format_scores, write_calibration

        result = calibrate_colors(args.frames, args.seed)
        print(format_scores(result))
        print(f"{result.frames} + {result.holdout_frames} held-out frames in {result.seconds:.1f} s")
        for path in write_calibration(result, args.out):
            print(path)
        return EXIT_OK

    parser.set_defaults(handler=handler)


def _add_perception(subparsers: argparse._SubParsersAction) -> None:
    from scenarios.perception_run import MAX_CROWD

    parser = _add_subparser(
        subparsers,
        "perception",
        help="score the vision pipeline's landmark percepts against ground truth",
        description="Place a robot at seeded random poses in the thesis' scan posture, render its camera "
        "(empty field, or with --crowd other robots around), run the vision pipeline with each camera model "
        "and score every percept against the true landmarks; write summary.json, table.md, detections.csv, "
        "visible.csv, errors_vs_distance.png, examples/ (frames with errors, truth marked) and overlays/ "
        "(the same frames as the pipeline saw them) into --out.",
    )

    def crowd_count(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected an integer 0-{MAX_CROWD}, got {text!r}") from None
        if not 0 <= value <= MAX_CROWD:
            raise argparse.ArgumentTypeError(f"expected an integer 0-{MAX_CROWD}, got {value}")
        return value

    parser.add_argument("--frames", type=positive_int, required=True, metavar="N", help="frames to render")
    parser.add_argument("--seed", type=int, default=0, help="seed of the poses (default 0)")
    parser.add_argument("--out", type=Path, required=True, metavar="DIR", help="output directory (created)")
    parser.add_argument("--crowd", type=crowd_count, default=0, metavar="K",
                        help=f"other robots standing on the field, 0-{MAX_CROWD} (default 0)")
    def camera_models() -> Iterable[str]:
        from agents.vision.camera_models import CAMERA_MODELS

        return CAMERA_MODELS

    parser.add_argument("--models", type=name_list(camera_models), default=("exact", "thesis"), metavar="M1,M2",
                        help="camera models to score, comma-separated (default exact,thesis)")
    parser.add_argument("--max-range-m", type=positive_float, default=4.0, metavar="M",
                        help="landmarks farther than this are not expected and their errors not counted (default 4)")
    parser.add_argument("--examples", type=int, default=6, metavar="N",
                        help="annotated PNGs of frames with a false positive or a miss (default 6)")
    parser.add_argument("--no-progress", dest="progress", action="store_false", help="no progress bar")

    def handler(args: argparse.Namespace) -> int:
        from scenarios.perception_run import PerceptionConfig, run_perception

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

    parser.set_defaults(handler=handler)


def _add_localize(subparsers: argparse._SubParsersAction) -> None:
    parser = _add_subparser(
        subparsers,
        "localize",
        help="scenario 1 of thesis chapter 6: one robot alone, move, scan, localize with every method",
        description="One robot alone on the field repeats a random motion, a five-frame head scan and a "
        "localization with each method side by side on the same percepts; each estimate is compared with "
        "the robot's true pose. Prints mean and median errors and the median localize() time per method.",
    )
    parser.add_argument("--samples", type=positive_int, default=50, metavar="N", help="localizations (default 50)")
    parser.add_argument("--seed", type=int, default=0, help="seed (default 0)")
    parser.add_argument("--methods", type=name_list(_localizer_names), default=("thesis", "particle", "hybrid", "odometry"),
                        metavar="M1,M2", help="localization methods, comma-separated (default thesis,particle,hybrid,odometry)")

    def handler(args: argparse.Namespace) -> int:
        from scenarios.localization_run import run_alone, summarize

        result = run_alone(args.samples, args.seed, args.methods)
        print("| method | samples | position mean / median (cm) | orientation mean / median (deg) | localize ms (median) |")
        print("|---|---|---|---|---|")
        for method, s in summarize(result.samples).items():
            print(f"| {method} | {s['with_estimate']}/{s['samples']} | {s['position_mean_cm']:.1f} / {s['position_median_cm']:.1f} "
                  f"| {s['orientation_mean_deg']:.1f} / {s['orientation_median_deg']:.1f} | {s['localize_ms_median']:.2f} |")
        print(f"{args.samples} samples, {result.sim_seconds:.0f} s simulated in {result.wall_seconds:.1f} s")
        return EXIT_OK

    parser.set_defaults(handler=handler)


def _add_scenario(subparsers: argparse._SubParsersAction) -> None:
    parser = _add_subparser(
        subparsers,
        "scenario",
        help="thesis chapter 6: run scenarios 1-3 (or a scenario file) and write their localization statistics",
        description="Run a scenario's independent runs (built-in 1, 2, 3, 'all', or a path to a TOML scenario "
        "file) and write results.csv, summary.json, table.md (thesis Tables 6.1/6.2 with the thesis' values), "
        "errors.png (thesis figure 6.15) and traces.png into --out. Every method of the scenario localizes on the "
        "same percepts and motions. Finished runs are kept in --out/runs; --resume continues an interrupted batch.",
    )
    parser.add_argument("scenarios", nargs="+", metavar="SCENARIO", help="1, 2, 3, all, or a scenario file")
    parser.add_argument("--samples", type=positive_int, default=None, metavar="N",
                        help="localization events per method (default: the scenario file's)")
    parser.add_argument("--seed", type=int, default=None, help="seed of the runs (default: the scenario file's)")
    parser.add_argument("--methods", type=name_list(_localizer_names), default=None, metavar="M1,M2",
                        help="localization methods, comma-separated (default: the scenario file's)")
    parser.add_argument("--workers", type=positive_int, default=None, metavar="W",
                        help="runs at once, in local processes or Ray CPUs (default: all cores)")
    parser.add_argument("--out", type=Path, default=Path("out/scenarios"), metavar="DIR",
                        help="output directory (default out/scenarios)")
    parser.add_argument("--backend", choices=("local", "ray"), default="local",
                        help="local processes (default) or Ray tasks (needs the ray extra)")
    parser.add_argument("--ray-address", default=None, metavar="ADDRESS",
                        help="Ray cluster to join (default: start a local Ray instance)")
    parser.add_argument("--resume", action="store_true", help="keep the finished runs in --out and run the rest")
    parser.add_argument("--no-progress", dest="progress", action="store_false", help="no progress bar")

    def handler(args: argparse.Namespace) -> int:
        from scenarios.scenario_batch import BatchOptions, default_workers, run_named

        options = BatchOptions(args.workers or default_workers(), args.backend, args.ray_address, args.resume,
                               args.progress)
        try:
            reports = run_named(args.scenarios, args.out, options, samples=args.samples, seed=args.seed,
                                methods=args.methods)
        except KeyboardInterrupt:
            print(f"robotstadium scenario: interrupted; finished runs are kept in {args.out}: "
                  "run again with --resume to continue", file=sys.stderr)
            return EXIT_INTERRUPTED
        from scenarios.scenario_report import table_markdown

        print(table_markdown(reports))
        wall = sum(r.wall_seconds for r in reports)
        print(f"{sum(len(r.samples) for r in reports)} result rows, {wall:.0f} s wall; written to {args.out}")
        return EXIT_OK

    parser.set_defaults(handler=handler)


SUBCOMMANDS: tuple[Callable[[argparse._SubParsersAction], None], ...] = (
    _add_world_demo,
    _add_bench,
    _add_match,
    _add_calibrate_colors,
    _add_perception,
    _add_localize,
    _add_scenario,
)


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
