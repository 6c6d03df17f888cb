"""The match runner: a whole match headless, its outputs, and policies that fail."""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
import pytest

from match.game import MatchConfig
from match.protocol import Motion, make_action
from match.referee import RefereeConfig
from match.runner import run_match
from scenarios import cli

pytestmark = pytest.mark.render

SHORT = RefereeConfig(half_seconds=2.0, initial_seconds=0.2, ready_seconds=0.4, set_seconds=0.2, shootout=False)
FULL_MATCH_STEPS = 32_000  # two 10-minute halves with their pauses, in 40 ms steps


class Plain:
    """A policy with nothing to reset."""

    def reset(self, agent_id: str, seed: int) -> None:
        pass


class Walker(Plain):
    def act(self, observation: dict) -> dict:
        return make_action(Motion.FORWARD, camera=1)


class FailsAfter(Plain):
    """Raises from the 6th step on."""

    def __init__(self) -> None:
        self.calls = 0

    def act(self, observation: dict) -> dict:
        self.calls += 1
        if self.calls > 5:
            raise RuntimeError("policy bug")
        return make_action(Motion.FORWARD)


class BadAction(Plain):
    def act(self, observation: dict) -> dict:
        return {"head": [9.0, 0.0]}


@pytest.fixture(scope="module")
def faulty_match(tmp_path_factory: pytest.TempPathFactory):
    out = tmp_path_factory.mktemp("match")
    config = MatchConfig(home_players=2, away_players=1, referee=SHORT)
    policies = {"home_0": Walker(), "home_1": FailsAfter(), "away_0": BadAction()}
    summary = run_match(config, policies, seed=3, out_dir=out, progress=False)
    return summary, out


def test_failing_policies_do_not_end_the_match(faulty_match) -> None:
    summary, out = faulty_match
    assert summary.winner is None and summary.sim_seconds > 4.0  # both halves were played
    faults = summary.faults
    assert faults["by_agent"]["home_1"] == summary.steps - 5
    assert faults["by_agent"]["away_0"] == summary.steps
    assert "home_0" not in faults["by_agent"]
    first = [d for d in faults["details"] if d["agent"] == "home_1"][0]
    assert first["error"] == "RuntimeError: policy bug"
    assert any("'head'" in d["error"] for d in faults["details"] if d["agent"] == "away_0")


def test_outputs_are_written(faulty_match) -> None:
    summary, out = faulty_match
    data = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    for key in ("score", "seed", "sim_seconds", "wall_seconds", "real_time_factor", "events_count", "radio", "faults"):
        assert key in data, key
    assert data["score"] == {"home": 0, "away": 0} and data["seed"] == 3
    events = [json.loads(line) for line in (out / "events.jsonl").read_text(encoding="utf-8").splitlines()]
    assert len(events) == data["events_count"]
    kinds = {e["kind"] for e in events}
    assert {"state", "kickoff", "half_time", "end", "fault"} <= kinds
    log = np.load(out / "match_log.npz")
    steps = summary.steps + 1
    assert log["robots"].shape == (steps, 3, 3) and log["ball"].shape == (steps, 3)
    assert list(log["agents"]) == ["home_0", "home_1", "away_0"]
    assert np.all(np.diff(log["time_s"]) > 0)
    # in the first half the walker walked; the robots whose policies failed stood still
    first_half = log["robots"][(log["half"] == 1) & (log["state"] == 3)]
    moved = np.linalg.norm(first_half[-1, :, :2] - first_half[0, :, :2], axis=1)
    assert moved[0] > 0.1 and moved[1] < 0.03 and moved[2] < 0.03
    assert np.isnan(log["estimates"]).all()


def test_a_full_match_log_stays_under_50_mb(faulty_match) -> None:
    summary, out = faulty_match
    bytes_per_step_per_robot = (out / "match_log.npz").stat().st_size / (summary.steps + 1) / 3
    assert bytes_per_step_per_robot * 8 * FULL_MATCH_STEPS < 50e6


@pytest.fixture
def quick_matches(monkeypatch: pytest.MonkeyPatch) -> None:
    """Matches of the match command with short pauses before the kick-off."""
    import scenarios.matches.play as play

    original = play.match_config

    def quick_config(*args, **kwargs):
        config = original(*args, **kwargs)
        return MatchConfig(config.home_players, config.away_players,
                           referee=RefereeConfig(half_seconds=config.referee.half_seconds, initial_seconds=0.2,
                                                 ready_seconds=0.4, set_seconds=0.2, shootout=config.referee.shootout))

    monkeypatch.setattr(play, "match_config", quick_config)


def test_match_command(tmp_path: Path, capsys: pytest.CaptureFixture[str], quick_matches: None) -> None:
    argv = ["match", "--home-players", "2", "--away-players", "1", "--half-seconds", "1.5", "--seed", "4",
            "--out", str(tmp_path), "--no-progress", "--no-shootout"]
    assert cli.main(argv) == 0
    data = json.loads((tmp_path / "summary.json").read_text(encoding="utf-8"))
    assert {key: data["config"][key] for key in ("home_players", "away_players", "half_seconds", "shootout")} == {
        "home_players": 2, "away_players": 1, "half_seconds": 1.5, "shootout": False}
    assert data["config"]["referee"]["half_seconds"] == 1.5 and data["config"]["referee"]["shootout"] is False
    assert data["faults"]["total"] == 0 and data["real_time_factor"] > 0
    assert "summary.json" in capsys.readouterr().out


