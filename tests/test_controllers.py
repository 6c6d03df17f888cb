"""Controller processes (match.controllers): faults cost only their robots, and well-behaved play is the same."""

from __future__ import annotations

import functools
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import cv2
import numpy as np
import pytest

from agents.policies import make_policy
from match.confinement import CONTROLLER_NICENESS
from match.controllers import CONTROLLER_OPENCV_THREADS, ControllerLimits, ProcessControllers
from match.errors import MatchConfigError
from scenarios.matches.play import PRELOAD, Lineup, run_lineup_match
from tests.user_policies import left_behind
from world.process_memory import ProcessorClock, cpu_seconds

pytestmark = pytest.mark.render

STEPS = 150
QUICK = {"initial_seconds": 0.2, "ready_seconds": 0.4, "set_seconds": 0.2}
GOOD = "tests.user_policies:Counted"
FAULTY = {"home_0": "tests.user_policies:Misbehaves", "home_1": "tests.user_policies:ExitsOften",
          "home_2": "tests.user_policies:Sleeps", "home_3": "tests.user_policies:Hoards"}
LIMITS = ControllerLimits(step_budget_s=0.25, hang_s=0.5, memory_mb=400.0, group="robot")


def play(out: Path, lineup: Lineup, limits: ControllerLimits | None) -> tuple[dict, float]:
    started = time.perf_counter()
    run_lineup_match(out, lineup, half_seconds=60.0, seed=4, progress=False, max_steps=STEPS, referee=QUICK,
                     shootout=False, controllers=limits)
    return json.loads((out / "summary.json").read_text(encoding="utf-8")), time.perf_counter() - started


def test_faulty_controllers_cost_only_their_robots(tmp_path: Path) -> None:
    clean, clean_wall = play(tmp_path / "clean", Lineup(GOOD, GOOD), LIMITS)
    faulty, faulty_wall = play(tmp_path / "faulty", Lineup(GOOD, GOOD, FAULTY), LIMITS)
    assert clean["completed"] and faulty["completed"] and faulty["steps"] == STEPS
    assert clean["faults"]["total"] == 0
    by_agent = faulty["faults"]["by_agent"]
    assert set(by_agent) == set(FAULTY)
    errors = [d["error"] for d in faulty["faults"]["details"]]
    for kind in ("RuntimeError: policy bug", "SystemExit: 4", "InvalidActionError", "ControllerDied",
                 "exit code 5", "ControllerTimeout", "ControllerHung", "ControllerMemory"):
        assert any(kind in error for error in errors), kind
    # the well-behaved robots acted on every step: their estimate counts their acts
    with np.load(tmp_path / "faulty" / "match_log.npz") as log:
        agents = list(log["agents"])
        estimates = log["estimates"]
    for agent in ("away_0", "away_1", "away_2", "away_3"):
        acts = np.rint(estimates[:, agents.index(agent), 0] * 100.0)
        assert np.array_equal(acts[1:], np.arange(1, STEPS + 1) % 100), agent
    assert np.isnan(estimates[:, agents.index("home_0"), 0]).all()  # a pose of two numbers is logged as none
    assert faulty_wall < 1.5 * clean_wall + 3.0, (faulty_wall, clean_wall)  # 1.3-1.5x measured on 2 cores


@pytest.mark.parametrize("policy", ["scripted", "team"])  # the team agent thinks between steps in a process
def test_controller_processes_play_the_same_match_as_in_process(tmp_path: Path, policy: str) -> None:
    lineup = Lineup(policy, policy)
    # a generous step budget: on a loaded machine a late answer (the robot stands) would change the match
    for name, limits in (("in_process", None), ("per_team", ControllerLimits(step_budget_s=30.0, group="team"))):
        run_lineup_match(tmp_path / name, lineup, home=2, away=2, half_seconds=60.0, seed=2, progress=False,
                         max_steps=100, referee=QUICK, controllers=limits)
    for name in ("events.jsonl", "match_log.npz"):
        assert (tmp_path / "in_process" / name).read_bytes() == (tmp_path / "per_team" / name).read_bytes(), name


