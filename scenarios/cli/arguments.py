"""What the subcommands share: exit codes, argparse types and the common arguments."""

from __future__ import annotations

import argparse
import math
import os
import sys
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import NoReturn

from scenarios.cli.outputs import output_problem
from scenarios.common.limits import HALF_SECONDS_MAX, HALF_SECONDS_MIN
from scenarios.common.termination import EXIT_INTERRUPTED

EXIT_OK = 0
EXIT_FAILED = 1
EXIT_USAGE = 2
# EXIT_INTERRUPTED (130: a Ctrl-C or a SIGTERM) is scenarios.common.termination's

Handler = Callable[[argparse.Namespace], int]


# ---- bounds shared by several commands --------------------------------------------------------

SEED_MAX = 2**32 - 1  # seeds 0 .. 2**32-1, as wide as the seeds a tournament draws for its matches
MAX_WORKERS = 64  # local processes (each holds a world of its own) or Ray CPUs


class Parser(argparse.ArgumentParser):
    """An argument parser whose usage errors are one line on stderr, ``PROG: error: MESSAGE``, and exit code 2."""

    def error(self, message: str) -> NoReturn:
        self.exit(EXIT_USAGE, f"{self.prog}: error: {one_line(message)}\n")


def one_line(text: object) -> str:
    """``text`` on one line: every run of whitespace, line breaks too, one space."""
    return " ".join(str(text).split())


# ---- argument types ------------------------------------------------------------------------


def _got(text: str, number: bool = False) -> str:
    """How a message shows the text given: as typed for a number, quoted otherwise, at most 40 characters."""
    shown = text.strip() if number else text
    shown = shown if len(shown) <= 40 else shown[:37] + "..."
    return shown if number else repr(shown)


def int_in(low: int, high: int) -> Callable[[str], int]:
    """An argparse type: an integer in ``[low, high]``."""

    def parse(text: str) -> int:
        expected = f"expected an integer in [{low}, {high}]"
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{expected}, got {_got(text)}") from None
        if not low <= value <= high:
            raise argparse.ArgumentTypeError(f"{expected}, got {_got(text, number=True)}")
        return value

    return parse


def number_in(low: float, high: float) -> Callable[[str], float]:
    """An argparse type: a finite number in ``[low, high]``."""

    def parse(text: str) -> float:
        expected = f"expected a number in [{low:g}, {high:g}]"
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{expected}, got {_got(text)}") from None
        if not (math.isfinite(value) and low <= value <= high):
            raise argparse.ArgumentTypeError(f"{expected}, got {_got(text, number=True)}")
        return value

    return parse


seed = int_in(0, SEED_MAX)
half_seconds = number_in(HALF_SECONDS_MIN, HALF_SECONDS_MAX)
workers = int_in(1, MAX_WORKERS)


def input_path(text: str) -> Path:
    """argparse type: a path to read, not empty (an empty path would read the current directory)."""
    if not text.strip() or "\0" in text:
        raise argparse.ArgumentTypeError(f"expected a path, got {_got(text)}")
    return Path(text)


def output_dir(text: str) -> Path:
    """argparse type: a directory to write into, existing and writable or one that can be created
    (see :func:`~scenarios.cli.outputs.output_problem`); nothing is created here."""
    problem = output_problem(text, directory=True)
    if problem is not None:
        raise argparse.ArgumentTypeError(problem)
    return Path(text)


def output_file(text: str) -> Path:
    """argparse type: a file to write, a writable one or one that can be created in a directory that can."""
    problem = output_problem(text, directory=False)
    if problem is not None:
        raise argparse.ArgumentTypeError(problem)
    return Path(text)


def name_list(choices: Callable[[], Iterable[str]]) -> Callable[[str], tuple[str, ...]]:
    """An argument type: comma-separated distinct names, each one of ``choices()`` (loaded when parsing)."""

    def parse(text: str) -> tuple[str, ...]:
        allowed = sorted(choices())
        names = tuple(name.strip() for name in text.split(",") if name.strip())
        if not names or any(n not in allowed for n in names) or len(set(names)) != len(names):
            raise argparse.ArgumentTypeError(f"expected distinct names among {allowed}, got {_got(text)}")
        return names

    return parse


