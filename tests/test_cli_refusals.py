"""Refusals: every bad number or path of every command ends with exit code 2, one line naming it, and
nothing written; scenario files out of bounds and damaged run, match and trial files on --resume are
refused the same way."""

from __future__ import annotations

import argparse
import json
import math
import os
from pathlib import Path

import pytest

from scenarios import cli
from scenarios.common.batch import BatchError, TaskResult
from scenarios.drills.records import TrialRecord
from scenarios.drills.records import stored_record as stored_trial
from scenarios.drills.settings import DrillSettings
from scenarios.drills.shooting import Shooting
from scenarios.localization.batch import RunStore
from scenarios.localization.file import ScenarioFileError, load_scenario
from scenarios.tournament.run import match_record, stored_record
from scenarios.tournament.settings import TournamentSettings

BAD_COUNTS = ("-1", "1.5", "nan", "inf", "1e308", "1" + "0" * 30, "9" * 5000, "ten", "")
BAD_SEEDS = ("-1", str(2**32), "1e3", "nan", "1" + "0" * 30, "seed", "")
BAD_NUMBERS = ("-1", "0", "nan", "inf", "-inf", "1e308", "ten", "")
BAD_DIRS = ("", " ", "a_file", "a_file/sub", "a_file/../sub", "broken", "loop/sub", "/proc/x", "/sys/x", "/proc",
            "/dev/null", "n" * 300, "a/" * 2100, "nul\0byte", "read_only/sub")
BAD_FILES = ("", "a_dir", "a_file/sub", "broken", "/proc/x", "/dev/null", "n" * 300, "read_only/x.json")

