"""A match between policies chosen by name: the glue of ``robotstadium match`` and the benchmark.

A team plays one policy name (``--home``/``--away``); single robots can play another
(``--policy home_2=NAME``). Names are those of :mod:`agents.policies`: built in, or
``package.module:ClassName``. Every name is resolved before anything is built or written, and
so are the robots whose camera videos are asked for (``--video``, :mod:`scenarios.matches.video`).
"""

from __future__ import annotations

import functools
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path

from agents.policies import DEFAULT_POLICY, make_policy, policy_factory
from match.controllers import ControllerLimits, Controllers, InProcessControllers, ProcessControllers
from match.game import Match, MatchConfig
from match.protocol import Policy
from match.protocol.ids import AgentId, Side, roster
from match.runner import MatchSummary, run_match
from scenarios.matches.provenance import lineup_record
from world.camera_profiles import DEFAULT_CAMERA_PROFILE
from world.config import WorldConfig


ALL_ROBOTS = "all"  # --video all
PRELOAD = ("agents.policies",)  # what the controller processes' server imports once


class LineupError(ValueError):
    """A line-up that names an unknown policy, or a robot that is not on the field."""


@dataclass(frozen=True)
class Lineup:
    """Who plays: a policy name per team and per-robot overrides (agent id -> policy name)."""

    home: str = DEFAULT_POLICY
    away: str = DEFAULT_POLICY
    overrides: Mapping[str, str] = field(default_factory=dict)

    def policy_name(self, agent: AgentId) -> str:
        return self.overrides.get(str(agent), self.home if agent.side is Side.HOME else self.away)

    def check(self, agents: tuple[AgentId, ...]) -> None:
        """Every name resolves and every override names a robot on the field; else :class:`LineupError`."""
        on_field = {str(a) for a in agents}
        for robot in self.overrides:
            if robot not in on_field:
                raise LineupError(f"--policy {robot}=...: {robot} is not on the field; robots: {', '.join(sorted(on_field))}")
        for name in dict.fromkeys([self.home, self.away, *self.overrides.values()]):
            try:
                policy_factory(name)
            except ValueError as error:
                raise LineupError(str(error)) from None

    def policies(self, agents: tuple[AgentId, ...]) -> dict[str, Policy]:
        """A new policy for every robot."""
        self.check(agents)
        try:
            return {str(a): make_policy(self.policy_name(a)) for a in agents}
        except ValueError as error:
            raise LineupError(str(error)) from None

    def controllers(self, agents: tuple[AgentId, ...], limits: ControllerLimits | None) -> Controllers:
        """Every robot's policy in this process (``limits`` None), or in controller processes held to ``limits``."""
        if limits is None:
            return InProcessControllers(self.policies(agents))
        self.check(agents)
        factories = {str(a): functools.partial(make_policy, self.policy_name(a)) for a in agents}
        return ProcessControllers(factories, limits, preload=PRELOAD)


def video_robots(requested: Sequence[str], agents: tuple[AgentId, ...]) -> tuple[str, ...]:
    """The robots of ``requested`` (agent ids, or ``all``) in field order; :class:`LineupError`
    for a robot not on the field."""
    on_field = [str(a) for a in agents]
    for robot in requested:
        if robot != ALL_ROBOTS and robot not in on_field:
            raise LineupError(f"--video {robot}: {robot} is not on the field; robots: {', '.join(on_field)} "
                              f"(or {ALL_ROBOTS})")
    return tuple(a for a in on_field if ALL_ROBOTS in requested or a in requested)


def match_config(home: int = 4, away: int = 4, half_seconds: float = 600.0, shootout: bool = True,
                 referee: Mapping[str, object] | None = None,
                 camera_profile: str = DEFAULT_CAMERA_PROFILE) -> MatchConfig:
    """The match of ``home`` against ``away`` robots; ``referee``: other referee settings (RefereeConfig fields);
    ``camera_profile``: the cameras' image profile (:mod:`world.camera_profiles`)."""
    config = MatchConfig(home_players=home, away_players=away, world=WorldConfig(camera_profile=camera_profile))
    settings = {**(referee or {}), "half_seconds": half_seconds, "shootout": shootout}
    return replace(config, referee=replace(config.referee, **settings))


def run_lineup_match(
    out_dir: Path | None,
    lineup: Lineup = Lineup(),
    *,
    home: int = 4,
    away: int = 4,
    half_seconds: float = 600.0,
    seed: int = 0,
    shootout: bool = True,
    progress: bool = True,
    max_steps: int | None = None,
    referee: Mapping[str, object] | None = None,
    videos: Sequence[str] = (),
    controllers: ControllerLimits | None = None,
    state_hashes: bool = False,
    camera_profile: str = DEFAULT_CAMERA_PROFILE,
) -> MatchSummary:
    """Play one match of ``home`` against ``away`` robots with the line-up's policies.

    ``referee``: referee settings other than the half's length and the shoot-out (e.g. the
    tournament's shorter pauses before the kick-off, for tests). ``videos``: robots (agent
    ids, or ``all``) whose camera videos are written into ``out_dir`` (``video_<agent>.mp4``).
    ``controllers``: the limits of the policies' controller processes; None: the policies run in
    this process. ``state_hashes``: write each step's hash of the world's state (see
    :func:`~match.runner.run_match`). ``camera_profile``: the cameras' image profile.
    """
    config = match_config(home, away, half_seconds, shootout, referee, camera_profile)
    agents = roster(home, away)
    filmed = video_robots(videos, agents)  # refused here, before the world is built
    if filmed and out_dir is None:
        raise LineupError(f"--video {', '.join(videos)}: videos need an output directory")
    lineup.check(agents)  # refused here too
    played_by = lineup_record({str(a): lineup.policy_name(a) for a in agents}, controllers)
    match = Match(config)
    try:
        policies = lineup.controllers(agents, controllers)
        if not filmed:
            return run_match(config, policies, seed=seed, out_dir=out_dir, progress=progress, max_steps=max_steps,
                             match=match, state_hashes=state_hashes, played_by=played_by)
        from scenarios.matches.video import VideoRecorder  # only when a video is asked for (not in tournaments)

        assert out_dir is not None
        names = {str(a): lineup.policy_name(a) for a in agents}
        with VideoRecorder(out_dir, filmed, policies=names) as recorder:
            return run_match(config, policies, seed=seed, out_dir=out_dir, progress=progress, max_steps=max_steps,
                             match=match, observer=recorder, state_hashes=state_hashes, played_by=played_by)
    finally:
        match.close()
