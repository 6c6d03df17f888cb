"""Where the policies run: in the simulator's process, or in controller processes of their own.

The runner (:mod:`match.runner`) asks its :class:`Controllers` for a :class:`Decision` every
control step: each robot's checked action (None: the robot stands this step), the faults of
that step, and what the policies report for the log (pose estimates, agent reports). Two
kinds give the same decisions for policies that behave:

- :class:`InProcessControllers` calls the policies one after the other in this process
  (fast to start, easy to debug: the PettingZoo env and the scenario runs work this way);
- :class:`ProcessControllers` runs them in controller processes, as RobotStadium runs each
  robot's controller as a program of its own: one process per robot or per team
  (:attr:`ControllerLimits.group`), started from a clean server process (``forkserver``
  where there is one, else ``spawn``), so a controller cannot reach the simulator's objects.
  Observations go out and actions come back over pipes (the camera images through shared
  memory of each process's own, :mod:`match.shared_images`; an answer is read bounded in size,
  time and kind, :mod:`match.answers`: one refused restarts its controller); a controller is confined to its
  robots and everything its policies start ends with it (:mod:`match.confinement`); the processes
  of one step work in
  parallel, each asked as soon as its robots' observations are built (the runner offers each
  one as the match builds it: the home team's controller acts while the away team's cameras
  are rendered), and a policy that is a :class:`~match.protocol.policy.Thinker` thinks after
  the answer went out, while the simulator plays the next step. A controller that has not
  answered within the step budget (:attr:`ControllerLimits.step_budget_s`, processor time: one
  kept from the processor by other work is waited for) gets its robots a stand for that step and a
  fault; while it is still busy its robots stand, and its late answer is dropped. It is then
  on probation: steps no longer wait for it (its answer counts when it comes while the others
  are awaited), so a slow controller cannot slow the match, and every late answer over the
  budget is a fault with the time it took; :data:`PROBATION_ANSWERS` answers within the
  budget in a row end the probation. One still busy :attr:`ControllerLimits.hang_s` after
  its deadline, one that dies and one whose resident memory passes
  :attr:`ControllerLimits.memory_mb` is stopped, recorded, and restarted on probation (built
  and reset again with the same seeds); its robots stand until it is back. One that fails
  before it was ready (its build or reset ends its process) or after :data:`MAX_RESTARTS`
  restarts stays stopped: its robots stand for the rest of the match. Only controllers
  that break their budget make a run depend on timing: for all others, process and
  in-process runs are the same, byte for byte, however loaded the machine.

A fault is anything a policy raises (every ``BaseException``, ``SystemExit`` and ``os._exit`` in a
controller process included, but a ``KeyboardInterrupt`` in the simulator's process, which is the
user's Ctrl-C; a controller process ignores Ctrl-C, so there it is the policy's own), an action that fails the
one action check (:func:`match.protocol.actions.parse_action`), or one of the process faults
above. Reports that fail their checks are not faults: the log records nothing for them
(:mod:`match.reports`).
"""

from __future__ import annotations

import logging
import multiprocessing
import signal
import sys
import time
import traceback
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from multiprocessing.connection import Connection, wait
from typing import Any, Protocol

import cv2
import numpy as np

from match.answers import Answer, AnswerReader, AnswerRefused
from match.confinement import children, confine_controller, end_orphans, end_session, guard_simulator
from match.errors import InvalidReportError, MatchConfigError
from match.protocol.actions import Action, parse_action
from match.protocol.policy import AgentReport, Policy, PoseTuple, Thinker, check_pose
from match.reports import ReportReader
from match.shared_images import SharedImages, receive_frames, unpack
from world.process_memory import ProcessorClock, peak_resident_mb, resident_mb

log = logging.getLogger(__name__)