# (command line up to the flag, the flag, its bad values); the flag's value comes last
BAD_PROFILES = ("fancy", "", "NAO", "clean,nao")
TABLE = [
    (["world-demo", "--out", "out"], "--seed", BAD_SEEDS),
    (["world-demo"], "--out", BAD_DIRS),
    (["bench", "--out", "out"], "--repeats", ("0", "5001", "1000000000000", *BAD_COUNTS)),
    (["bench"], "--out", BAD_DIRS),
    (["bench", "--out", "out"], "--compare", ("", "nul\0byte", "nowhere.json", "a_dir", "a_file", "broken", "loop",
                                              "/proc/x", "/dev/null", "/dev/zero", "n" * 300)),
    (["match"], "--home", ("nope", "no.such.module:Policy", "", "os:getcwd", "builtins:object")),
    (["match"], "--away", ("nope", "")),
    (["match"], "--policy", ("home_9=scripted", "home_1", "home_1=nope", "=scripted", "home_0=os:system")),
    (["match"], "--home-players", ("0", "5", *BAD_COUNTS)),
    (["match"], "--away-players", ("0", "5", *BAD_COUNTS)),
    (["match"], "--half-seconds", ("0.5", "86401", "1e307", *BAD_NUMBERS)),
    (["match"], "--seed", BAD_SEEDS),
    (["match"], "--out", BAD_DIRS),
    (["match"], "--video", ("home_9", "everyone", "")),
    (["match"], "--controller-per", ("squad", "")),
    (["match"], "--step-budget", ("0", "3601", *BAD_NUMBERS)),
    (["match"], "--controller-memory", ("63", "1e7", *BAD_NUMBERS)),
    (["match"], "--camera-profile", BAD_PROFILES),
    (["calibrate-colors", "--out", "t.json"], "--frames", ("0", "2001", *BAD_COUNTS)),
    (["calibrate-colors", "--out", "t.json"], "--seed", BAD_SEEDS),
    (["calibrate-colors"], "--out", BAD_FILES),
    (["calibrate-colors", "--out", "t.json"], "--camera-profile", BAD_PROFILES),
    (["perception", "--frames", "1", "--out", "out"], "--frames", ("0", "20001", *BAD_COUNTS)),
    (["perception", "--frames", "1", "--out", "out"], "--seed", BAD_SEEDS),
    (["perception", "--frames", "1"], "--out", BAD_DIRS),
    (["perception", "--frames", "1", "--out", "out"], "--crowd", ("8", *BAD_COUNTS)),
    (["perception", "--frames", "1", "--out", "out"], "--models", ("fisheye", "exact,exact", "")),
    (["perception", "--frames", "1", "--out", "out"], "--max-range-m", ("0.05", "21", *BAD_NUMBERS)),
    (["perception", "--frames", "1", "--out", "out"], "--examples", ("1001", *BAD_COUNTS)),
    (["perception", "--frames", "1", "--out", "out"], "--camera-profile", BAD_PROFILES),
    (["perception", "--frames", "1", "--out", "out"], "--head-rate", ("-0.1", "5.5", "-1", "nan", "inf", "-inf", "1e308", "ten", "")),
    (["localize"], "--samples", ("0", "10001", *BAD_COUNTS)),
    (["localize"], "--seed", BAD_SEEDS),
    (["localize"], "--methods", ("kalman", "thesis,thesis", "")),
    (["scenario", "1", "--out", "out"], "--samples", ("0", "100001", *BAD_COUNTS)),
    (["scenario", "1", "--out", "out"], "--seed", BAD_SEEDS),
    (["scenario", "1", "--out", "out"], "--methods", ("kalman", "")),
    (["scenario", "1", "--out", "out"], "--half-seconds", ("0.5", "86401", *BAD_NUMBERS)),
    (["scenario", "1", "--out", "out"], "--workers", ("0", "65", *BAD_COUNTS)),
    (["scenario", "1"], "--out", BAD_DIRS),
    (["scenario", "1", "--out", "out"], "--camera-profile", BAD_PROFILES),
    (["tournament", "scripted", "stand", "--out", "out"], "--matches", ("0", "1001", *BAD_COUNTS)),
    (["tournament", "scripted", "stand", "--out", "out"], "--half-seconds", ("0.5", "86401", *BAD_NUMBERS)),
    (["tournament", "scripted", "stand", "--out", "out"], "--players", ("0", "5", *BAD_COUNTS)),
    (["tournament", "scripted", "stand", "--out", "out"], "--seed", BAD_SEEDS),
    (["tournament", "scripted", "stand", "--out", "out"], "--workers", ("0", "65", *BAD_COUNTS)),
    (["tournament", "scripted", "stand", "--out", "out"], "--camera-profile", BAD_PROFILES),
    (["tournament", "scripted", "stand"], "--out", BAD_DIRS),
    (["tournament", "scripted", "stand", "--out", "out"], "--plots-for", ("-1", "10", "1e3", "")),
    (["tournament", "scripted", "stand", "--out", "out"], "--pauses", ("1,2", "0,0,61", "-1,0,0", "nan,0,0", "a,b,c")),
    (["tournament", "scripted", "stand", "--out", "out"], "--controller-per", ("squad", "")),
    (["tournament", "scripted", "stand", "--out", "out"], "--step-budget", ("0", "3601", *BAD_NUMBERS)),
    (["tournament", "scripted", "stand", "--out", "out"], "--controller-memory", ("63", "1e7", *BAD_NUMBERS)),
    (["replay", "match"], "--out", BAD_FILES),
    (["replay", "match"], "--stride", ("0", "100001", *BAD_COUNTS)),
    (["rerun", "match"], "--out", BAD_DIRS),
    (["drill", "throw-in", "--out", "out"], "--home", ("nope", "no.such.module:Policy", "", "os:getcwd")),
    (["drill", "throw-in", "--out", "out"], "--away", ("nope", "")),
    (["drill", "throw-in", "--out", "out"], "--players", ("0", "5", *BAD_COUNTS)),
    (["drill", "shooting", "--out", "out"], "--striker", ("nope", "builtins:object")),
    (["drill", "shooting", "--out", "out"], "--keeper", ("nope", "")),
    (["drill", "duel", "--out", "out"], "--home", ("nope",)),
    (["drill", "duel", "--out", "out"], "--away", ("nope",)),
    (["drill", "duel", "--out", "out"], "--spread", ("-0.1", "0.91", "1e308", "nan", "inf", "ten", "")),
    (["drill", "goal-line", "--out", "out"], "--defenders", ("nope", "team:missing.toml")),
    (["drill", "goal-line", "--out", "out"], "--attacker", ("nope",)),
    *((["drill", name, "--out", "out"], flag, values) for name in ("throw-in", "shooting", "duel", "goal-line")
      for flag, values in (("--seconds", ("0", "601", *BAD_COUNTS)), ("--trials", ("0", "10001", *BAD_COUNTS)),
                           ("--seed", BAD_SEEDS), ("--workers", ("0", "65", *BAD_COUNTS)))),
    *((["drill", name], "--out", BAD_DIRS) for name in ("throw-in", "shooting", "duel", "goal-line")),
]