def test_a_controller_process_has_a_thinker_think_after_its_answer_and_records_what_it_raises(tmp_path: Path) -> None:
    summary, _ = play(tmp_path, Lineup("tests.user_policies:ThinksLater", GOOD), LIMITS)
    details = summary["faults"]["details"]
    assert {d["agent"] for d in details} == {"home_0", "home_1", "home_2", "home_3"}
    assert all("RuntimeError: think" in d["error"] for d in details)
    assert 4 * (STEPS // 7 - 2) <= len(details) <= 4 * (STEPS // 7)  # the thinks of a step's answer: one fewer
    with np.load(tmp_path / "match_log.npz") as log:
        agents, estimates = list(log["agents"]), log["estimates"]
    for agent in ("home_0", "away_0"):  # a thinker's last act is counted when it thinks: after the answer
        acts = np.rint(estimates[:, agents.index(agent), 0] * 100.0)
        lag = 1 if agent.startswith("home") else 0
        assert np.array_equal(acts[1:], (np.arange(1, STEPS + 1) - lag) % 100), agent


@pytest.mark.parametrize("settings", [{"step_budget_s": 0.0}, {"step_budget_s": float("nan")},
                                      {"memory_mb": 1e12}, {"hang_s": -1.0}, {"group": "squad"},
                                      {"step_budget_s": True}])
def test_controller_limits_are_checked(settings: dict) -> None:
    with pytest.raises(MatchConfigError, match=next(iter(settings))):
        ControllerLimits(**settings)


def test_a_controller_that_dies_before_it_is_ready_stays_stopped(tmp_path: Path) -> None:
    lineup = Lineup("stand", "stand", {"home_0": "tests.user_policies:ExitsOnReset"})
    run_lineup_match(tmp_path, lineup, home=1, away=1, half_seconds=60.0, seed=1, progress=False, max_steps=40,
                     referee=QUICK, controllers=LIMITS)
    summary = json.loads((tmp_path / "summary.json").read_text(encoding="utf-8"))
    assert summary["completed"] and summary["steps"] == 40
    assert summary["faults"]["by_agent"] == {"home_0": 1}
    error = summary["faults"]["details"][0]["error"]
    assert error.startswith("ControllerFailed") and "exit code 6" in error and "before it was ready" in error


def test_in_process_every_fault_of_a_policy_is_contained_too(tmp_path: Path) -> None:
    lineup = Lineup("stand", "stand", {"home_0": "tests.user_policies:Misbehaves",
                                       "away_0": "tests.user_policies:RaisesOnReset"})
    run_lineup_match(tmp_path, lineup, home=1, away=1, half_seconds=60.0, seed=1, progress=False, max_steps=30,
                     referee=QUICK, controllers=None)
    summary = json.loads((tmp_path / "summary.json").read_text(encoding="utf-8"))
    assert summary["completed"] and summary["steps"] == 30
    assert summary["faults"]["by_agent"] == {"home_0": 30, "away_0": 1}  # every act of Misbehaves is a fault
    errors = {d["error"].split(":")[0] for d in summary["faults"]["details"]}
    assert errors == {"RuntimeError", "SystemExit", "InvalidActionError"}


def test_a_controller_starts_on_its_robots_observations_before_the_step_is_decided() -> None:
    factories = {agent: functools.partial(make_policy, GOOD) for agent in ("home_0", "home_1", "away_0")}
    with ProcessControllers(factories, ControllerLimits(group="team")) as controllers:
        controllers.start(dict.fromkeys(factories, 0))
        home, away = (controllers._of_agent[agent] for agent in ("home_0", "away_0"))
        controllers.offer("home_0", {})
        assert not home.busy  # one of its robots' observations is still missing
        controllers.offer("home_1", {})
        assert home.busy and not away.busy
        decision = controllers.decide({agent: {} for agent in factories})
        assert not decision.faults and all(decision.actions[agent] is not None for agent in factories)
        assert not home.busy and not away.busy
        controllers.offer("away_0", {})  # a step the match ends before deciding: closing still works
        assert away.busy
    assert not away.busy and away.process is None


def test_images_reach_the_controller_processes_as_they_were_rendered() -> None:
    """Each step's images reach the policies in the controller processes unchanged, whatever their shape."""
    factories = {agent: functools.partial(make_policy, "tests.user_policies:ImageProbe")
                 for agent in ("home_0", "home_1", "away_0")}
    rng = np.random.default_rng(7)
    with ProcessControllers(factories, ControllerLimits(group="team", step_budget_s=30.0)) as controllers:
        controllers.start(dict.fromkeys(factories, 0))
        for _ in range(3):
            images = {agent: rng.integers(0, 256, (120, 160, 3), dtype=np.uint8) for agent in factories}
            images["away_0"] = images["away_0"][:60]  # a policy of another env may get another shape
            for agent in factories:
                controllers.offer(agent, {"image": images[agent]})
            decision = controllers.decide({agent: {"image": images[agent]} for agent in factories})
            assert not decision.faults
            for agent, image in images.items():
                expected = (image.flat[0] / 10.0, int(image.sum()) % 1000 / 100.0, float(image.shape[0]))
                assert decision.estimates[agent] == expected, agent


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="peak memory is read from /proc")
def test_peak_resident_memory_of_the_live_controller_processes() -> None:
    factories = {agent: functools.partial(make_policy, "stand") for agent in ("home_0", "away_0")}
    controllers = ProcessControllers(factories, ControllerLimits(group="robot"), preload=PRELOAD)
    try:
        assert controllers.peak_resident_mb() is None  # none started yet
        decision = controllers.start({"home_0": 1, "away_0": 2})
        assert decision.faults == ()
        peak = controllers.peak_resident_mb()
        assert peak is not None and 2.0 < peak < 2 * LIMITS.memory_mb, peak  # two small Python processes
    finally:
        controllers.close()
    assert controllers.peak_resident_mb() is None  # closed: no live process