PolicyFactory = Callable[[], Policy]  # builds a robot's policy; picklable for controller processes
GROUPS = ("robot", "team")
MEMORY_CHECK_EVERY_STEPS = 25
PROBATION_ANSWERS = 3  # answers within the step budget in a row that end a controller's probation
STARVED_POLL_S = 0.02  # how often a controller kept from the processor is asked how much it has used
CLOSE_WAIT_S = 1.0  # at most this long for the answers of a step the match ended before
MAX_RESTARTS = 100  # restarts of one controller in a match; then it stays stopped (each costs about 20-50 ms)
# the allowed range of each number of ControllerLimits (seconds, MiB)
LIMIT_BOUNDS = {"step_budget_s": (0.001, 3600.0), "start_budget_s": (0.1, 3600.0), "hang_s": (0.0, 3600.0),
                "memory_mb": (64.0, 1_048_576.0)}


@dataclass(frozen=True)
class ControllerLimits:
    """How controller processes are run and held to account.

    ``step_budget_s``: processor seconds a controller may spend on one step (all its robots) before its
    robots stand for it; one that other work keeps from the processor is waited for (up to ``hang_s``
    past the budget), so a match does not depend on the machine's load (where the system does not
    report processor time, Linux's ``/proc``, the budget is wall seconds);
    ``start_budget_s``: to build and reset its policies before the first step; ``hang_s``:
    wall seconds past a missed deadline after which a controller still busy is restarted;
    ``memory_mb``: resident memory (MiB) past which it is stopped and restarted (checked
    every :data:`MEMORY_CHECK_EVERY_STEPS` steps, where the system reports it: Linux);
    ``group``: ``robot`` (one process per robot) or ``team`` (one per team).
    """

    step_budget_s: float = 0.5
    start_budget_s: float = 120.0
    hang_s: float = 10.0
    memory_mb: float = 2048.0
    group: str = "team"

    def __post_init__(self) -> None:
        for name, (low, high) in LIMIT_BOUNDS.items():
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not low <= value <= high:
                raise MatchConfigError(f"controller limit {name} = {value!r}; expected a number in [{low:g}, {high:g}]")
        if self.group not in GROUPS:
            raise MatchConfigError(f"controller group {self.group!r}; expected one of {list(GROUPS)}")


@dataclass(frozen=True)
class PolicyFault:
    """One fault of a robot's controller: ``error`` is ``"Type: message"``, ``where`` ``file:line`` or None."""

    agent: str
    error: str
    where: str | None = None

    @classmethod
    def of(cls, agent: str, error: BaseException) -> PolicyFault:
        frame = traceback.extract_tb(error.__traceback__)[-1] if error.__traceback__ else None
        return cls(agent, _describe(error), f"{frame.filename}:{frame.lineno}" if frame else None)


@dataclass(frozen=True)
class Decision:
    """One step's decisions (agent id -> action, None: stands), faults and reports (agent id -> report)."""

    actions: Mapping[str, Action | None]
    faults: tuple[PolicyFault, ...] = ()
    estimates: Mapping[str, PoseTuple | None] = field(default_factory=dict)
    reports: Mapping[str, AgentReport | None] = field(default_factory=dict)


class Controllers(Protocol):
    """The policies of one match, wherever they run."""

    agents: tuple[str, ...]

    def start(self, seeds: Mapping[str, int]) -> Decision:
        """(Re)set every policy for a new match (its ``reset``); the decision's actions are empty."""

    def offer(self, agent: str, observation: Mapping[str, Any]) -> None:
        """One robot's observation of the coming :meth:`decide`, as soon as it is built (optional early start)."""

    def decide(self, observations: Mapping[str, Mapping[str, Any]]) -> Decision:
        """Every robot's action for this step's observations (agent id -> observation dict)."""

    def close(self) -> None:
        """Free what the policies hold (processes); idempotent."""


