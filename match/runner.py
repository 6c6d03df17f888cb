"""The one game loop: play a :class:`~match.game.Match` with one policy per robot, and write what happened.

Every run goes through :func:`run_match`: full matches, tournaments, and the scenario runs
(refereed, or in the match's free play). Policies follow :class:`match.protocol.policy.Policy`:
:meth:`reset` with the robot's id and a seed before the first step, then ``act(observation)``
every control step; a :class:`~match.protocol.policy.PoseReporter` has its estimate logged
beside the truth, an :class:`~match.protocol.policy.AgentReporter` its report
(:mod:`match.reports`). They run in this process or in controller processes
(:mod:`match.controllers`). A policy that raises, returns an invalid action, misses its step
budget or dies does not end the match: its robot stands still for that step and the fault
is recorded (agent, step, time, error); a report that raises or does not fit is logged as
nothing (NaN) with one warning per robot. The outputs are written however the run ends.

Whoever needs to watch the run (a localization-sample collector, a video writer) passes a
:class:`MatchObserver`: it sees the match after the policies decided each step, and can end
the run; an :class:`ObservationWatcher` also sees the observations the policies acted on.

Outputs in ``out_dir``: ``summary.json`` (with each team's match statistics, see
:mod:`match.statistics`), ``events.jsonl`` (one event per line) and ``match_log.npz`` (see
:mod:`match.log`).
"""

from __future__ import annotations

import enum
import importlib
import json
import logging
import os
import platform
import sys
import time
from collections.abc import Mapping
from dataclasses import asdict, dataclass, field, replace
from importlib import metadata
from pathlib import Path
from typing import Any, Protocol, runtime_checkable

import numpy as np
from tqdm import tqdm

from match.errors import InvalidActionError
from match.events import EventKind, MatchEvent
from match.game import Match, MatchConfig
from match.log import MatchLog
from match.controllers import Controllers, Decision, InProcessControllers, PolicyFault, ProcessControllers
from match.protocol.actions import Action
from match.protocol.game_control import SecondaryState
from match.protocol.ids import Side
from match.protocol.policy import Policy, PoseTuple
from match.statistics import TeamRadio, match_statistics
import world

log = logging.getLogger(__name__)

FAULT_DETAILS_PER_AGENT = 20  # faults beyond this are counted, not described
PROGRESS_EVERY_STEPS = 25
STATE_HASHES = "state_hashes.txt"  # "step digest" per line, written on request (run_match's state_hashes)
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

    def observed(self, match: Match, observations: Mapping[str, Mapping[str, Any]],
                 estimates: Mapping[str, PoseTuple | None]) -> None:
        """Called every step right after :meth:`decided`, with the observations (agent id -> the
        observation dict) the policies have just acted on and their pose estimates after acting (agent
        id -> estimate, None: none); the world has not moved since the observations were taken."""


@dataclass
class FaultRecord:
    counts: dict[str, int] = field(default_factory=dict)
    details: list[dict] = field(default_factory=list)

    def add(self, fault: PolicyFault, time_s: float, step: int) -> MatchEvent | None:
        """Count ``fault``; its event (for the first :data:`FAULT_DETAILS_PER_AGENT` of its robot), else None."""
        self.counts[fault.agent] = self.counts.get(fault.agent, 0) + 1
        if self.counts[fault.agent] > FAULT_DETAILS_PER_AGENT:
            return None
        detail = {"agent": fault.agent, "step": step, "time_s": round(time_s, 3), "error": fault.error,
                  "where": fault.where}
        self.details.append(detail)
        log.warning("policy of %s failed at %.2f s: %s", fault.agent, time_s, fault.error)
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
    completed: bool = True  # False: the run stopped on an error or an interruption (``stopped_reason``)
    stopped_reason: str | None = None
    policy_seeds: dict[str, int] | None = None  # the seed each policy's reset got
    played_by: dict | None = None  # who played and where, as the caller recorded it (run_match's played_by)

    @property
    def real_time_factor(self) -> float:
        return self.sim_seconds / self.wall_seconds if self.wall_seconds > 0 else float("inf")

    def to_json(self, config: MatchConfig) -> dict:
        return {
            "completed": self.completed,
            "stopped_reason": self.stopped_reason,
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
                "referee": plain_json(asdict(config.referee)),
                "radio": plain_json(asdict(config.radio)),
                "world": {"physics": plain_json(asdict(config.world.physics)), "render": plain_json(asdict(config.world.render)),
                          "camera_profile": config.world.camera_profile},
                "initial_camera": int(config.initial_camera),
            },
            "policy_seeds": self.policy_seeds,
            "played_by": self.played_by,
            "command_line": list(sys.argv),
            "versions": package_versions(),
            "machine": machine_description(),
        }


