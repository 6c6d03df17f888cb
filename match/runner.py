"""The one game loop: play a :class:`~match.game.Match` with one policy per robot, and write what happened.

Every run goes through :func:`run_match`: full matches, tournaments, and the scenario runs
(refereed, or in the match's free play). Policies follow :class:`match.protocol.policy.Policy`:
:meth:`reset` with the robot's id and a seed before the first step, then ``act(observation)``
every control step; a :class:`~match.protocol.policy.PoseReporter` has its estimate logged
beside the truth, an :class:`~match.protocol.policy.AgentReporter` its report
(:mod:`match.reports`). A policy that raises, or returns an invalid action, does not end the
match: its robot stands still for that step and the fault is recorded; a report that raises
or does not fit is logged as nothing (NaN) with one warning per robot.

Whoever needs to watch the run (a localization-sample collector, a video writer) passes a
:class:`MatchObserver`: it sees the match after the policies decided each step, and can end
the run; an :class:`ObservationWatcher` also sees the observations the policies acted on.

Outputs in ``out_dir``: ``summary.json`` (with each team's match statistics, see
:mod:`match.statistics`), ``events.jsonl`` (one event per line) and ``match_log.npz`` (see
:mod:`match.log`).
"""

from __future__ import annotations

import json
import logging
import platform
import time
import traceback
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from importlib import metadata
from pathlib import Path
from typing import Any, Protocol, runtime_checkable

import numpy as np
from tqdm import tqdm

from match.events import EventKind, MatchEvent
from match.game import Match, MatchConfig
from match.log import MatchLog
from match.protocol.actions import Action, parse_action
from match.protocol.game_control import SecondaryState
from match.protocol.ids import Side
from match.protocol.policy import Policy
from match.reports import ReportReader
from match.statistics import TeamRadio, match_statistics

log = logging.getLogger(__name__)

FAULT_DETAILS_PER_AGENT = 20  # faults beyond this are counted, not described
PROGRESS_EVERY_STEPS = 25
POLICY_SEED_STREAM = 2  # Match.reset draws streams 0 (world) and 1 (radio) from the match seed


class MatchObserver(Protocol):
    """Watches a run step by step (ground truth allowed: it is not a policy)."""

    def decided(self, match: Match, actions: Mapping[str, Action | None]) -> None:
        """Called every step after all policies acted, before the step is played (None: a fault)."""

    def done(self, match: Match) -> bool:
        """Checked before every step: True ends the run there."""


@runtime_checkable
class ObservationWatcher(MatchObserver, Protocol):
    """An observer that also sees what the robots observed (a camera-video writer).

    Evaluation only: it must not hand anything back to a policy.
    """

    def observed(self, match: Match, observations: Mapping[str, Mapping[str, Any]]) -> None:
        """Called every step right after :meth:`decided`, with the observations (agent id -> the
        observation dict) the policies have just acted on; the world has not moved since they were taken."""


@dataclass
class FaultRecord:
    counts: dict[str, int] = field(default_factory=dict)
    details: list[dict] = field(default_factory=list)

    def add(self, agent: str, time_s: float, error: BaseException) -> MatchEvent | None:
        self.counts[agent] = self.counts.get(agent, 0) + 1
        if self.counts[agent] > FAULT_DETAILS_PER_AGENT:
            return None
        where = traceback.extract_tb(error.__traceback__)[-1] if error.__traceback__ else None
        detail = {
            "agent": agent,
            "time_s": round(time_s, 3),
            "error": f"{type(error).__name__}: {error}",
            "where": f"{where.filename}:{where.lineno}" if where else None,
        }
        self.details.append(detail)
        log.warning("policy of %s failed at %.2f s: %s", agent, time_s, detail["error"])
        return MatchEvent(time_s, EventKind.FAULT, detail)

    def to_json(self) -> dict:
        return {"total": sum(self.counts.values()), "by_agent": dict(self.counts), "details": self.details}


@dataclass(frozen=True)
class MatchSummary:
    score: dict[str, int]
    shootout: dict[str, int] | None
    winner: str | None
    seed: int
    sim_seconds: float
    wall_seconds: float
    steps: int
    events_count: int
    radio: dict
    faults: dict
    statistics: dict | None = None  # per team (match.statistics), when the match wrote its outputs

    @property
    def real_time_factor(self) -> float:
        return self.sim_seconds / self.wall_seconds if self.wall_seconds > 0 else float("inf")

    def to_json(self, config: MatchConfig) -> dict:
        return {
            "score": self.score,
            "shootout": self.shootout,
            "winner": self.winner,
            "seed": self.seed,
            "sim_seconds": round(self.sim_seconds, 3),
            "wall_seconds": round(self.wall_seconds, 3),
            "real_time_factor": round(self.real_time_factor, 3),
            "steps": self.steps,
            "events_count": self.events_count,
            "radio": self.radio,
            "faults": self.faults,
            "statistics": self.statistics,
            "config": {
                "home_players": config.home_players,
                "away_players": config.away_players,
                "half_seconds": config.referee.half_seconds,
                "shootout": config.referee.shootout,
            },
            "versions": package_versions(),
        }


