"""Policies by name: the built-in ones, and the user's by import path ``package.module:ClassName``.

Every command and scenario file chooses policies through :func:`policy_factory`, so a bad
name is refused the same way everywhere, before anything runs, with the known names listed.
A team agent (``team`` or a variant) plays another parameter set as ``team:path/to/params.toml``
(:mod:`agents.team.params`; the file is read, and refused if bad, when the name is resolved).
A policy class is called with keyword options only (none for a plain choice by name) and
must provide ``reset(agent_id, seed)`` and ``act(observation)``
(:class:`match.protocol.policy.Policy`).
"""

from __future__ import annotations

import functools
import importlib
import re
from collections.abc import Callable
from typing import Any

from agents.behavior.policies.scan_localize import ScanLocalizeAgent
from agents.behavior.policies.scripted import ScriptedPlayer
from agents.behavior.policies.stand import StandPolicy
from agents.team.agent import TeamAgent
from agents.team.params import ParameterError, TeamParams
from match.protocol import Policy, policy_factory_problem

PolicyFactory = Callable[..., Policy]

# name -> (factory, one line for listings)
BUILTIN_POLICIES: dict[str, tuple[PolicyFactory, str]] = {
    "scripted": (ScriptedPlayer, "ball chaser by its camera and gyro; keeper as player 0; no localization"),
    "scan_localize": (ScanLocalizeAgent, "thesis chapter 6 cycle: a motion, a five-frame head scan, a localization"),
    "stand": (StandPolicy, "stands still, camera off"),
    "team": (TeamAgent, "the team agent: vision, localization (particle filter) while playing, roles over the radio"),
    "team-thesis": (functools.partial(TeamAgent, method="thesis"), "the team agent localizing with the thesis' method"),
    "team-particle": (functools.partial(TeamAgent, method="particle"), "the team agent with the particle filter"),
    "team-hybrid": (functools.partial(TeamAgent, method="hybrid"), "the team agent with the hybrid method"),
    "team-odometry": (functools.partial(TeamAgent, method="odometry"), "the team agent on odometry alone"),
    "team-blind": (functools.partial(TeamAgent, avoid_obstacles=False), "the team agent that does not avoid obstacles"),
}
DEFAULT_POLICY = "team"  # what a match plays unless told otherwise
PARAMETER_SUFFIX = ".toml"  # NAME:FILE.toml: the built-in NAME with the parameters of FILE
_IMPORT_PATH = re.compile(r"^[A-Za-z_][\w]*(\.[A-Za-z_][\w]*)*:[A-Za-z_][\w]*$")


class PolicyNameError(ValueError):
    """A policy name that is neither built in nor an importable ``package.module:ClassName``."""


def known_policies() -> str:
    """The built-in names and the import-path form, for messages."""
    return (", ".join(BUILTIN_POLICIES) + ", or package.module:ClassName"
            + f" (a team agent with other parameters: team:FILE{PARAMETER_SUFFIX})")


def policy_factory(name: str) -> PolicyFactory:
    """The class (or factory) a policy name stands for; :class:`PolicyNameError` if there is none."""
    if not isinstance(name, str):
        raise PolicyNameError(f"policy name {name!r}; expected a string: {known_policies()}")
    if name in BUILTIN_POLICIES:
        return BUILTIN_POLICIES[name][0]
    base, _, path = name.partition(":")
    if base in BUILTIN_POLICIES and path.endswith(PARAMETER_SUFFIX):
        return _with_parameters(name, base, path)
    if not _IMPORT_PATH.match(name):
        raise PolicyNameError(f"unknown policy {name!r}; expected {known_policies()}")
    module_name, _, attribute = name.partition(":")
    try:
        module = importlib.import_module(module_name)
    except ImportError as error:
        raise PolicyNameError(f"policy {name!r}: cannot import module {module_name!r} ({error})") from None
    factory = getattr(module, attribute, None)
    if factory is None or not callable(factory):
        raise PolicyNameError(f"policy {name!r}: module {module_name!r} has no class or function {attribute!r}")
    problem = policy_factory_problem(factory)
    if problem is not None:
        raise PolicyNameError(f"policy {name!r}: {attribute} {problem}; expected a class with reset(agent_id, seed) "
                              "and act(observation), or a function marked @match.protocol.policy_builder")
    return factory


def _with_parameters(name: str, base: str, path: str) -> PolicyFactory:
    """The built-in team agent ``base`` with the parameters of the TOML file at ``path``."""
    factory = BUILTIN_POLICIES[base][0]
    team = factory.func if isinstance(factory, functools.partial) else factory
    if team is not TeamAgent:
        raise PolicyNameError(f"policy {name!r}: {base} takes no parameter file (the team agents do)")
    try:
        params = TeamParams.load(path)
    except ParameterError as error:
        raise PolicyNameError(f"policy {name!r}: {error}") from error
    return functools.partial(factory, params=params)


def make_policy(name: str, **options: Any) -> Policy:
    """A new policy of that name, built with ``options`` (keyword arguments of its class)."""
    factory = policy_factory(name)
    try:
        policy = factory(**options)
    except TypeError as error:
        raise PolicyNameError(f"policy {name!r} cannot be built with options {sorted(options)}: {error}") from None
    if not isinstance(policy, Policy):
        raise PolicyNameError(f"policy {name!r} built a {type(policy).__name__}, which lacks reset() or act()")
    return policy