def run_match(
    config: MatchConfig,
    policies: Mapping[str, Policy] | Controllers,
    *,
    seed: int = 0,
    out_dir: Path | None = None,
    progress: bool = True,
    max_steps: int | None = None,
    match: Match | None = None,
    observer: MatchObserver | None = None,
    policy_seeds: Mapping[str, int] | None = None,
    state_hashes: bool = False,
    played_by: Mapping[str, object] | None = None,
) -> MatchSummary:
    """Play one match to the end (or ``max_steps``, or until ``observer`` is done) and write its outputs.

    ``policies``: agent id -> policy, called in this process, or :class:`~match.controllers.Controllers`
    (e.g. controller processes), which the run closes when it ends, as it closes the match it
    builds when ``match`` is None. ``policy_seeds``: the seed
    each policy's ``reset`` gets (default: drawn from ``seed``). The outputs are written
    however the run ends; one stopped by an error or Ctrl-C has ``completed`` False in its
    summary, and the error is raised again. ``state_hashes``: also write ``STATE_HASHES`` into ``out_dir``,
    each step's number and the world's :meth:`~world.world.World.state_digest` before it is played (to find
    the first step at which two runs differ, on two machines say). ``played_by``: who played and where, as
    the caller knows it (the policies as named, the controllers' settings), kept in ``summary.json``.
    """
    if state_hashes and out_dir is None:
        raise ValueError("state hashes need an output directory")
    _warn_if_numpy_uncapped()
    if isinstance(policies, (InProcessControllers, ProcessControllers)):
        controllers: Controllers = policies
    else:
        controllers = InProcessControllers(policies)
    own_match = None
    threads = None
    try:
        if match is None:
            match = own_match = Match(config)
        threads = match.world.camera_threads
        # controller processes take the other cores: the frames are drawn sooner on one than on threads
        # that would take turns with them
        match.world.camera_threads = threads and not isinstance(controllers, ProcessControllers)
        summary = _run(config, controllers, seed, out_dir, progress, max_steps, match, observer, policy_seeds,
                       state_hashes, dict(played_by) if played_by is not None else None)
        return summary
    finally:
        controllers.close()
        if own_match is not None:
            own_match.close()
        elif match is not None and threads is not None:
            match.world.camera_threads = threads