def policy_name(text: str) -> str:
    """argparse type: a built-in policy name or an importable ``package.module:ClassName``.

    As with ``python -m``, modules in the current directory can be named.
    """
    from agents.policies import policy_factory

    if os.getcwd() not in sys.path:
        sys.path.insert(0, os.getcwd())
    try:
        policy_factory(text)
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error)) from None
    return text


def policy_override(text: str) -> tuple[str, str]:
    """argparse type: ``AGENT=POLICY``, e.g. ``home_2=mypkg.mod:Striker``."""
    from match.protocol.ids import AgentId

    agent, sep, name = text.partition("=")
    try:
        agent_id = AgentId.parse(agent.strip())
    except ValueError as error:
        raise argparse.ArgumentTypeError(f"expected AGENT=POLICY; {error}") from None
    if not sep:
        raise argparse.ArgumentTypeError(f"expected AGENT=POLICY, e.g. home_2=scripted; got {_got(text)}")
    return str(agent_id), policy_name(name.strip())


def robot_or_all(text: str) -> str:
    """argparse type: an agent id (``home_0`` .. ``away_3``) or ``all``."""
    from match.protocol.ids import AgentId

    if text.strip() == "all":
        return "all"
    try:
        return str(AgentId.parse(text.strip()))
    except ValueError as error:
        raise argparse.ArgumentTypeError(f"expected a robot (home_0 .. away_3) or all; {error}") from None


def localizer_names() -> Iterable[str]:
    """The localization methods' names (loaded when an argument names them)."""
    from agents.localization import LOCALIZERS

    return LOCALIZERS


def camera_model_names() -> Iterable[str]:
    """The camera models' names (loaded when an argument names them)."""
    from agents.vision.camera_models import CAMERA_MODELS

    return CAMERA_MODELS


# ---- parsers and common arguments ----------------------------------------------------------


def verbose_flag(parser: argparse.ArgumentParser, default: object) -> None:
    parser.add_argument("-v", "--verbose", action="store_true", default=default, help="log debug messages")


def add_subparser(subparsers: argparse._SubParsersAction, name: str, **kwargs) -> argparse.ArgumentParser:
    """A subcommand's parser; it accepts ``--verbose`` after the subcommand name too."""
    common = argparse.ArgumentParser(add_help=False)
    verbose_flag(common, argparse.SUPPRESS)  # do not overwrite a --verbose given before
    return subparsers.add_parser(name, parents=[common], **kwargs)


def add_out_dir(parser: argparse.ArgumentParser, default: str | None = None) -> None:
    """``--out DIR``, the output directory (checked when parsing, the default too): required without a ``default``."""
    text = "output directory, created if missing; refused before anything runs if it cannot be written"
    if default is None:
        parser.add_argument("--out", type=output_dir, required=True, metavar="DIR", help=text)
    else:
        parser.add_argument("--out", type=output_dir, default=default, metavar="DIR",
                            help=f"{text} (default {default})")


def add_seed(parser: argparse.ArgumentParser, text: str, default: int | None = 0, default_text: str = "") -> None:
    """``--seed N``: an integer 0 .. :data:`SEED_MAX`; ``text`` says what it seeds."""
    shown = default_text or str(default)
    parser.add_argument("--seed", type=seed, default=default, metavar="N",
                        help=f"{text}, 0-{SEED_MAX} (default {shown})")


def camera_profile_name(text: str) -> str:
    """An argparse type: the name of a camera profile (:data:`world.camera_profiles.CAMERA_PROFILES`)."""
    from world.camera_profiles import CAMERA_PROFILES

    if text not in CAMERA_PROFILES:
        raise argparse.ArgumentTypeError(f"expected one of {', '.join(CAMERA_PROFILES)}, got {_got(text)}")
    return text