class InProcessControllers:
    """The policies called in this process, one after the other (see the module). From :meth:`start` to
    :meth:`close`, ``sys.stdout`` and ``sys.stderr`` cannot be closed (a policy closing them would close the
    match's progress and messages too)."""

    def __init__(self, policies: Mapping[str, Policy]):
        self.agents = tuple(policies)
        self._policies = dict(policies)
        self._reader = ReportReader(self._policies)
        self._streams: list[tuple[str, _KeptOpen]] = []

    def start(self, seeds: Mapping[str, int]) -> Decision:
        self._keep_streams_open()
        faults = []
        for agent, policy in self._policies.items():
            try:
                policy.reset(agent, int(seeds[agent]))
            except KeyboardInterrupt:
                raise
            except BaseException as error:  # noqa: B036 - SystemExit of a policy is its own fault
                faults.append(PolicyFault.of(agent, error))
        return Decision({}, tuple(faults), self._reader.estimates(), self._reader.reports())

    def offer(self, agent: str, observation: Mapping[str, Any]) -> None:
        """Nothing: here the policies act one after the other in :meth:`decide`."""

    def decide(self, observations: Mapping[str, Mapping[str, Any]]) -> Decision:
        actions, faults = _act_all(self._policies, observations)
        return Decision(actions, tuple(faults), self._reader.estimates(), self._reader.reports())

    def close(self) -> None:
        for name, kept in self._streams:
            if getattr(sys, name) is kept:
                setattr(sys, name, kept.stream)
        self._streams = []

    def _keep_streams_open(self) -> None:
        for name in ("stdout", "stderr"):
            stream = getattr(sys, name)
            if stream is not None and not isinstance(stream, _KeptOpen):
                kept = _KeptOpen(stream)
                setattr(sys, name, kept)
                self._streams.append((name, kept))


class _KeptOpen:
    """A text stream whose ``close`` does nothing; everything else is the stream's."""

    def __init__(self, stream: Any):
        self.stream = stream

    def close(self) -> None:
        """Left open: the match still writes to it."""

    def __getattr__(self, name: str) -> Any:
        return getattr(self.stream, name)


