"""The batch engine of scenarios and tournaments: tasks here or in worker processes, failures, crashes, the store."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from scenarios.common.batch import BatchError, BatchOptions, ResultStore, execute
from scenarios.common.termination import terminate_as_interrupt
from tests import batch_work

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(autouse=True)
def importable_tests(monkeypatch: pytest.MonkeyPatch) -> None:
    """Spawned workers import ``tests.batch_work`` from the parent's sys.path."""
    monkeypatch.syspath_prepend(str(ROOT))


def results_by_task(results) -> dict:
    return {r.task: r for r in results}


def test_tasks_run_here_with_one_worker_and_a_failure_does_not_stop_them() -> None:
    ticks = []
    results = results_by_task(execute([1, 2, 3], batch_work.raises_on_two, BatchOptions(workers=1),
                                      lambda n=1: ticks.append(n)))
    assert results[1].value == 1 and results[3].value == 9
    assert results[2].failed and results[2].error == "RuntimeError: task two fails" and results[2].attempts == 1


def test_a_worker_that_dies_is_retried_alone_and_recorded_with_its_exit_code() -> None:
    results = results_by_task(execute([1, 2, 3, 4], batch_work.dies_on_three, BatchOptions(workers=2)))
    assert sorted(results) == [1, 2, 3, 4]
    assert results[3].failed and "exit code 3" in results[3].error and results[3].attempts == 2
    for task in (1, 2, 4):  # a task broken with the pool ran again alone and finished
        assert not results[task].failed and results[task].value == task * task


def test_isolated_tasks_run_in_a_worker_process_even_with_one_worker() -> None:
    results = results_by_task(execute([3, 5], batch_work.dies_on_three, BatchOptions(workers=1), isolate=True))
    assert results[3].failed and "exit code 3" in results[3].error
    assert results[5].value == 25


def test_ticks_from_worker_processes_reach_the_progress() -> None:
    ticks = []
    results = list(execute([1, 2, 3], batch_work.square, BatchOptions(workers=2), lambda n=1: ticks.append(n)))
    assert sorted(r.value for r in results) == [1, 4, 9] and len(ticks) == 3


def test_a_store_keeps_its_files_and_refuses_other_settings_naming_both(tmp_path: Path) -> None:
    store = ResultStore(tmp_path, fingerprint="aaaa", settings={"matches": 4, "seed": 1}, resume=False,
                        marker="marker.json", prefix="match", key="match", what="matches")
    store.save(0, {"match": 0, "value": 1.5})
    assert json.loads((tmp_path / "runs" / "match_0000.json").read_text()) == {"fingerprint": "aaaa", "match": 0,
                                                                                 "value": 1.5}
    again = ResultStore(tmp_path, fingerprint="aaaa", settings={"matches": 4, "seed": 1}, resume=True,
                        marker="marker.json", prefix="match", key="match", what="matches")
    assert again.load() == {0: {"fingerprint": "aaaa", "match": 0, "value": 1.5}}
    with pytest.raises(BatchError) as refused:
        ResultStore(tmp_path, fingerprint="bbbb", settings={"matches": 6, "seed": 1}, resume=True,
                    marker="marker.json", prefix="match", key="match", what="matches")
    message = str(refused.value)
    assert "matches=4" in message and "matches=6" in message and "seed" not in message
    assert "aaaa" in message and "bbbb" in message and "--resume" in message
    fresh = ResultStore(tmp_path, fingerprint="bbbb", settings={"matches": 6, "seed": 1}, resume=False,
                        marker="marker.json", prefix="match", key="match", what="matches")
    assert fresh.load() == {}  # a fresh batch starts over


def _worker_pids(directory: Path, count: int, timeout_s: float = 60.0) -> list[int]:
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        files = sorted(directory.glob("worker*.pid"))
        if len(files) == count:
            return [int(f.read_text()) for f in files]
        time.sleep(0.1)
    raise AssertionError(f"{count} workers did not start within {timeout_s:g} s")


def _running(pid: int) -> bool:
    """The process exists and is not a zombie."""
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except (FileNotFoundError, ProcessLookupError, IndexError):
        return False
    return state != "Z"


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
@pytest.mark.parametrize("stop", [signal.SIGTERM, signal.SIGKILL], ids=["sigterm", "sigkill"])
@pytest.mark.parametrize("alone", [False, True], ids=["pool", "alone"])
def test_a_stopped_batch_leaves_no_worker_running(tmp_path: Path, stop: signal.Signals, alone: bool) -> None:
    """``kill`` of a batch's main process (SIGTERM: as Ctrl-C, exit code 130; SIGKILL: no cleanup at all) ends
    its workers, in the pool and a task run alone after a crash, instead of letting them play on."""
    if alone:
        (tmp_path / "die-first").touch()
    tasks = 1 if alone else 2
    main = subprocess.Popen([sys.executable, "-c", "import sys; from tests import batch_work; "
                             f"batch_work.run_until_stopped(sys.argv[1], {tasks})", str(tmp_path)],
                            cwd=ROOT, env={**os.environ, "PYTHONPATH": str(ROOT)})
    try:
        pids = _worker_pids(tmp_path, tasks)
        main.send_signal(stop)
        code = main.wait(timeout=30)
    finally:
        main.kill()
    assert code == (130 if stop == signal.SIGTERM else -signal.SIGKILL)
    deadline = time.monotonic() + 15
    while any(_running(pid) for pid in pids) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not [pid for pid in pids if _running(pid)], "workers still running after their batch was stopped"


def test_a_sigterm_is_a_ctrl_c_within_the_block_and_the_old_handler_is_back_after() -> None:
    before = signal.getsignal(signal.SIGTERM)
    with pytest.raises(KeyboardInterrupt, match="SIGTERM"), terminate_as_interrupt():
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(1)  # the handler runs at the next bytecode; never reached
    assert signal.getsignal(signal.SIGTERM) is before