def test_a_controller_maps_only_its_own_robots_images_and_the_simulator_holds_none_open() -> None:
    """A hostile policy finds no image memory of the other team: not among the descriptors of the processes
    above it (the simulator's included), not in its own address space beyond its own robots' slots."""
    factories = {"home_0": functools.partial(make_policy, "tests.user_policies:SnoopsImages"),
                 "home_1": functools.partial(make_policy, "tests.user_policies:ImageProbe"),
                 "away_0": functools.partial(make_policy, "tests.user_policies:ImageProbe"),
                 "away_1": functools.partial(make_policy, "tests.user_policies:ImageProbe")}
    rng = np.random.default_rng(8)
    with ProcessControllers(factories, ControllerLimits(group="team", step_budget_s=30.0)) as controllers:
        controllers.start(dict.fromkeys(factories, 0))
        for _ in range(3):
            images = {agent: rng.integers(1, 256, (120, 160, 3), dtype=np.uint8) for agent in factories}
            decision = controllers.decide({agent: {"image": images[agent]} for agent in factories})
            assert not decision.faults
            assert decision.estimates["home_0"] == (0.0, 2.0, 0.0)  # nothing opened; its team's two slots
            for agent in ("away_0", "away_1"):
                image = images[agent]
                assert decision.estimates[agent] == (image.flat[0] / 10.0, int(image.sum()) % 1000 / 100.0, 120.0)


def _estimate_in_a_controller(policy: str) -> object:
    """The pose estimate ``policy`` (of tests.user_policies) reports after one step in a controller process."""
    factories = {"home_0": functools.partial(make_policy, f"tests.user_policies:{policy}")}
    with ProcessControllers(factories, ControllerLimits(group="robot")) as controllers:
        assert not controllers.start({"home_0": 0}).faults
        return controllers.decide({"home_0": {}}).estimates["home_0"]


def test_a_controller_runs_below_the_simulators_priority() -> None:
    estimate = _estimate_in_a_controller("ReportsPriority")
    niceness = os.getpriority(os.PRIO_PROCESS, 0)
    assert estimate == (float(min(niceness + CONTROLLER_NICENESS, 19)), 0.0, 0.0)
    assert estimate[0] > niceness or niceness == 19  # lower priority than this process


