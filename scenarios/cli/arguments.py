"""What the subcommands share: exit codes, argparse types and the common arguments."""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Callable, Iterable
from pathlib import Path

EXIT_OK = 0
EXIT_FAILED = 1
EXIT_USAGE = 2
EXIT_INTERRUPTED = 130  # Ctrl-C, as shells report it

Handler = Callable[[argparse.Namespace], int]


# ---- argument types ------------------------------------------------------------------------


def positive_int(text: str) -> int:
    """argparse type: an integer >= 1."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {value}")
    return value


def positive_float(text: str) -> float:
    """argparse type: a finite number > 0."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive number, got {text!r}") from None
    if not (value > 0 and value < float("inf")):
        raise argparse.ArgumentTypeError(f"expected a positive number, got {value}")
    return value


def name_list(choices: Callable[[], Iterable[str]]) -> Callable[[str], tuple[str, ...]]:
    """An argument type: comma-separated distinct names, each one of ``choices()`` (loaded when parsing)."""

    def parse(text: str) -> tuple[str, ...]:
        allowed = sorted(choices())
        names = tuple(name.strip() for name in text.split(",") if name.strip())
        if not names or any(n not in allowed for n in names) or len(set(names)) != len(names):
            raise argparse.ArgumentTypeError(f"expected distinct names among {allowed}, got {text!r}")
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
        raise argparse.ArgumentTypeError(f"expected AGENT=POLICY, e.g. home_2=scripted; got {text!r}")
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


def add_out_dir(parser: argparse.ArgumentParser, default: Path | None = None) -> None:
    """``--out DIR``, the output directory: required without a ``default``."""
    if default is None:
        parser.add_argument("--out", type=Path, required=True, metavar="DIR", help="output directory (created)")
    else:
        parser.add_argument("--out", type=Path, default=default, metavar="DIR", help=f"output directory (default {default})")


def add_batch_arguments(parser: argparse.ArgumentParser, unit: str) -> None:
    """``--workers``, ``--backend``, ``--ray-address`` and ``--resume`` of a batch of ``unit`` (e.g. "runs")."""
    parser.add_argument("--workers", type=int, default=None, metavar="W",
                        help=f"{unit} at once, in local processes or Ray CPUs (default: all cores)")
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
    from match.controllers import GROUPS, ControllerLimits

    default = ControllerLimits()
    parser.add_argument("--in-process", dest="controllers", action="store_false",
                        help="run the policies in the simulator's process (for debugging; default: controller "
                             "processes, held to a step budget and a memory limit)")
    parser.add_argument("--controller-per", choices=GROUPS, default=default.group,
                        help=f"one controller process per robot or per team (default {default.group})")
    parser.add_argument("--step-budget", type=positive_float, default=default.step_budget_s, metavar="S",
                        help=f"wall seconds a controller has to answer one step before its robots stand for it "
                             f"(default {default.step_budget_s:g})")
    parser.add_argument("--controller-memory", type=positive_float, default=default.memory_mb, metavar="MB",
                        help=f"resident memory (MiB) past which a controller process is restarted "
                             f"(default {default.memory_mb:g})")


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