def run_match(
    config: MatchConfig,
    policies: Mapping[str, Policy],
    *,
    seed: int = 0,
    out_dir: Path | None = None,
    progress: bool = True,
    max_steps: int | None = None,
    match: Match | None = None,
    observer: MatchObserver | None = None,
    policy_seeds: Mapping[str, int] | None = None,
) -> MatchSummary:
    """Play one match to the end (or ``max_steps``, or until ``observer`` is done) and write its outputs.

    ``policy_seeds``: the seed each policy's ``reset`` gets (default: drawn from ``seed``).
    """
    match = match or Match(config)
    missing = [a for a in match.agent_names if a not in policies]
    if missing:
        raise ValueError(f"no policy for agents {missing}; policies given for {sorted(policies)}")
    seeds = dict(policy_seeds) if policy_seeds is not None else default_policy_seeds(seed, match.agent_names)
    for agent in match.agent_names:
        policies[agent].reset(agent, int(seeds[agent]))
    out_dir = Path(out_dir) if out_dir is not None else None
    if out_dir is not None:
        out_dir.mkdir(parents=True, exist_ok=True)
    events_file = open(out_dir / "events.jsonl", "w", encoding="utf-8") if out_dir else None
    faults = FaultRecord()
    radio = TeamRadio()
    match_log = MatchLog(match.agent_names)
    reports = ReportReader(policies)
    watcher = observer if isinstance(observer, ObservationWatcher) else None
    started = time.perf_counter()
    observations = match.reset(seed)
    _write_events(events_file, match.events)
    total_play_s = 2 * config.referee.half_seconds
    bar = tqdm(total=round(total_play_s), unit="s", desc="match", disable=not progress, dynamic_ncols=True)
    steps = 0
    try:
        match_log.record(match, reports.estimates(), reports.reports())
        while not match.finished and (max_steps is None or steps < max_steps):
            if observer is not None and observer.done(match):
                break
            actions: dict[str, Action | None] = {}
            for agent in match.agent_names:
                try:
                    actions[agent] = parse_action(agent, policies[agent].act(observations[agent]))
                except Exception as error:  # a failing policy must not end the match
                    event = faults.add(agent, match.world.time_s, error)
                    if event is not None:
                        match.events.append(event)
                        _write_events(events_file, [event])
                    actions[agent] = None
            if observer is not None:
                observer.decided(match, actions)
            if watcher is not None:
                watcher.observed(match, observations)
            result = match.step(actions)
            observations = result.observations
            radio.actions(actions)
            radio.observations(observations)
            steps += 1
            _write_events(events_file, result.events)
            match_log.record(match, reports.estimates(), reports.reports())
            if progress and steps % PROGRESS_EVERY_STEPS == 0:
                _update_bar(bar, match, total_play_s, time.perf_counter() - started)
    finally:
        if progress:
            _update_bar(bar, match, total_play_s, time.perf_counter() - started)
        bar.close()
        if events_file:
            events_file.close()
        if out_dir is not None:
            match_log.save(out_dir / "match_log.npz")
    wall = time.perf_counter() - started
    summary = _summarize(match, seed, wall, steps, faults, radio)
    if out_dir is not None:
        with np.load(out_dir / "match_log.npz") as arrays:  # the statistics read what was written
            statistics = match_statistics([e.to_json() for e in match.events], arrays,
                                          {"radio": summary.radio, "faults": summary.faults})
        summary = replace(summary, statistics=statistics)
        (out_dir / "summary.json").write_text(json.dumps(summary.to_json(config), indent=2) + "\n", encoding="utf-8")
    how = "finished" if match.finished else f"stopped after {steps} steps"
    log.info("match %s: %s in %.1f s of simulated time (%.2fx real time)", how, summary.score, summary.sim_seconds,
             summary.real_time_factor)
    return summary


def default_policy_seeds(seed: int, agents: tuple[str, ...]) -> dict[str, int]:
    """One seed per robot's policy, drawn from the match seed apart from the match's own draws."""
    children = np.random.SeedSequence(seed).spawn(POLICY_SEED_STREAM + 1)[POLICY_SEED_STREAM].spawn(len(agents))
    return {agent: int(child.generate_state(1)[0]) for agent, child in zip(agents, children)}


def _write_events(handle, events) -> None:
    if handle is None:
        return
    for event in events:
        handle.write(json.dumps(event.to_json()) + "\n")


def _update_bar(bar, match: Match, total_play_s: float, wall_s: float) -> None:
    referee = match.referee
    played = (referee.half - 1) * referee.config.half_seconds + referee.config.half_seconds - referee.seconds_remaining
    bar.n = round(min(played, total_play_s))
    score = f"{referee.score[Side.HOME]}-{referee.score[Side.AWAY]}"
    if referee.secondary is SecondaryState.PENALTY_SHOOTOUT and referee.shootout is not None:
        score += f" (pens {referee.shootout.goals(Side.HOME)}-{referee.shootout.goals(Side.AWAY)})"
    bar.set_postfix_str(f"score {score}, sim {match.world.time_s:.0f} s, {match.world.time_s / max(wall_s, 1e-9):.2f}x")


def _summarize(match: Match, seed: int, wall: float, steps: int, faults: FaultRecord, radio: TeamRadio) -> MatchSummary:
    referee = match.referee
    shootout = None
    if referee.shootout is not None:
        shootout = {side.value: referee.shootout.goals(side) for side in Side}
    winner = None
    if referee.finished:
        end = [e for e in referee.events if e.kind is EventKind.END]
        winner = end[-1].details.get("winner") if end else None
    return MatchSummary(
        score=match.score,
        shootout=shootout,
        winner=winner,
        seed=seed,
        sim_seconds=match.world.time_s,
        wall_seconds=wall,
        steps=steps,
        events_count=len(match.events),
        radio={**match.radio.counts.to_json(), "by_side": radio.to_json()},
        faults=faults.to_json(),
    )


def package_versions() -> dict:
    """Versions of Python and of the packages a result depends on (for summaries)."""
    versions = {"python": platform.python_version()}
    for package in ("robotstadium", "pybullet", "numpy", "pettingzoo", "gymnasium"):
        try:
            versions[package] = metadata.version(package)
        except metadata.PackageNotFoundError:
            versions[package] = None
    return versions