def add_camera_profile(parser: argparse.ArgumentParser, default_text: str = "") -> None:
    """``--camera-profile NAME``: what the robots' cameras do to the rendered frames (None when not given)."""
    from world.camera_profiles import DEFAULT_CAMERA_PROFILE

    parser.add_argument("--camera-profile", type=camera_profile_name, default=None, metavar="NAME",
                        help="the cameras' image profile: clean (the rendered frames), robotstadium (the thesis' "
                             "simulator: faint noise, motion blur) or nao (a Nao V3/V4 camera: sensor noise, YUV422, "
                             "vignetting, exposure and colour cast, blur, rolling shutter, lost frames); "
                             f"default {default_text or DEFAULT_CAMERA_PROFILE}")


def add_batch_arguments(parser: argparse.ArgumentParser, unit: str) -> None:
    """``--workers``, ``--backend``, ``--ray-address`` and ``--resume`` of a batch of ``unit`` (e.g. "runs")."""
    parser.add_argument("--workers", type=workers, default=None, metavar="W",
                        help=f"{unit} at once, in local processes or Ray CPUs, 1-{MAX_WORKERS} (default: all cores)")
    parser.add_argument("--backend", choices=("local", "ray"), default="local",
                        help="local processes (default) or Ray tasks (needs the ray extra)")
    parser.add_argument("--ray-address", default=None, metavar="ADDRESS",
                        help="Ray cluster to join (default: start a local Ray instance)")
    parser.add_argument("--resume", action="store_true", help=f"keep the finished {unit} in --out and run the rest")


def batch_options(args: argparse.Namespace):
    """The :class:`~scenarios.common.batch.BatchOptions` of :func:`add_batch_arguments` and ``--no-progress``."""
    from scenarios.common.batch import BatchOptions, default_workers

    workers = args.workers if args.workers is not None else default_workers()
    return BatchOptions(workers, args.backend, args.ray_address, args.resume, args.progress)


def add_controller_arguments(parser: argparse.ArgumentParser) -> None:
    """``--in-process``, ``--controller-per``, ``--step-budget`` and ``--controller-memory`` (match.controllers)."""
    from match.controllers import GROUPS, LIMIT_BOUNDS, ControllerLimits

    default = ControllerLimits()
    budget, memory = LIMIT_BOUNDS["step_budget_s"], LIMIT_BOUNDS["memory_mb"]
    parser.add_argument("--in-process", dest="controllers", action="store_false",
                        help="run the policies in the simulator's process (for debugging; default: controller "
                             "processes, held to a step budget and a memory limit)")
    parser.add_argument("--controller-per", choices=GROUPS, default=default.group,
                        help=f"one controller process per robot or per team (default {default.group})")
    parser.add_argument("--step-budget", type=number_in(*budget), default=default.step_budget_s, metavar="S",
                        help=f"processor seconds a controller may spend on one step before its robots stand for "
                             f"it (one kept waiting for the processor by other work is waited for), "
                             f"{budget[0]:g}-{budget[1]:g} (default {default.step_budget_s:g})")
    parser.add_argument("--controller-memory", type=number_in(*memory), default=default.memory_mb, metavar="MB",
                        help=f"resident memory (MiB) past which a controller process is restarted, "
                             f"{memory[0]:g}-{memory[1]:g} (default {default.memory_mb:g})")


def controller_limits(args: argparse.Namespace):
    """The :class:`~match.controllers.ControllerLimits` of :func:`add_controller_arguments`, None: in process."""
    from match.controllers import ControllerLimits

    if not args.controllers:
        return None
    return ControllerLimits(step_budget_s=args.step_budget, memory_mb=args.controller_memory,
                            group=args.controller_per)


def add_no_progress(parser: argparse.ArgumentParser) -> None:
    """``--no-progress``: ``args.progress`` is False."""
    parser.add_argument("--no-progress", dest="progress", action="store_false", help="no progress bar")