def _run(config: MatchConfig, controllers: Controllers, seed: int, out_dir: Path | None, progress: bool,
         max_steps: int | None, match: Match, observer: MatchObserver | None,
         policy_seeds: Mapping[str, int] | None, state_hashes: bool, played_by: dict | None) -> MatchSummary:
    missing = [a for a in match.agent_names if a not in controllers.agents]
    if missing:
        raise ValueError(f"no policy for agents {missing}; policies given for {sorted(controllers.agents)}")
    seeds = dict(policy_seeds) if policy_seeds is not None else default_policy_seeds(seed, match.agent_names)
    out_dir = Path(out_dir) if out_dir is not None else None
    if out_dir is not None:
        out_dir.mkdir(parents=True, exist_ok=True)
    faults = FaultRecord()
    radio = TeamRadio()
    match_log = MatchLog(match.agent_names)
    watcher = observer if isinstance(observer, ObservationWatcher) else None
    started = time.perf_counter()
    total_play_s = 2 * config.referee.half_seconds
    steps = 0
    stopped: BaseException | None = None
    events_file = hashes_file = bar = None
    try:  # from here on, however the run ends, its outputs are written
        events_file = open(out_dir / "events.jsonl", "w", encoding="utf-8") if out_dir else None
        hashes_file = open(out_dir / STATE_HASHES, "w", encoding="ascii") if out_dir and state_hashes else None
        bar = tqdm(total=round(total_play_s), unit="s", desc="match", disable=not progress, dynamic_ncols=True)
        decision = controllers.start(seeds)
        observations = match.reset(seed)
        _write_events(events_file, match.events)
        _record_faults(decision, faults, match, 0, events_file)
        match_log.record(match, decision.estimates, decision.reports)
        while not match.finished and (max_steps is None or steps < max_steps):
            if observer is not None and observer.done(match):
                break
            if hashes_file:
                hashes_file.write(f"{steps} {match.world.state_digest()}\n")
            decision = controllers.decide({a: observations[a] for a in match.agent_names})
            _record_faults(decision, faults, match, steps, events_file)
            actions = _playable(match, {agent: decision.actions.get(agent) for agent in match.agent_names}, faults,
                                steps, events_file)
            if observer is not None:
                observer.decided(match, actions)
            if watcher is not None:
                watcher.observed(match, observations, decision.estimates)
            last = max_steps is not None and steps + 1 >= max_steps
            result = match.step(actions, observed=None if last else controllers.offer)
            observations = result.observations
            radio.actions(actions)
            radio.observations(observations)
            steps += 1
            _write_events(events_file, result.events)
            match_log.record(match, decision.estimates, decision.reports, actions)
            if progress and steps % PROGRESS_EVERY_STEPS == 0:
                _update_bar(bar, match, total_play_s, time.perf_counter() - started)
    except BaseException as error:  # the outputs are written all the same, then it is raised again
        stopped = error
        raise
    finally:
        if bar is not None:
            if progress:
                _update_bar(bar, match, total_play_s, time.perf_counter() - started)
            bar.close()
        if events_file:
            events_file.close()
        if hashes_file:
            hashes_file.close()
        summary = replace(_summarize(match, seed, time.perf_counter() - started, steps, faults, radio, stopped),
                          policy_seeds=seeds, played_by=played_by)
        if out_dir is not None:
            summary = _write_outputs(out_dir, config, match, match_log, summary)
    how = "finished" if match.finished else f"stopped after {steps} steps"
    log.info("match %s: %s in %.1f s of simulated time (%.2fx real time)", how, summary.score, summary.sim_seconds,
             summary.real_time_factor)
    return summary


def _record_faults(decision: Decision, faults: FaultRecord, match: Match, step: int, events_file) -> None:
    for fault in decision.faults:
        event = faults.add(fault, match.world.time_s, step)
        if event is not None:
            match.events.append(event)
            _write_events(events_file, [event])


def _playable(match: Match, actions: dict[str, Action | None], faults: FaultRecord, step: int,
              events_file) -> dict[str, Action | None]:
    """``actions`` with every one the match refuses (e.g. a walk past the walk limits) replaced by None (stand),
    each a recorded fault: one robot's bad action never refuses the whole step."""
    while True:
        try:
            match.check_actions(actions)
            return actions
        except InvalidActionError as error:
            if actions.get(error.agent) is None:
                raise
            fault = PolicyFault(error.agent, f"{type(error).__name__}: {error}")
            _record_faults(Decision({}, (fault,)), faults, match, step, events_file)
            actions[error.agent] = None


def _write_outputs(out_dir: Path, config: MatchConfig, match: Match, match_log: MatchLog,
                   summary: MatchSummary) -> MatchSummary:
    """Write ``match_log.npz`` and ``summary.json``; the summary with the statistics (read from what was written;
    None for a run that stopped before they could be computed)."""
    match_log.save(out_dir / "match_log.npz")
    try:
        with np.load(out_dir / "match_log.npz") as arrays:
            statistics = match_statistics([e.to_json() for e in match.events], arrays,
                                          {"radio": summary.radio, "faults": summary.faults})
    except Exception:
        if summary.completed:
            raise
        log.warning("no statistics for a match that stopped early (%s)", summary.stopped_reason, exc_info=True)
        statistics = None
    summary = replace(summary, statistics=statistics)
    (out_dir / "summary.json").write_text(json.dumps(summary.to_json(config), indent=2) + "\n", encoding="utf-8")
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