class ProcessControllers:
    """The policies in controller processes (see the module).

    ``factories``: agent id -> a picklable callable that builds its policy (in the controller
    process); ``preload``: modules the server process imports once for all controllers
    (their policies' modules), so that starting one is a fork, not a fresh interpreter.
    """

    def __init__(self, factories: Mapping[str, PolicyFactory], limits: ControllerLimits = ControllerLimits(),
                 preload: Sequence[str] = ()):
        self.agents = tuple(factories)
        self.limits = limits
        methods = multiprocessing.get_all_start_methods()
        self._context = multiprocessing.get_context("forkserver" if "forkserver" in methods else "spawn")
        if "forkserver" in methods and preload:
            self._context.set_forkserver_preload(["__main__", "match.controllers", *preload])
        groups: dict[str, list[str]] = {}
        for agent in self.agents:
            groups.setdefault(agent if limits.group == "robot" else agent.split("_")[0], []).append(agent)
        self._controllers = [_Controller(self._context, {a: factories[a] for a in members})
                             for members in groups.values()]
        self._of_agent = {agent: c for c in self._controllers for agent in c.agents}
        self._steps = 0
        self._step_open = False  # a step's health checks are done and its asks may go out
        self._offered: dict[str, Mapping[str, Any]] = {}
        self._asked: list[_Controller] = []
        self._step_faults: list[PolicyFault] = []
        self._askable_now: set[int] = set()
        self._estimates: dict[str, PoseTuple | None] = dict.fromkeys(self.agents)
        self._reports: dict[str, AgentReport | None] = dict.fromkeys(self.agents)
        self._spared: frozenset[int] | None = None

    def start(self, seeds: Mapping[str, int]) -> Decision:
        guard_simulator()
        if self._spared is None:  # the children this process had of its own, before any controller started
            self._spared = frozenset(children())
        faults: list[PolicyFault] = []
        for controller in self._controllers:
            controller.stop()  # from an earlier match, if any
            controller.probation, controller.restarts = False, 0
            controller.seeds = {a: int(seeds[a]) for a in controller.agents}
            faults += controller.launch()
        self._collect(self._controllers, _started, time.perf_counter() + self.limits.start_budget_s, faults)
        for controller in self._controllers:
            if not _started(controller):
                faults += controller.fail(f"did not start within {self.limits.start_budget_s:g} s")
        return Decision({}, tuple(faults), dict(self._estimates), dict(self._reports))

    def offer(self, agent: str, observation: Mapping[str, Any]) -> None:
        """Keep one robot's observation of the coming step; a controller whose robots' observations are all
        here is asked at once, so it works while the simulator builds the others' (the step's checks of late
        answers and health come first, as in :meth:`decide`). Its answer is awaited in :meth:`decide`."""
        self._open_step()
        self._offered[agent] = observation
        controller = self._of_agent.get(agent)
        if (controller is not None and self._askable(controller)
                and all(a in self._offered for a in controller.agents)):
            self._step_faults += controller.ask({a: self._offered[a] for a in controller.agents})
            self._asked.append(controller)

    def decide(self, observations: Mapping[str, Mapping[str, Any]]) -> Decision:
        self._open_step()
        faults, asked = self._step_faults, self._asked
        for controller in self._controllers:
            if self._askable(controller):
                faults += controller.ask({a: observations[a] for a in controller.agents if a in observations})
                asked.append(controller)
        self._step_open, self._offered, self._asked, self._step_faults = False, {}, [], []
        in_good_standing = [c for c in asked if not c.probation]
        self._collect(in_good_standing, _answered, time.perf_counter() + self.limits.step_budget_s, faults)
        self._wait_for_the_starved(in_good_standing, faults)
        actions: dict[str, Action | None] = dict.fromkeys(self.agents)
        for controller in asked:
            controller.closed_step = True
            if controller.answer is not None:
                actions.update(controller.answer)
            elif controller.busy and not controller.probation:
                controller.probation = True
                faults += [PolicyFault(a, f"ControllerTimeout: no action within the step budget of "
                                          f"{self.limits.step_budget_s:g} s") for a in controller.agents]
        return Decision(actions, tuple(faults), dict(self._estimates), dict(self._reports))

    def _wait_for_the_starved(self, controllers: Sequence[_Controller], faults: list[PolicyFault]) -> None:
        """Go on waiting for those still busy that have not used their step budget of processor time: other
        work kept them from the processor, and that must not decide what a robot does (it would make a match
        depend on the machine's load). Each is waited for up to its hang limit of wall time."""
        budget = self.limits.step_budget_s
        starved = [c for c in controllers if c.busy and c.starved(budget)]
        while starved:
            now = time.perf_counter()
            cutoff = min(c.asked_at for c in starved) + budget + self.limits.hang_s
            if now >= cutoff:
                return
            self._collect(starved, _answered, min(cutoff, now + STARVED_POLL_S), faults)
            starved = [c for c in starved if c.busy and c.starved(budget)]

    def peak_resident_mb(self) -> float | None:
        """The peak resident memory (MiB) of the live controller processes, summed: each one's high-water mark
        since it started (Linux's ``VmHWM``); None where the system does not say (or none is running).

        Read it before :meth:`close` (:func:`~match.runner.run_match` closes the controllers when the run
        ends); a restarted controller's earlier processes are not counted.
        """
        peaks = [peak_resident_mb(c.process.pid) for c in self._controllers if c.process is not None]
        known = [peak for peak in peaks if peak is not None]
        return sum(known) if known else None

    def close(self) -> None:
        """Stop every controller process; one still working on an offered step gets its step budget (at most
        :data:`CLOSE_WAIT_S`) to answer first, so that it ends on its own rather than killed."""
        busy = [c for c in self._controllers if c.busy and not c.probation]
        if busy:
            self._collect(busy, _answered, time.perf_counter() + min(self.limits.step_budget_s, CLOSE_WAIT_S), [])
        self._step_open, self._offered, self._asked, self._step_faults = False, {}, [], []
        for controller in self._controllers:
            controller.stop()
        end_orphans(self._spared or frozenset())

    def _open_step(self) -> None:
        """Begin a step once: read the late answers that arrived, then restart the dead, hung or too big."""
        if self._step_open:
            return
        self._step_open = True
        self._steps += 1
        faults = self._step_faults
        self._collect(self._controllers, _started, time.perf_counter(), faults)  # late answers that arrived
        now = time.perf_counter()
        for controller in self._controllers:
            faults += controller.check_health(now, self.limits, self._steps % MEMORY_CHECK_EVERY_STEPS == 0)
        self._askable_now = {id(c) for c in self._controllers if c.ready and not c.busy}

    def _askable(self, controller: _Controller) -> bool:
        """Ready and idle when the step began, and not asked in it yet."""
        return id(controller) in self._askable_now and all(c is not controller for c in self._asked)

    def __enter__(self) -> ProcessControllers:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def _collect(self, controllers: Sequence[_Controller], done: Callable[[_Controller], bool], deadline: float,
                 faults: list[PolicyFault]) -> None:
        """Read messages until every one of ``controllers`` is ``done`` or ``deadline`` (perf_counter) passed;
        the messages of the others that arrive meanwhile (late answers, resets) are read too."""
        pending = {id(c) for c in controllers if not done(c)}
        while True:
            waiting = {c.conn: c for c in self._controllers if c.conn is not None and (c.busy or not _started(c))}
            timeout = max(0.0, deadline - time.perf_counter()) if pending else 0.0
            ready = wait(list(waiting), timeout=timeout) if waiting else []
            if not ready:
                return
            for conn in ready:
                controller = waiting[conn]
                faults += controller.receive(self._estimates, self._reports, self.limits.step_budget_s)
                if done(controller):
                    pending.discard(id(controller))


