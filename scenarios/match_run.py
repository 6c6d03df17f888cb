"""The ``robotstadium match`` command: a full match with the built-in team policies."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from agents.behavior.scripted import ScriptedPlayer
from match.game import Match, MatchConfig
from match.runner import MatchSummary, run_match


def default_policies(agent_names: tuple[str, ...] | list[str]) -> dict[str, ScriptedPlayer]:
    """The runner's default policy for every robot (the scripted ball chaser / goalkeeper)."""
    return {agent: ScriptedPlayer(agent) for agent in agent_names}


def match_config(home: int = 4, away: int = 4, half_seconds: float = 600.0, shootout: bool = True) -> MatchConfig:
    config = MatchConfig(home_players=home, away_players=away)
    return replace(config, referee=replace(config.referee, half_seconds=half_seconds, shootout=shootout))


def run_default_match(
    out_dir: Path,
    *,
    home: int = 4,
    away: int = 4,
    half_seconds: float = 600.0,
    seed: int = 0,
    shootout: bool = True,
    progress: bool = True,
    max_steps: int | None = None,
) -> MatchSummary:
    config = match_config(home, away, half_seconds, shootout)
    match = Match(config)
    try:
        return run_match(config, default_policies(match.agent_names), seed=seed, out_dir=out_dir, progress=progress,
                         max_steps=max_steps, match=match)
    finally:
        match.close()