# Refusals that name what is wrong without a flag: (command line, a word the message holds)
OTHER_REFUSALS = [
    (["match", "--home-players", "2", "--policy", "home_3=scripted"], "--policy"),
    (["match", "--policy", "home_1=stand", "--policy", "home_1=scripted"], "--policy"),
    (["match", "--away-players", "1", "--video", "away_2"], "--video"),
    (["tournament", "scripted", "--out", "out"], "POLICY"),
    (["tournament", "scripted", "nope", "--out", "out"], "POLICY"),
    (["tournament", "stand", "os:system", "--out", "out"], "not a policy class"),
    (["tournament", "scripted", "stand", "--matches", "2", "--plots-for", "4", "--out", "out"], "--plots-for"),
    (["scenario", "nope.toml", "--out", "out"], "nope.toml"),
    (["scenario", "a_dir", "--out", "out"], "a_dir"),
    (["scenario", "", "--out", "out"], "<file>"),
    (["scenario", "1", "1", "--out", "out"], "distinct"),
    (["calibrate-colors", "--out", "taken.json"], "--out"),  # taken_report.json is a directory
    (["replay", "match"], "MATCH_DIR"),  # match/replay.html is a directory
    (["replay", ""], "MATCH_DIR"),
    (["replay", "a_file"], "a_file"),
    (["rerun", "", "--out", "out"], "MATCH_DIR"),
    (["rerun", "a_file", "--out", "out"], "a_file"),
    (["rerun", "a_dir", "--out", "out"], "summary.json"),
    (["drill", "nope", "--out", "out"], "'nope'"),
    (["drill", "", "--out", "out"], "DRILL"),
    (["drill"], "DRILL"),
    (["drill", "shooting", "--seed", "4294967295", "--trials", "2", "--out", "out"], "--seed 4294967295"),
]


def _cases():
    for argv, flag, values in TABLE:
        for value in values:
            yield pytest.param(argv, flag, value, id=f"{_command(argv)} {flag} {value[:16]!r}")


def _command(argv: list[str]) -> str:
    """The command a command line runs: its first word, and a drill's name."""
    return " ".join(argv[:2]) if argv[0] == "drill" else argv[0]