def _started(controller: _Controller) -> bool:
    return controller.ready or controller.process is None


def _answered(controller: _Controller) -> bool:
    return not controller.busy


class _Controller:
    """One controller process and its robots, seen from the simulator's side."""

    def __init__(self, context, factories: Mapping[str, PolicyFactory]):
        self.agents = tuple(factories)
        self.factories = dict(factories)
        self.seeds: dict[str, int] = {}
        self._context = context
        self.process = None
        self.conn: Connection | None = None
        self.reader: AnswerReader | None = None  # of the current process's answers
        self.ready = False  # reset answered: it can be asked
        self.busy = False  # asked, not answered
        self.asked_at = 0.0
        self.asked_cpu_s: float | None = None  # the processor time its process had used when last asked
        self.sequence = 0
        self.answer: dict[str, Action | None] | None = None
        self.closed_step = False  # the step it was last asked for has been played
        self.probation = False  # missed a deadline: steps do not wait for it (see ProcessControllers)
        self.answers_in_budget = 0  # on probation: answers within the budget in a row
        self.restarts = 0  # in this match
        self.images: SharedImages | None = None  # the image slots of its current process
        self.clock: ProcessorClock | None = None  # its current process's processor time

    def launch(self) -> list[PolicyFault]:
        """Start the process and send it the reset (answered later)."""
        parent, child = self._context.Pipe()
        process = self._context.Process(target=serve, args=(child, self.factories), daemon=True,
                                        name=f"controller {','.join(self.agents)}")
        try:
            process.start()  # kept only once started: a Ctrl-C or SIGTERM in here leaves nothing to stop
        except Exception as error:  # no process could be started: the robots stand
            return [PolicyFault.of(a, error) for a in self.agents]
        finally:
            child.close()
        self.process, self.conn, self.ready, self.busy = process, parent, False, False
        self.reader = AnswerReader(parent)
        self.clock = ProcessorClock(process.pid)
        self.images = SharedImages(len(self.agents))
        try:
            self.images.hand_over(parent, process.pid)
        except (OSError, ValueError) as error:
            return self.restart(f"ControllerDied: cannot reach its process ({_describe(error)})")
        return self._send(("reset", self.seeds))

    def ask(self, observations: Mapping[str, Mapping[str, Any]]) -> list[PolicyFault]:
        self.sequence += 1
        self.answer = None
        self.closed_step = False
        self.busy = True
        self.asked_at = time.perf_counter()
        self.asked_cpu_s = self.clock.seconds() if self.clock is not None else None
        assert self.images is not None
        return self._send(("act", self.sequence, self.images.pack(observations)))

    def starved(self, budget_s: float) -> bool:
        """Whether it has used less than ``budget_s`` of processor time since it was asked (False where the
        system does not say: then the wall clock alone counts)."""
        if self.clock is None or self.asked_cpu_s is None:
            return False
        used = self.clock.seconds()
        return used is not None and used - self.asked_cpu_s < budget_s

    def receive(self, estimates: dict, reports: dict, budget_s: float) -> list[PolicyFault]:
        """Read one message (an answer, a late answer, a reset's answer) or the process's death. An answer is
        read as its bytes arrive, bounded in size and kind (:class:`~match.answers.AnswerReader`): one refused
        stops the controller and restarts it."""
        assert self.reader is not None
        try:
            answer = self.reader.read()
        except (EOFError, OSError):
            return self.restart(f"ControllerDied: controller process ended (exit code {self._exit_code()})")
        except AnswerRefused as error:
            return self.restart(f"ControllerRefused: {error}")
        return [] if answer is None else self._handle(answer, estimates, reports, budget_s)

    def _handle(self, answer: Answer, estimates: dict, reports: dict, budget_s: float) -> list[PolicyFault]:
        faults = [PolicyFault(a, error, where) for a, error, where in answer.faults if a in self.agents]
        if answer.kind == "reset":
            self.ready = True
            self._update_reports(answer.estimates, answer.reports, estimates, reports)
        else:
            sequence, actions = answer.sequence, answer.actions
            new_estimates, new_reports = answer.estimates, answer.reports
            self.busy = False
            took_s = time.perf_counter() - self.asked_at
            self._on_probation_answer(took_s <= budget_s)
            if sequence == self.sequence and self.answer is None and not self.closed_step:
                self.answer = {}
                for agent in self.agents:  # checked again on this side: the process may send anything
                    try:
                        self.answer[agent] = parse_action(agent, dict.get(actions, agent))
                    except Exception as error:
                        self.answer[agent] = None
                        faults.append(PolicyFault.of(agent, error))
                self._update_reports(new_estimates, new_reports, estimates, reports)
            else:  # its step was played without it
                faults = []
                if self.probation and took_s > budget_s:
                    faults = [PolicyFault(a, f"ControllerTimeout: answered after {took_s:.2f} s, over the step "
                                             f"budget of {budget_s:g} s") for a in self.agents]
        return faults

    def _on_probation_answer(self, within_budget: bool) -> None:
        if not self.probation:
            return
        self.answers_in_budget = self.answers_in_budget + 1 if within_budget else 0
        if self.answers_in_budget >= PROBATION_ANSWERS:
            self.probation, self.answers_in_budget = False, 0

    def _update_reports(self, new_estimates: Mapping, new_reports: Mapping, estimates: dict, reports: dict) -> None:
        """The reports of this controller's robots, checked again on this side (unpickling skips the checks)."""
        for agent in self.agents:
            estimates[agent] = _checked(check_pose, dict.get(new_estimates, agent))
            reports[agent] = _checked(AgentReport.check, dict.get(new_reports, agent))

    def check_health(self, now: float, limits: ControllerLimits, check_memory: bool) -> list[PolicyFault]:
        """Restart a controller that died, hangs, or holds too much memory."""
        if self.process is None:
            return []
        if not self.process.is_alive():
            return self.restart(f"ControllerDied: controller process ended (exit code {self._exit_code()})")
        if self.busy and now - self.asked_at > limits.step_budget_s + limits.hang_s:
            return self.restart(f"ControllerHung: still busy {now - self.asked_at:.1f} s after it was asked")
        if check_memory:
            rss_mb = resident_mb(self.process.pid)
            if rss_mb is not None and rss_mb > limits.memory_mb:
                return self.restart(f"ControllerMemory: {rss_mb:.0f} MiB resident, over the limit of "
                                    f"{limits.memory_mb:g} MiB")
        return []

    def restart(self, reason: str) -> list[PolicyFault]:
        """Stop it and start it again, unless it never got ready or has been restarted too often: then for good."""
        if not self.ready and not self.busy:
            return self.fail(f"{reason}, before it was ready")
        if self.restarts >= MAX_RESTARTS:
            return self.fail(f"{reason}, after {MAX_RESTARTS} restarts")
        log.warning("controller of %s: %s; restarting it", ",".join(self.agents), reason)
        self.restarts += 1
        self.stop()
        return [PolicyFault(a, reason) for a in self.agents] + self.launch()

    def fail(self, reason: str) -> list[PolicyFault]:
        """Stop it for good: its robots stand for the rest of the match."""
        log.warning("controller of %s: %s; its robots stand from now on", ",".join(self.agents), reason)
        self.stop()
        return [PolicyFault(a, f"ControllerFailed: {reason}") for a in self.agents]

    def stop(self) -> None:
        if self.conn is not None:
            try:
                self.conn.send(("close",))
            except (OSError, ValueError):
                pass
        if self.process is not None:
            self.process.join(timeout=0.2 if not self.busy else 0.0)
            if self.process.is_alive():
                self.process.kill()
                self.process.join(timeout=5.0)
            if self.process.pid is not None:
                end_session(self.process.pid)  # what its policies started and left in its session
            if not self.process.is_alive():
                self.process.close()
        if self.conn is not None:
            self.conn.close()
        if self.images is not None:
            self.images.close()
            self.images = None
        if self.clock is not None:
            self.clock.close()
            self.clock = None
        self.process, self.conn, self.ready, self.busy, self.answer = None, None, False, False, None
        self.reader = None
        self.probation, self.answers_in_budget = True, 0  # a restarted controller starts on probation

    def _send(self, message: tuple) -> list[PolicyFault]:
        assert self.conn is not None
        try:
            self.conn.send(message)
        except (OSError, ValueError) as error:
            return self.restart(f"ControllerDied: cannot reach its process ({_describe(error)})")
        return []

    def _exit_code(self) -> object:
        if self.process is None:
            return None
        self.process.join(timeout=0.5)
        return self.process.exitcode