def _summarize(match: Match, seed: int, wall: float, steps: int, faults: FaultRecord, radio: TeamRadio,
               stopped: BaseException | None = None) -> MatchSummary:
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
        completed=stopped is None,
        stopped_reason=None if stopped is None else _reason(stopped),
    )


def plain_json(value: object) -> object:
    """A config value as JSON has it: enums by their value, tuples as lists, the rest as it is."""
    if isinstance(value, dict):
        return {str(k): plain_json(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain_json(v) for v in value]
    if isinstance(value, enum.Enum):
        return value.value
    return value


def _reason(error: BaseException) -> str:
    if isinstance(error, KeyboardInterrupt):
        return "interrupted"
    return f"{type(error).__name__}: {error}"[:300]


def package_versions() -> dict:
    """Versions of Python and of the packages a result depends on (for summaries)."""
    versions = {"python": platform.python_version()}
    for package in ("robotstadium", "pybullet", "numpy", "pettingzoo", "gymnasium"):
        try:
            versions[package] = metadata.version(package)
        except metadata.PackageNotFoundError:
            versions[package] = None
    return versions


def machine_description() -> dict:
    """What a rerun needs to know about this machine: the CPU, numpy's SIMD features in use and the kernels its
    BLAS was pinned to (``blas_core``, :mod:`world`; None where not pinned).

    Runs are byte-identical on one machine and software stack; another CPU or another numpy
    may take other SIMD paths (see the design's section on determinism).
    """
    cpu = platform.processor() or None
    try:
        with open("/proc/cpuinfo", encoding="utf-8", errors="replace") as info:
            names = [line.split(":", 1)[1].strip() for line in info if line.startswith("model name")]
        cpu = names[0] if names else cpu
    except OSError:
        pass
    return {"cpu": cpu, "architecture": platform.machine(), "system": platform.system(),
            "numpy_simd": numpy_simd_features(), "blas_core": os.environ.get("OPENBLAS_CORETYPE")}


AVX512_LEVEL = "X86_V4"  # numpy's name of the AVX-512 kernels that world caps (world/__init__.py)


def _warn_if_numpy_uncapped() -> None:
    """Log once a match runs numpy's AVX-512 kernels: numpy was imported before :mod:`world` could cap them
    (see there), so this match may differ in the last bits, and then in its play, from the same seed played
    by ``robotstadium`` (summary.json records the kernels as ``machine.numpy_simd``)."""
    global _UNCAPPED_WARNED
    if _UNCAPPED_WARNED or AVX512_LEVEL not in (numpy_simd_features() or ()):
        return
    _UNCAPPED_WARNED = True
    log.warning("numpy runs its AVX-512 kernels (numpy was imported before world): this match may differ from "
                "the same seed played by robotstadium; import world (or match) before numpy, or set "
                "NPY_DISABLE_CPU_FEATURES='%s' before starting Python", world.NUMPY_CAP)


_UNCAPPED_WARNED = False


def numpy_simd_features() -> list[str] | None:
    """The SIMD extensions numpy uses here (its baseline and those its dispatched kernels found), None if unknown."""
    for module_name in ("numpy._core._multiarray_umath", "numpy.core._multiarray_umath"):
        try:
            module = importlib.import_module(module_name)
        except ImportError:
            continue
        found = getattr(module, "__cpu_features__", None)
        baseline = getattr(module, "__cpu_baseline__", [])
        if found is None:
            return None
        dispatch = getattr(module, "__cpu_dispatch__", list(found))
        return sorted(set(baseline) | {name for name in dispatch if found.get(name)})
    return None