def test_a_controller_keeps_opencv_to_its_own_thread() -> None:
    assert _estimate_in_a_controller("ReportsOpenCVThreads") == (float(CONTROLLER_OPENCV_THREADS), 0.0, 0.0)


def test_opencvs_blobs_are_the_same_on_one_thread_as_on_its_pool() -> None:
    rng = np.random.default_rng(7)
    masks = [(rng.random((120, 160)) < density).astype(np.uint8) for density in (0.02, 0.2, 0.5, 0.8)]
    threads = cv2.getNumThreads()
    try:
        cv2.setNumThreads(max(2, threads))
        pooled = [cv2.connectedComponentsWithStats(mask, connectivity=8) for mask in masks]
        cv2.setNumThreads(1)
        alone = [cv2.connectedComponentsWithStats(mask, connectivity=8) for mask in masks]
    finally:
        cv2.setNumThreads(threads)
    for (count, labels, stats, centroids), (count_1, labels_1, stats_1, centroids_1) in zip(pooled, alone):
        assert count == count_1
        assert np.array_equal(labels, labels_1) and np.array_equal(stats, stats_1)
        assert np.array_equal(centroids, centroids_1)


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="processes are found in /proc")
def test_a_processor_clock_reads_its_process_until_it_ends() -> None:
    busy = subprocess.Popen([sys.executable, "-c", "import time\nend = time.process_time() + 0.3\n"
                                                   "while time.process_time() < end: pass\ntime.sleep(60)"])
    clock = ProcessorClock(busy.pid)
    try:
        first = clock.seconds()
        deadline = time.monotonic() + 10.0
        while (clock.seconds() or 0.0) < 0.3 and time.monotonic() < deadline:
            time.sleep(0.05)
        used = clock.seconds()
        assert first is not None and used is not None and 0.3 <= used < 1.0
        assert used == pytest.approx(cpu_seconds(busy.pid), abs=0.02)  # the path's reading, from a descriptor
        busy.kill()
        busy.wait()
        assert clock.seconds() is None  # gone: never another process that took its pid
    finally:
        busy.kill()
        busy.wait()
        clock.close()
    clock.close()  # twice: nothing more


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="processes are found in /proc")
def test_no_process_a_policy_starts_outlives_its_match() -> None:
    for pid in left_behind():  # from an earlier run that failed
        os.kill(pid, signal.SIGKILL)
    factories = {"home_0": functools.partial(make_policy, "tests.user_policies:LeavesChildren"),
                 "away_0": functools.partial(make_policy, "stand")}
    with ProcessControllers(factories, ControllerLimits(group="robot")) as controllers:
        decision = controllers.start(dict.fromkeys(factories, 0))
        assert not decision.faults
        deadline = time.monotonic() + 5.0
        while len(left_behind()) < 4 and time.monotonic() < deadline:
            time.sleep(0.05)
        assert len(left_behind()) == 4  # in its session, in a session of its own, forked, a daemon
        controllers.decide({agent: {} for agent in factories})
    assert left_behind() == []


def test_a_keyboard_interrupt_raised_by_a_policy_costs_only_its_robot() -> None:
    """In a controller process Ctrl-C is ignored: a KeyboardInterrupt is the policy's own, a fault like another."""
    factories = {"home_0": functools.partial(make_policy, "tests.user_policies:InterruptsItself"),
                 "home_1": functools.partial(make_policy, GOOD)}
    with ProcessControllers(factories, ControllerLimits(group="team", step_budget_s=30.0)) as controllers:
        controllers.start(dict.fromkeys(factories, 0))
        for step in range(1, 4):
            decision = controllers.decide({agent: {} for agent in factories})
            assert [(f.agent, f.error) for f in decision.faults] == [("home_0", "KeyboardInterrupt: not the user's")]
            assert decision.estimates["home_1"][0] == step / 100.0  # its teammate acted
        assert controllers._of_agent["home_0"].restarts == 0