# ---- the controller process ---------------------------------------------------------------


CONTROLLER_OPENCV_THREADS = 1
"""OpenCV's threads in a controller process: its own. A policy's image calls are small (a 160x120 frame's
blobs), and OpenCV's pool, one thread per core, spent more processor time handing them out than it
saved, time taken from the simulator and the other team; the results are the same."""


def serve(conn: Connection, factories: Mapping[str, PolicyFactory]) -> None:
    """A controller process's loop: confine itself (:func:`~match.confinement.confine_controller`), keep
    OpenCV to its own thread (:data:`CONTROLLER_OPENCV_THREADS`), take its image slots
    (:func:`~match.shared_images.receive_frames`), build the policies, then answer resets and steps until
    told to close, or until the simulator's end of ``conn`` is closed (it stopped, or was stopped, without
    a word): then it ends quietly."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the simulator's to handle
    confine_controller()
    cv2.setNumThreads(CONTROLLER_OPENCV_THREADS)
    try:
        frames = receive_frames(conn)
        _answer(conn, factories, frames)
    except (EOFError, BrokenPipeError, ConnectionResetError):
        return


def _answer(conn: Connection, factories: Mapping[str, PolicyFactory], frames: np.ndarray) -> None:
    policies: dict[str, Policy] = {}
    broken: dict[str, str] = {}
    for agent, factory in factories.items():
        try:
            policies[agent] = factory()
        except BaseException as error:  # noqa: B036 - a policy that cannot be built is its robot's fault
            broken[agent] = f"PolicyBuildError: {_describe(error)}"
    reader = ReportReader(policies)
    thinkers = {agent: policy for agent, policy in policies.items() if isinstance(policy, Thinker)}
    thought: list[PolicyFault] = []  # faults of the thinking after the last answer: sent with the next one
    while True:
        message = conn.recv()
        if message[0] == "close":
            return
        if message[0] == "reset":
            faults = [(a, broken[a], None) for a in broken]
            for agent, policy in policies.items():
                try:
                    policy.reset(agent, message[1][agent])
                except BaseException as error:  # noqa: B036
                    fault = PolicyFault.of(agent, error)
                    faults.append((agent, fault.error, fault.where))
            conn.send(("reset", reader.estimates(), reader.reports(), faults))
            continue
        _, sequence, observations = message
        observations = unpack(frames, observations)
        actions, faults = _act_all(policies, observations, interrupts_are_faults=True)
        faults += [PolicyFault(a, broken[a]) for a in broken if a in observations]
        faults_sent = [(f.agent, f.error, f.where) for f in thought + faults]
        conn.send(("act", sequence, actions, reader.estimates(), reader.reports(), faults_sent))
        thought = _think_all(thinkers, observations)  # while the simulator plays the next step


def _act_all(policies: Mapping[str, Policy], observations: Mapping[str, Mapping[str, Any]],
             interrupts_are_faults: bool = False) -> tuple[dict[str, Action | None], list[PolicyFault]]:
    """Each policy's checked action for its observation; a policy that raises or returns a bad action stands.
    ``interrupts_are_faults``: a ``KeyboardInterrupt`` is the policy's own too (in a controller process,
    which ignores Ctrl-C), not the user's stop."""
    actions: dict[str, Action | None] = {}
    faults: list[PolicyFault] = []
    for agent, observation in observations.items():
        policy = policies.get(agent)
        if policy is None:
            actions[agent] = None
            continue
        try:
            actions[agent] = parse_action(agent, policy.act(observation))
        except KeyboardInterrupt as error:
            if not interrupts_are_faults:
                raise
            faults.append(PolicyFault.of(agent, error))
            actions[agent] = None
        except BaseException as error:  # noqa: B036 - a failing policy must not end the match
            faults.append(PolicyFault.of(agent, error))
            actions[agent] = None
    return actions, faults


def _think_all(thinkers: Mapping[str, Thinker], observations: Mapping[str, Any]) -> list[PolicyFault]:
    """Each :class:`~match.protocol.policy.Thinker` that was asked this step thinks, in a controller process;
    what one raises is its fault (a ``KeyboardInterrupt`` too: the process ignores Ctrl-C)."""
    faults: list[PolicyFault] = []
    for agent, policy in thinkers.items():
        if agent not in observations:
            continue
        try:
            policy.think()
        except BaseException as error:  # noqa: B036 - as in _act_all
            faults.append(PolicyFault.of(agent, error))
    return faults


def _checked(check: Callable[[object], Any], value: object) -> Any:
    try:
        return check(value)
    except InvalidReportError:
        return None


def _describe(error: BaseException) -> str:
    try:
        text = str(error)
    except Exception:
        text = "<unprintable>"
    if len(text) > 300:
        text = text[:297] + "..."
    return f"{type(error).__name__}: {text}"