def test_match_command_plays_policies_by_name(tmp_path: Path, quick_matches: None) -> None:
    argv = ["match", "--home", "stand", "--away", "tests.user_policies:WalkForward", "--policy", "home_1=scripted",
            "--home-players", "2", "--away-players", "1", "--half-seconds", "1", "--seed", "2", "--out", str(tmp_path),
            "--no-progress", "--no-shootout"]
    assert cli.main(argv) == 0
    log = np.load(tmp_path / "match_log.npz")
    agents = [str(a) for a in log["agents"]]
    poses = log["robots"]
    playing = np.flatnonzero((log["state"] == 3) & (log["half"] == 1))  # PLAYING in the first half
    moved = np.hypot(*(poses[playing[-1], :, :2] - poses[playing[0], :, :2]).T)
    assert moved[agents.index("home_0")] < 0.05  # stand
    assert moved[agents.index("away_0")] > 0.1  # the user's walker


@pytest.mark.parametrize(
    "flags, words",
    [
        (["--home", "striker"], ["--home", "unknown policy 'striker'", "scripted", "scan_localize", "stand"]),
        (["--away", "tests.user_policies:Nope"], ["--away", "no class or function 'Nope'"]),
        (["--policy", "home_3=stand", "--home-players", "2"], ["home_3 is not on the field"]),
        (["--policy", "home_9=stand"], ["--policy", "home_9"]),
        (["--policy", "home_1"], ["--policy", "AGENT=POLICY"]),
        (["--policy", "home_1=stand", "--policy", "home_1=scripted"], ["home_1 more than once"]),
    ],
)
def test_match_command_refuses_bad_policies_before_writing(
    flags: list[str], words: list[str], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "out"
    try:
        code = cli.main(["match", *flags, "--out", str(out), "--no-progress"])
    except SystemExit as exit_info:
        code = exit_info.code
    assert code == 2 and not out.exists()
    message = capsys.readouterr().err
    for word in words:
        assert word in message


@pytest.mark.parametrize("argv", [["match", "--home-players", "5"], ["match", "--half-seconds", "-3"],
                                  ["match", "--away-players", "0"]])
def test_match_command_refuses_bad_options(argv: list[str], tmp_path: Path) -> None:
    try:
        code = cli.main([*argv, "--out", str(tmp_path), "--no-progress"])
    except SystemExit as exit_info:
        code = exit_info.code
    assert code == 2


def test_the_run_closes_the_match_it_builds_and_leaves_one_given_open(monkeypatch: pytest.MonkeyPatch) -> None:
    from match.game import Match

    closed: list[Match] = []
    close = Match.close
    monkeypatch.setattr(Match, "close", lambda self: (closed.append(self), close(self))[1])
    config = MatchConfig(home_players=1, away_players=1, referee=SHORT)
    policies = {"home_0": Walker(), "away_0": Walker()}
    run_match(config, policies, seed=1, progress=False, max_steps=2)
    assert len(closed) == 1  # its own match: its world and its server are gone
    match = Match(config)
    try:
        run_match(config, policies, seed=1, progress=False, max_steps=2, match=match)
        assert len(closed) == 1 and match.world is not None  # the caller's match: still open
    finally:
        match.close()


def test_a_match_warns_when_numpy_was_imported_before_world_could_cap_its_kernels() -> None:
    import subprocess
    import sys

    script = ("import numpy\n"  # before world: numpy keeps its AVX-512 kernels where the processor has them
              "from match.runner import AVX512_LEVEL, numpy_simd_features, run_match\n"
              "from match.game import MatchConfig\n"
              "from agents.behavior.policies.stand import StandPolicy\n"
              "config = MatchConfig(home_players=1, away_players=1)\n"
              "print('AVX512' if AVX512_LEVEL in numpy_simd_features() else 'AVX2')\n"
              "run_match(config, {'home_0': StandPolicy(), 'away_0': StandPolicy()}, progress=False, max_steps=2)\n")
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120,
                          env={k: v for k, v in os.environ.items() if k != "NPY_DISABLE_CPU_FEATURES"})
    assert done.returncode == 0, done.stderr
    warned = "numpy runs its AVX-512 kernels" in done.stderr
    assert warned == done.stdout.strip().endswith("AVX512")


def test_importing_world_first_pins_numpys_blas_kernels_and_the_summary_says_so() -> None:
    import subprocess
    import sys

    import world

    if not world._has_avx2_fma():
        pytest.skip("not an x86-64 processor with AVX2 and FMA: nothing is pinned")
    script = ("import world, numpy, ctypes\n"
              "from match.runner import machine_description\n"
              "lib = next(line.split()[-1] for line in open('/proc/self/maps') if 'openblas' in line)\n"
              "name = next(n for n in ('scipy_openblas_get_corename64_', 'openblas_get_corename64_',\n"
              "                        'openblas_get_corename') if hasattr(ctypes.CDLL(lib), n))\n"
              "corename = getattr(ctypes.CDLL(lib), name)\n"
              "corename.restype = ctypes.c_char_p\n"
              "print(corename().decode(), machine_description()['blas_core'])\n")
    env = {k: v for k, v in os.environ.items() if k != "OPENBLAS_CORETYPE"}
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=60, env=env)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == [world.BLAS_CORE, world.BLAS_CORE]