def test_in_process_a_policy_cannot_close_the_matchs_output(tmp_path: Path, capsys) -> None:
    stdout, stderr = sys.stdout, sys.stderr
    lineup = Lineup("stand", "stand", {"home_0": "tests.user_policies:ClosesOutput"})
    run_lineup_match(tmp_path, lineup, home=1, away=1, half_seconds=60.0, seed=1, progress=True, max_steps=30,
                     referee=QUICK, controllers=None)
    summary = json.loads((tmp_path / "summary.json").read_text(encoding="utf-8"))
    assert summary["completed"] and summary["steps"] == 30 and summary["faults"]["total"] == 0
    assert sys.stdout is stdout and sys.stderr is stderr and not stdout.closed and not stderr.closed
    print("still open")
    assert "still open" in capsys.readouterr().out


def _burn(seconds: float) -> None:
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        pass


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="processor time is read from /proc")
def test_a_match_is_the_same_on_a_loaded_machine(tmp_path: Path) -> None:
    """Processes burning both cores beside a match with a controller per robot and a budget of processor
    time (20 ms) a few times what its policies need: the match is the same, byte for byte."""
    import multiprocessing

    limits = ControllerLimits(step_budget_s=0.02, group="robot")
    lineup = Lineup(GOOD, GOOD)
    idle, _ = play(tmp_path / "idle", lineup, limits)
    burners = [multiprocessing.get_context("spawn").Process(target=_burn, args=(120.0,), daemon=True)
               for _ in range(2)]
    for burner in burners:
        burner.start()
    try:
        loaded, _ = play(tmp_path / "loaded", lineup, limits)
    finally:
        for burner in burners:
            burner.kill()
            burner.join()
    assert idle["faults"]["total"] == loaded["faults"]["total"] == 0
    for name in ("events.jsonl", "match_log.npz"):
        assert (tmp_path / "idle" / name).read_bytes() == (tmp_path / "loaded" / name).read_bytes(), name


def test_a_controller_kept_from_the_processor_is_waited_for() -> None:
    """Stopped (as a loaded machine would keep it from the processor) before it is asked, a controller has
    used none of its processor budget when the wall-clock budget has passed: its answer is awaited."""
    import threading

    factories = {"home_0": functools.partial(make_policy, GOOD)}
    with ProcessControllers(factories, ControllerLimits(step_budget_s=0.02, hang_s=5.0, group="robot")) as controllers:
        controllers.start({"home_0": 0})
        pid = controllers._of_agent["home_0"].process.pid
        os.kill(pid, signal.SIGSTOP)
        resume = threading.Timer(0.3, os.kill, (pid, signal.SIGCONT))
        resume.start()
        started = time.perf_counter()
        decision = controllers.decide({"home_0": {}})
        waited = time.perf_counter() - started
        resume.join()
    assert not decision.faults and decision.estimates["home_0"][0] == 0.01, decision
    assert waited >= 0.25


@pytest.mark.render
def test_a_match_with_controller_processes_draws_its_frames_on_one_thread() -> None:
    """Controller processes take the other cores: during the run the world draws its cameras on one
    thread, and a match the caller gave back has the setting it had."""
    from match.game import Match, MatchConfig
    from match.referee import RefereeConfig
    from match.runner import run_match

    class Seen:
        def __init__(self) -> None:
            self.threads: list[bool] = []

        def decided(self, match, actions) -> None:
            self.threads.append(match.world.camera_threads)

        def done(self, match) -> bool:
            return len(self.threads) >= 2

    config = MatchConfig(home_players=1, away_players=1, referee=RefereeConfig(**QUICK))
    factories = {agent: functools.partial(make_policy, GOOD) for agent in ("home_0", "away_0")}
    match = Match(config)
    try:
        match.world.camera_threads = True
        before = match.world.camera_threads  # False where numba's threads cannot be had
        seen = Seen()
        run_match(config, ProcessControllers(factories, ControllerLimits(group="team")), seed=1, progress=False,
                  match=match, observer=seen)
        assert seen.threads == [False, False]
        assert match.world.camera_threads == before
    finally:
        match.close()