@pytest.fixture
def place(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """The current directory: a regular file, a directory, broken and looping links, a read-only directory,
    a match directory whose replay page is a directory, a report path that is a directory."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "a_file").write_text("x\n", encoding="utf-8")
    (tmp_path / "a_dir").mkdir()
    (tmp_path / "broken").symlink_to(tmp_path / "nowhere")
    (tmp_path / "loop").symlink_to(tmp_path / "loop")
    (tmp_path / "read_only").mkdir(mode=0o555)
    (tmp_path / "match" / "replay.html").mkdir(parents=True)
    (tmp_path / "taken_report.json").mkdir()
    return tmp_path


def snapshot(root: Path) -> dict[str, object]:
    """Every path under ``root`` with its content (a file), its target (a link) or None (a directory)."""
    found: dict[str, object] = {}
    for directory, dirs, files in os.walk(root):
        for name in dirs + files:
            path = Path(directory) / name
            key = str(path.relative_to(root))
            if path.is_symlink():
                found[key] = os.readlink(path)
            else:
                found[key] = path.read_bytes() if path.is_file() else None
    return found


def refused(argv: list[str], capsys: pytest.CaptureFixture[str]) -> str:
    """The one line on stderr of a command refused with exit code 2."""
    try:
        code = cli.main(argv)
    except SystemExit as exit_info:  # refused while parsing
        code = exit_info.code
    captured = capsys.readouterr()
    assert code == cli.EXIT_USAGE, captured
    assert "Traceback" not in captured.err
    lines = captured.err.splitlines()
    assert len(lines) == 1 and captured.err.endswith("\n"), captured.err
    assert lines[0].startswith((f"robotstadium {argv[0]}: error: ", f"robotstadium {_command(argv)}: error: "))
    return lines[0]


@pytest.mark.parametrize(("argv", "flag", "value"), list(_cases()))
def test_a_bad_value_is_refused_with_one_line_naming_the_flag_and_nothing_written(
    argv: list[str], flag: str, value: str, place: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    if value.startswith("read_only") and os.geteuid() == 0:
        pytest.skip("root writes into a read-only directory")
    before = snapshot(place)
    line = refused([*argv, flag, value], capsys)
    assert flag in line and len(line) < 400
    assert snapshot(place) == before


@pytest.mark.parametrize(("argv", "word"), OTHER_REFUSALS, ids=[" ".join(a)[:40] for a, _ in OTHER_REFUSALS])
def test_a_refusal_of_the_library_is_one_line_and_writes_nothing(
    argv: list[str], word: str, place: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    before = snapshot(place)
    assert word in refused(argv, capsys)
    assert snapshot(place) == before


def _valued_arguments() -> set[tuple[str, str]]:
    """(command, flag or positional) of every argument that takes a value; a drill's are ``drill NAME``'s."""
    found = set()

    def visit(parser: argparse.ArgumentParser, command: str) -> None:
        for action in parser._actions:
            if isinstance(action, argparse._SubParsersAction):
                if command:
                    found.add((command, action.dest))
                for name, sub in action.choices.items():
                    visit(sub, f"{command} {name}".strip())
            elif action.nargs != 0 and not isinstance(action, argparse._HelpAction):
                found.add((command, action.option_strings[-1] if action.option_strings else action.dest))

    visit(cli.build_parser(), "")
    return found


DRILL_COMMANDS = ("drill throw-in", "drill shooting", "drill duel", "drill goal-line")


def test_the_table_covers_every_argument_that_takes_a_value() -> None:
    covered = {(_command(argv), flag) for argv, flag, _ in TABLE}
    positionals = {("scenario", "scenarios"), ("tournament", "policies"), ("replay", "match_dir"),
                   ("rerun", "match_dir"), ("drill", "drill")}  # OTHER_REFUSALS
    free = {(command, flag) for command in ("scenario", "tournament", *DRILL_COMMANDS)
            for flag in ("--backend", "--ray-address")}
    assert _valued_arguments() - covered - positionals - free == set()


BOUNDS_IN_HELP = {
    "world-demo": ["0-4294967295"],
    "bench": ["1-5000"],
    "match": ["1-4", "1-86400", "0-4294967295"],
    "calibrate-colors": ["1-2000", "0-4294967295"],
    "perception": ["1-20000", "0-4294967295", "0-7", "0.1-20 m", "0-1000"],
    "localize": ["1-10000", "0-4294967295"],
    "scenario": ["1-100000", "0-4294967295", "1-86400", "1-64"],
    "tournament": ["1-1000", "1-86400", "1-4", "0-4294967295", "1-64"],
    "replay": ["1-100000"],
    "drill throw-in": ["1-4", "1-600 s", "1-10000", "0-4294967295", "1-64"],
    "drill shooting": ["1-600 s", "1-10000", "0-4294967295", "1-64"],
    "drill duel": ["1-600 s", "0-0.9 m", "1-10000", "0-4294967295", "1-64"],
    "drill goal-line": ["1-600 s", "1-10000", "0-4294967295", "1-64"],
}


@pytest.mark.parametrize("command", BOUNDS_IN_HELP)
def test_the_help_states_every_bound(command: str, capsys: pytest.CaptureFixture[str],
                                     monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("COLUMNS", "1000")  # no line breaks inside a range
    with pytest.raises(SystemExit):
        cli.main([*command.split(), "--help"])
    text = capsys.readouterr().out
    for bound in BOUNDS_IN_HELP[command]:
        assert bound in text, bound


BAD_BENCH_FILES = [
    ("truncated", b'{"render_ms_median": 4.'),
    ("binary", bytes(range(256))),
    ("empty", b""),
    ("deep", b"[" * 100_000 + b"]" * 100_000),
    ("array", b'[{"render_ms_median": 4.0}]'),
    ("null", b"null"),
    ("string", b'"bench"'),
    ("no figures", b'{"repeats": 20, "match_steps": 40, "machine": {"cpu": "x"}}'),
    ("figures as text", b'{"render_ms_median": "4.0", "env_steps_per_s": "20"}'),
    ("figures as booleans", b'{"render_ms_median": true}'),
    ("figures not finite", b'{"render_ms_median": NaN, "env_steps_per_s": Infinity}'),
    ("over a megabyte", b'{"render_ms_median": 4.0, "pad": "' + b"a" * 1_000_000 + b'"}'),
]


@pytest.mark.parametrize("content", [c for _, c in BAD_BENCH_FILES], ids=[n for n, _ in BAD_BENCH_FILES])
def test_bench_refuses_a_file_to_compare_that_is_no_bench_json(content: bytes, place: Path,
                                                               capsys: pytest.CaptureFixture[str]) -> None:
    (place / "old.json").write_bytes(content)
    before = snapshot(place)
    line = refused(["bench", "--out", "out", "--quick", "--compare", "old.json"], capsys)
    assert "--compare old.json: " in line and "expected a bench.json" in line and len(line) < 400
    assert snapshot(place) == before


# ---- scenario files ------------------------------------------------------------------------

BASE = 'name = "t"\nsamples = 2\n'
ROBOT = '[[robots]]\nid = "home_1"\npolicy = "scan_localize"\nmeasured = true\n'
BAD_FILES_TEXT = [
    ("nested arrays", "x = " + "[" * 3000 + "]" * 3000 + "\n" + BASE + ROBOT, "<syntax>"),
    ("nested tables", "x = " + "{a = " * 3000 + "1" + "}" * 3000 + "\n" + BASE + ROBOT, "<syntax>"),
    ("over a megabyte", BASE + 'description = "' + "a" * 1_100_000 + '"\n' + ROBOT, "<file>"),
    ("long description", BASE + 'description = "' + "a" * 5000 + '"\n' + ROBOT, "description"),
    ("long name", 'name = "' + "n" * 300 + '"\nsamples = 2\n' + ROBOT, "name"),
    ("many samples", 'name = "t"\nsamples = 1000000\n' + ROBOT, "samples"),
    ("huge motion scale", BASE + "[noise]\nmotion_scale = 1e308\n" + ROBOT, "noise.motion_scale"),
    ("huge warm-up", BASE + "[limits]\nmax_sim_seconds_per_run = 1e308\nwarmup_seconds = 1e307\n" + ROBOT,
     "limits.max_sim_seconds_per_run"),
    ("tiny run", BASE + "[limits]\nmax_sim_seconds_per_run = 1e-300\n" + ROBOT, "limits.max_sim_seconds_per_run"),
    ("huge half", BASE + "[match]\nhalf_seconds = 1e308\n" + ROBOT, "match.half_seconds"),
    ("tiny period", BASE + "referee = true\n[sampling]\nperiod_seconds = 5e-324\n" + ROBOT, "sampling.period_seconds"),
    ("huge thesis figure", BASE + "[thesis]\nposition_mean_cm = 1e308\nposition_ci95_cm = 1\n"
     "orientation_mean_deg = 1\norientation_ci95_deg = 1\n" + ROBOT, "thesis.position_mean_cm"),
    ("huge heading", BASE + ROBOT + "start = [0.0, 0.0, 1e308]\n", "robots[0].start"),
    ("long policy", BASE + '[[robots]]\nid = "home_1"\npolicy = "' + "p" * 300 + '"\nmeasured = true\n',
     "robots[0].policy"),
    ("deep robots", BASE + "robots = " + "[" * 100 + "]" * 100 + "\n", "robots"),
]


@pytest.mark.parametrize(("text", "key"), [c[1:] for c in BAD_FILES_TEXT], ids=[c[0] for c in BAD_FILES_TEXT])
def test_a_scenario_file_out_of_bounds_is_a_precise_error(text: str, key: str, place: Path,
                                                          capsys: pytest.CaptureFixture[str]) -> None:
    path = place / "bad.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(ScenarioFileError) as caught:
        load_scenario(path)
    assert caught.value.key == key and str(caught.value).startswith(f"{path}: {key}: expected ")
    assert len(str(caught.value)) < 500
    before = snapshot(place)
    line = refused(["scenario", "bad.toml", "--out", "out"], capsys)
    assert "bad.toml" in line and key in line
    assert snapshot(place) == before


def test_a_file_within_the_bounds_loads(place: Path) -> None:
    path = place / "good.toml"
    path.write_text(BASE + 'description = "' + "a" * 4000 + '"\n[noise]\nmotion_scale = 5\n[limits]\n'
                    "max_sim_seconds_per_run = 10\nwarmup_seconds = 9.5\n" + ROBOT + "start = [0, 0, -360]\n",
                    encoding="utf-8")
    spec = load_scenario(path)
    assert (spec.motion_noise_scale, spec.max_sim_seconds_per_run, spec.warmup_seconds) == (5.0, 10.0, 9.5)
    assert math.cos(spec.robots[0].start.theta) == pytest.approx(1.0)


# ---- damaged run files on --resume -----------------------------------------------------------

SCENARIO = load_scenario("1")
GOOD_RUN = {
    "fingerprint": SCENARIO.fingerprint(), "run": 0, "seed": SCENARIO.run_seeds()[0], "sim_seconds": 30.0,
    "wall_seconds": 4.0, "complete": True,
    "samples": [{"run": 0, "robot": "home_1", "method": "thesis", "event": 0, "sim_time_s": 12.5, "true_x": 0.5,
                 "true_y": -1.0, "true_theta": 0.3, "est_x": math.nan, "est_y": math.nan, "est_theta": math.nan,
                 "landmarks_used": 0, "percepts": 3, "compute_ms": 0.2}],
}
DAMAGED_RUNS = [
    ("truncated", json.dumps(GOOD_RUN)[:60].encode()),
    ("binary", bytes(range(256))),
    ("empty", b""),
    ("array", b"[1, 2, 3]"),
    ("string", b'"run"'),
    ("deep", b"[" * 100_000 + b"]" * 100_000),
    ("huge number", b'{"run": ' + b"1" * 5000 + b"}"),
    ("no fingerprint", json.dumps({**GOOD_RUN, "fingerprint": None}).encode()),
    ("missing seed", json.dumps({k: v for k, v in GOOD_RUN.items() if k != "seed"}).encode()),
    ("seed of another run", json.dumps({**GOOD_RUN, "seed": 3}).encode()),
    ("another run's index", json.dumps({**GOOD_RUN, "run": 1}).encode()),
    ("index as text", json.dumps({**GOOD_RUN, "run": "0"}).encode()),
    ("time as text", json.dumps({**GOOD_RUN, "sim_seconds": "30"}).encode()),
    ("complete as number", json.dumps({**GOOD_RUN, "complete": 1}).encode()),
    ("samples an object", json.dumps({**GOOD_RUN, "samples": {"0": 1}}).encode()),
    ("a sample an array", json.dumps({**GOOD_RUN, "samples": [[1, 2]]}).encode()),
    ("a sample without its robot", json.dumps({**GOOD_RUN, "samples": [{"run": 0}]}).encode()),
    ("a sample's key unknown", json.dumps({**GOOD_RUN, "samples": [{**GOOD_RUN["samples"][0], "x": 1}]}).encode()),
    ("a sample's bool count",
     json.dumps({**GOOD_RUN, "samples": [{**GOOD_RUN["samples"][0], "percepts": True}]}).encode()),
]


def _scenario_dir(root: Path, run_file: bytes, marker: bytes | None = None) -> Path:
    out = root / "out"
    (out / "runs").mkdir(parents=True)
    marker = marker or json.dumps({"scenario": SCENARIO.name, "fingerprint": SCENARIO.fingerprint()}).encode()
    (out / "scenario.json").write_bytes(marker)
    (out / "runs" / "run_0000.json").write_bytes(run_file)
    return out


def test_a_sound_run_file_is_resumed_as_written(tmp_path: Path) -> None:
    out = _scenario_dir(tmp_path, json.dumps(GOOD_RUN).encode())
    outcome = RunStore(out, SCENARIO, resume=True, write=False).load()[0]
    assert (outcome.run, outcome.seed, outcome.complete, len(outcome.samples)) == (0, GOOD_RUN["seed"], True, 1)
    assert outcome.samples[0].percepts == 3 and math.isnan(outcome.samples[0].est_x)


@pytest.mark.parametrize("content", [c for _, c in DAMAGED_RUNS], ids=[n for n, _ in DAMAGED_RUNS])
def test_resume_refuses_a_damaged_run_file_naming_it(content: bytes, place: Path,
                                                     capsys: pytest.CaptureFixture[str]) -> None:
    out = _scenario_dir(place, content)
    before = snapshot(place)
    line = refused(["scenario", "1", "--resume", "--out", str(out), "--no-progress"], capsys)
    assert str(out / "runs" / "run_0000.json") in line and "--resume" in line
    assert snapshot(place) == before
    with pytest.raises(BatchError):
        RunStore(out, SCENARIO, resume=True, write=False)


@pytest.mark.parametrize("marker", [b"{", b"[]", b"\xff\xfe", b"null"])
def test_resume_refuses_a_damaged_marker_naming_it(marker: bytes, place: Path,
                                                   capsys: pytest.CaptureFixture[str]) -> None:
    out = _scenario_dir(place, json.dumps(GOOD_RUN).encode(), marker)
    before = snapshot(place)
    assert str(out / "scenario.json") in refused(["scenario", "1", "--resume", "--out", str(out)], capsys)
    assert snapshot(place) == before


def test_several_scenarios_are_all_checked_before_any_runs(place: Path, capsys: pytest.CaptureFixture[str]) -> None:
    damaged = place / "out" / "scenario_2"
    (damaged / "runs").mkdir(parents=True)
    spec = load_scenario("2")
    (damaged / "scenario.json").write_text(json.dumps({"scenario": spec.name, "fingerprint": spec.fingerprint()}))
    (damaged / "runs" / "run_0001.json").write_text("{", encoding="utf-8")
    before = snapshot(place)
    assert "run_0001.json" in refused(["scenario", "1", "2", "--resume", "--out", "out"], capsys)
    assert snapshot(place) == before  # scenario 1, named first, did not run


TOURNAMENT = TournamentSettings(("scripted", "stand"), 2, 2.0, 1, 0, False, (0.2, 0.4, 0.2))
TOURNAMENT_ARGS = ["tournament", "scripted", "stand", "--matches", "2", "--players", "1", "--half-seconds", "2",
                   "--pauses", "0.2,0.4,0.2", "--no-shootout", "--no-progress", "--workers", "1", "--resume"]


def _played(index: int = 0) -> dict:
    task = TOURNAMENT.tasks()[index]
    record = {"fingerprint": TOURNAMENT.fingerprint(), **match_record(task, TaskResult(task, error="x"))}
    record.update(status="ok", error=None, home_goals=1, away_goals=0, winner_side="home", sim_seconds=4.0,
                  wall_seconds=2.0, statistics={"home": {"goals": 1, "possession": 0.6}, "away": {"goals": 0}})
    return record


DAMAGED_MATCHES = [
    ("truncated", json.dumps(_played())[:40]),
    ("array", "[]"),
    ("status unknown", json.dumps({**_played(), "status": "won"})),
    ("status missing", json.dumps({k: v for k, v in _played().items() if k != "status"})),
    ("another policy", json.dumps({**_played(), "home_policy": "team"})),
    ("another seed", json.dumps({**_played(), "seed": 1})),
    ("goals as text", json.dumps({**_played(), "home_goals": "1"})),
    ("winner unknown", json.dumps({**_played(), "winner_side": "both"})),
    ("statistics an array", json.dumps({**_played(), "statistics": []})),
    ("a team's statistic as text", json.dumps({**_played(), "statistics": {"home": {"goals": "1"}, "away": {}}})),
    ("a team missing", json.dumps({**_played(), "statistics": {"home": {}}})),
]


def test_a_sound_match_record_is_resumed_as_written() -> None:
    assert stored_record(TOURNAMENT.tasks(), 0, _played()) == _played()
    with pytest.raises(ValueError, match="match 7"):
        stored_record(TOURNAMENT.tasks(), 7, {**_played(), "match": 7})


@pytest.mark.parametrize("content", [c for _, c in DAMAGED_MATCHES], ids=[n for n, _ in DAMAGED_MATCHES])
def test_resume_refuses_a_damaged_match_record_naming_it(content: str, place: Path,
                                                         capsys: pytest.CaptureFixture[str]) -> None:
    out = place / "out"
    (out / "runs").mkdir(parents=True)
    (out / "tournament.json").write_text(json.dumps({**TOURNAMENT.to_json(), "fingerprint": TOURNAMENT.fingerprint()}))
    (out / "runs" / "match_0000.json").write_text(content, encoding="utf-8")
    before = snapshot(place)
    line = refused([*TOURNAMENT_ARGS, "--out", str(out)], capsys)
    assert str(out / "runs" / "match_0000.json") in line
    assert snapshot(place) == before


DRILL = DrillSettings(Shooting(seconds=1), (("striker", "stand"), ("keeper", "stand")), trials=2, seed=0)
DRILL_ARGS = ["drill", "shooting", "--striker", "stand", "--keeper", "stand", "--seconds", "1", "--trials", "2",
              "--no-progress", "--workers", "1", "--resume"]


def _trial(index: int = 0) -> dict:
    record = TrialRecord(index, index, "ok", "none", {"ball_x": 1.5, "ball_y": -0.2, "time_s": 1.0}, 1.4, 0.6)
    return {"fingerprint": DRILL.fingerprint(), **record.to_json()}


DAMAGED_TRIALS = [
    ("truncated", json.dumps(_trial())[:40]),
    ("array", "[]"),
    ("deep", "[" * 100_000 + "]" * 100_000),
    ("status unknown", json.dumps({**_trial(), "status": "won"})),
    ("status missing", json.dumps({k: v for k, v in _trial().items() if k != "status"})),
    ("another seed", json.dumps({**_trial(), "seed": 7})),
    ("another trial's index", json.dumps({**_trial(), "trial": 1})),
    ("outcome unknown", json.dumps({**_trial(), "outcome": "won"})),
    ("outcome missing", json.dumps({k: v for k, v in _trial().items() if k != "outcome"})),
    ("a figure as text", json.dumps({**_trial(), "time_s": "1.0"})),
    ("a figure missing", json.dumps({k: v for k, v in _trial().items() if k != "ball_x"})),
    ("a figure not finite", json.dumps({**_trial(), "ball_y": float("inf")})),
    ("a huge number", '{"trial": 0, "seed": ' + "1" * 5000 + "}"),
    ("no attempts", json.dumps({**_trial(), "attempts": 0})),
    ("failed without its error", json.dumps({**_trial(), "status": "failed"})),
]


def _drill_dir(root: Path, content: str, marker: dict | None = None) -> Path:
    out = root / "out"
    (out / "runs").mkdir(parents=True)
    marker = marker or {**DRILL.to_json(), "fingerprint": DRILL.fingerprint()}
    (out / "drill.json").write_text(json.dumps(marker), encoding="utf-8")
    (out / "runs" / "trial_0000.json").write_text(content, encoding="utf-8")
    return out


def test_a_sound_trial_record_is_resumed_as_written(tmp_path: Path) -> None:
    record = stored_trial(DRILL.tasks(), 0, _trial())
    assert record.to_json() == {k: v for k, v in _trial().items() if k != "fingerprint"}
    with pytest.raises(ValueError, match="trial 7"):
        stored_trial(DRILL.tasks(), 7, {**_trial(), "trial": 7})


@pytest.mark.parametrize("content", [c for _, c in DAMAGED_TRIALS], ids=[n for n, _ in DAMAGED_TRIALS])
def test_resume_refuses_a_damaged_trial_record_naming_it(content: str, place: Path,
                                                         capsys: pytest.CaptureFixture[str]) -> None:
    out = _drill_dir(place, content)
    before = snapshot(place)
    line = refused([*DRILL_ARGS, "--out", str(out)], capsys)
    assert str(out / "runs" / "trial_0000.json") in line and "--resume" in line and len(line) < 400
    assert snapshot(place) == before


def test_resume_refuses_a_drill_of_other_settings_naming_both(place: Path, capsys: pytest.CaptureFixture[str]) -> None:
    other = DrillSettings(Shooting(seconds=2), DRILL.policies, trials=2, seed=0)
    out = _drill_dir(place, json.dumps(_trial()), {**other.to_json(), "fingerprint": other.fingerprint()})
    before = snapshot(place)
    line = refused([*DRILL_ARGS, "--out", str(out)], capsys)
    assert other.fingerprint() in line and DRILL.fingerprint() in line
    assert snapshot(place) == before
