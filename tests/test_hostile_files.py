"""Hostile files under the names a command reads: a match directory for ``replay``, run records for
``--resume`` (tournaments and scenarios) and scenario files.

Each case ends with exit code 2 and one line on stderr naming the file and the field, no
traceback, nothing written or rewritten (every path under the directory keeps its bytes, link
target and modification time), in under 2 s; all of them together, one after the other in a
fresh process, raise its peak memory by less than 64 MB over what its imports take. The files are links to ``/dev/zero`` or pipes, JSON nested 100,000 levels
deep, an array header claiming a terabyte, numbers of thousands of digits, values out of range
or in disagreement with each other.
"""

from __future__ import annotations

import io
import json
import math
import os
import subprocess
import sys
import time
import zipfile
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

from scenarios import cli
from scenarios.replay.synthetic import synthetic_match
from tests.test_cli_refusals import GOOD_RUN, SCENARIO, TOURNAMENT, TOURNAMENT_ARGS, _played

SECONDS_PER_CASE = 2.0
GROWTH_MB = 64.0
DEEP = b"[" * 100_000 + b"]" * 100_000
LONG_NUMBER = "9" * 5000


def _fifo(path: Path) -> None:
    path.unlink(missing_ok=True)
    os.mkfifo(path)  # opening it to read would wait for a writer


def _zero(path: Path) -> None:
    path.unlink(missing_ok=True)
    path.symlink_to("/dev/zero")  # it never ends


# ---- a match directory for replay ------------------------------------------------------------------


def _match(root: Path) -> Path:
    return synthetic_match(root / "m", half_seconds=4.0, estimators=("home_0",))


def _events(change: Callable[[list[dict]], object]) -> Callable[[Path], Path]:
    def setup(root: Path) -> Path:
        directory = _match(root)
        path = directory / "events.jsonl"
        events = [json.loads(line) for line in path.read_text().splitlines()]
        lines = change(events)
        path.write_text(lines if isinstance(lines, str) else "\n".join(json.dumps(e) for e in events) + "\n")
        return directory
    return setup


def _summary(change: Callable[[dict], object]) -> Callable[[Path], Path]:
    def setup(root: Path) -> Path:
        directory = _match(root)
        path = directory / "summary.json"
        summary = json.loads(path.read_text())
        text = change(summary)
        path.write_text(text if isinstance(text, str) else json.dumps(summary))
        return directory
    return setup


def _replace(name: str, make: Callable[[Path], None]) -> Callable[[Path], Path]:
    def setup(root: Path) -> Path:
        directory = _match(root)
        make(directory / name)
        return directory
    return setup


def _npz_members(path: Path, members: dict[str, bytes]) -> None:
    with zipfile.ZipFile(path) as archive:
        kept = {info.filename: archive.read(info) for info in archive.infolist()}
    path.unlink()
    with zipfile.ZipFile(path, "w") as archive:
        for name, data in {**kept, **members}.items():
            archive.writestr(name, data)


def _npy_header(shape: tuple[int, ...], descr: str = "<f4") -> bytes:
    buffer = io.BytesIO()
    np.lib.format.write_array_header_1_0(buffer, {"descr": descr, "fortran_order": False, "shape": shape})
    return buffer.getvalue() + bytes(64)  # a few bytes of data, far fewer than the header claims


def _npy(array: np.ndarray) -> bytes:
    buffer = io.BytesIO()
    np.save(buffer, array, allow_pickle=True)
    return buffer.getvalue()


def _npz(members: Callable[[Path], dict[str, bytes]]) -> Callable[[Path], Path]:
    def setup(root: Path) -> Path:
        directory = _match(root)
        _npz_members(directory / "match_log.npz", members(directory))
        return directory
    return setup


def _half(value: float) -> Callable[[Path], dict[str, bytes]]:
    def members(directory: Path) -> dict[str, bytes]:
        with np.load(directory / "match_log.npz") as log:
            half = log["half"].astype(np.float64)
        half[len(half) // 2] = value
        return {"half.npy": _npy(half)}
    return members


def _set_at(events: list[dict], index: int, **values) -> None:
    events[index].update(values)


def _long_time(events: list[dict]) -> str:
    lines = [json.dumps(e) for e in events]
    lines[3] = lines[3].replace(f'"time_s": {json.dumps(events[3]["time_s"])}', f'"time_s": {LONG_NUMBER}', 1)
    return "\n".join(lines) + "\n"


REPLAY = [
    ("events nested 100,000 deep", _events(lambda e: DEEP.decode() + "\n"), ["events.jsonl", "nested deeper"]),
    ("summary nested 100,000 deep", _summary(lambda s: DEEP.decode()), ["summary.json", "nested deeper"]),
    ("robots header of a terabyte", _npz(lambda d: {"robots.npy": _npy_header((10**12, 4, 3))}),
     ["match_log.npz", "robots", "(1000000000000, 4, 3)"]),
    ("time header of a terabyte", _npz(lambda d: {"time_s.npy": _npy_header((10**12,), "<f8")}),
     ["match_log.npz", "time_s", "1000000000000"]),
    ("a pickled array", _npz(lambda d: {"extra.npy": _npy(np.array([{"a": 1}], dtype=object))}),
     ["match_log.npz", "array extra", "Python objects"]),
    ("100 arrays", _npz(lambda d: {f"x{i}.npy": _npy(np.zeros(1)) for i in range(100)}),
     ["match_log.npz", "arrays, more than 64"]),
    ("half of 1.7 in the log", _npz(_half(1.7)), ["match_log.npz", "half", "float64", "integers"]),
    ("time_s as text", _events(lambda e: _set_at(e, 3, time_s="1.0")), ["events.jsonl", "line 4", "time_s"]),
    ("time_s of 5,000 digits", _events(_long_time), ["events.jsonl", "line 4", "time_s", "5000 digits"]),
    ("time_s negative", _events(lambda e: _set_at(e, 3, time_s=-1.0)), ["events.jsonl", "line 4", "time_s"]),
    ("time_s of 399 digits", _events(lambda e: _set_at(e, 3, time_s=10**398)), ["events.jsonl", "line 4", "time_s"]),
    ("sim_seconds of 399 digits", _summary(lambda s: s.update(sim_seconds=10**398)), ["summary.json", "sim_seconds"]),
    ("a detail NaN in an event", _events(lambda e: _set_at(e, 2, x=math.nan)), ["events.jsonl", "line 3", "x = NaN"]),
    ("half of 1.7 in an event", _events(lambda e: _set_at(e, 0, half=1.7)), ["events.jsonl", "line 1", "half"]),
    ("a goal tally of 10**30", _events(lambda e: _set_at(e, 0, score={"home": 10**30, "away": 0})),
     ["events.jsonl", "line 1", "score.home"]),
    ("summary linked to /dev/zero", _replace("summary.json", _zero), ["summary.json", "not an existing regular file"]),
    ("events linked to /dev/zero", _replace("events.jsonl", _zero), ["events.jsonl", "not an existing regular file"]),
    ("log linked to /dev/zero", _replace("match_log.npz", _zero), ["match_log.npz", "not an existing regular file"]),
    ("summary a pipe", _replace("summary.json", _fifo), ["summary.json", "not an existing regular file"]),
    ("events a pipe", _replace("events.jsonl", _fifo), ["events.jsonl", "not an existing regular file"]),
    ("log a pipe", _replace("match_log.npz", _fifo), ["match_log.npz", "not an existing regular file"]),
    ("goals -5", _summary(lambda s: s.update(score={"home": -5, "away": 0})), ["summary.json", "score"]),
    ("0-3 recorded as a home win", _summary(lambda s: s.update(score={"home": 0, "away": 3}, winner="home")),
     ["summary.json", "winner", "0-3"]),
    ("sim_seconds NaN", _summary(lambda s: s.update(sim_seconds=math.nan)), ["summary.json", "sim_seconds"]),
    ("seed of 5,000 digits", _summary(lambda s: s.__setitem__("seed", -1) or json.dumps(s).replace(
        '"seed": -1', f'"seed": {LONG_NUMBER}')), ["summary.json", "seed", "5000 digits"]),
    ("half_seconds NaN", _summary(lambda s: s["config"].update(half_seconds=math.nan)),
     ["summary.json", "config.half_seconds"]),
]


# ---- run records for --resume ----------------------------------------------------------------------


def _tournament(record: object, marker: Callable[[Path], None] | None = None) -> Callable[[Path], Path]:
    def setup(root: Path) -> Path:
        out = root / "out"
        (out / "runs").mkdir(parents=True)
        (out / "tournament.json").write_text(json.dumps({**TOURNAMENT.to_json(),
                                                         "fingerprint": TOURNAMENT.fingerprint()}))
        path = out / "runs" / "match_0000.json"
        if callable(record):
            record(path)
        else:
            path.write_text(record if isinstance(record, str) else json.dumps(record), encoding="utf-8")
        if marker is not None:
            marker(out / "tournament.json")
        return out
    return setup


def _scenario(run: object, marker: Callable[[Path], None] | None = None) -> Callable[[Path], Path]:
    def setup(root: Path) -> Path:
        out = root / "out"
        (out / "runs").mkdir(parents=True)
        (out / "scenario.json").write_text(json.dumps({"scenario": SCENARIO.name,
                                                       "fingerprint": SCENARIO.fingerprint()}))
        path = out / "runs" / "run_0000.json"
        if callable(run):
            run(path)
        else:
            path.write_text(run if isinstance(run, str) else json.dumps(run), encoding="utf-8")
        if marker is not None:
            marker(out / "scenario.json")
        return out
    return setup


def _sample(**values) -> dict:
    return {**GOOD_RUN, "samples": [{**GOOD_RUN["samples"][0], **values}]}


RESUME = [
    ("record nested 100,000 deep", _tournament(DEEP.decode()), ["match_0000.json", "nested deeper"]),
    ("record linked to /dev/zero", _tournament(_zero), ["match_0000.json", "not an existing regular file"]),
    ("record a pipe", _tournament(_fifo), ["match_0000.json", "not an existing regular file"]),
    ("marker linked to /dev/zero", _tournament(_played(), _zero), ["tournament.json", "not an existing regular file"]),
    ("marker a pipe", _tournament(_played(), _fifo), ["tournament.json", "not an existing regular file"]),
    ("home_goals 10**30", _tournament({**_played(), "home_goals": 10**30}), ["match_0000.json", "home_goals"]),
    ("home_goals of 5,000 digits", _tournament(json.dumps(_played()).replace('"home_goals": 1',
                                                                             f'"home_goals": {LONG_NUMBER}')),
     ["match_0000.json", "home_goals", "5000 digits"]),
    ("home_goals of 399 digits", _tournament({**_played(), "home_goals": 10**398}), ["match_0000.json", "home_goals"]),
    ("a statistic of 399 digits", _tournament({**_played(), "statistics": {"home": {"touches": 10**398}, "away": {}}}),
     ["match_0000.json", "statistics.home.touches"]),
    ("goals -5", _tournament({**_played(), "away_goals": -5}), ["match_0000.json", "away_goals"]),
    ("0-3 recorded as a home win", _tournament({**_played(), "home_goals": 0, "away_goals": 3}),
     ["match_0000.json", "winner_side", "0-3"]),
    ("a shoot-out after 1-0", _tournament({**_played(), "home_shootout": 3, "away_shootout": 2}),
     ["match_0000.json", "shoot-out after 1-0"]),
    ("sim_seconds NaN", _tournament(json.dumps({**_played(), "sim_seconds": math.nan})),
     ["match_0000.json", "sim_seconds"]),
    ("a statistic of 1e300", _tournament({**_played(), "statistics": {"home": {"touches": 1e300}, "away": {}}}),
     ["match_0000.json", "statistics.home.touches"]),
    ("scenario run nested 100,000 deep", _scenario(DEEP.decode()), ["run_0000.json", "nested deeper"]),
    ("scenario run linked to /dev/zero", _scenario(_zero), ["run_0000.json", "not an existing regular file"]),
    ("scenario run a pipe", _scenario(_fifo), ["run_0000.json", "not an existing regular file"]),
    ("scenario marker a pipe", _scenario(GOOD_RUN, _fifo), ["scenario.json", "not an existing regular file"]),
    ("scenario sim_seconds NaN", _scenario(json.dumps({**GOOD_RUN, "sim_seconds": math.nan})),
     ["run_0000.json", "sim_seconds"]),
    ("a sample's position 1e300", _scenario(_sample(true_x=1e300)), ["run_0000.json", "samples[0].true_x"]),
    ("a sample of another run", _scenario(_sample(run=3)), ["run_0000.json", "samples[0].run"]),
    ("a sample's count of 399 digits", _scenario(_sample(percepts=10**398)), ["run_0000.json", "samples[0].percepts"]),
]


# ---- scenario files ----------------------------------------------------------------------------------

SCENARIO_TEXT = 'name = "t"\nsamples = 2\n[[robots]]\nid = "home_1"\npolicy = "scan_localize"\nmeasured = true\n'


def _scenario_file(make: Callable[[Path], None] | str) -> Callable[[Path], Path]:
    def setup(root: Path) -> Path:
        path = root / "bad.toml"
        if callable(make):
            make(path)
        else:
            path.write_text(make, encoding="utf-8")
        return path
    return setup


FILES = [
    ("a key of 20,000 dotted parts", _scenario_file("a" + ".a" * 19_999 + " = 1\n" + SCENARIO_TEXT),
     ["bad.toml", "<syntax>", "dotted parts"]),
    ("a table header of 20,000 parts", _scenario_file("[" + "a." * 19_999 + "a]\nb = 1\n" + SCENARIO_TEXT),
     ["bad.toml", "<syntax>", "dotted parts"]),
    ("arrays nested 100,000 deep", _scenario_file("x = " + DEEP.decode() + "\n" + SCENARIO_TEXT),
     ["bad.toml", "<syntax>"]),
    ("linked to /dev/zero", _scenario_file(_zero), ["bad.toml", "<file>"]),
    ("a pipe", _scenario_file(_fifo), ["bad.toml", "<file>"]),
    ("a function as policy", _scenario_file(SCENARIO_TEXT.replace("scan_localize", "os:system")),
     ["bad.toml", "robots[0].policy", "not a policy class"]),
]

SCENARIO_RESUME = ["scenario", "1", "--resume", "--out", "out", "--no-progress"]
TOURNAMENT_RESUME = [*TOURNAMENT_ARGS, "--out", "out"]
CASES = ([(name, setup, words, ["replay", "m"]) for name, setup, words in REPLAY]
         + [(name, setup, words, SCENARIO_RESUME if "run_0000.json" in words or "scenario.json" in words
             else TOURNAMENT_RESUME) for name, setup, words in RESUME]
         + [(name, setup, words, ["scenario", "bad.toml", "--out", "out"]) for name, setup, words in FILES])


def snapshot(root: Path) -> dict[str, object]:
    """Every path under ``root``: its bytes (a regular file), its target (a link) or its kind, and its
    modification time; a pipe or a device is never opened."""
    found: dict[str, object] = {}
    for directory, dirs, files in os.walk(root):
        for name in dirs + files:
            path = Path(directory) / name
            info = path.lstat()
            if path.is_symlink():
                content: object = os.readlink(path)
            elif path.is_file():
                content = path.read_bytes()
            else:
                content = "directory" if path.is_dir() else "other"
            found[str(path.relative_to(root))] = (content, info.st_mtime_ns)
    return found


def refusal(argv: list[str]) -> tuple[int, str]:
    """The exit code and the stderr of one command, run in this process (a pipe must not block it)."""
    from contextlib import redirect_stderr, redirect_stdout

    err, out = io.StringIO(), io.StringIO()
    with redirect_stderr(err), redirect_stdout(out):
        try:
            code = cli.main(argv)
        except SystemExit as exit_info:
            code = exit_info.code
    return code, err.getvalue()


@pytest.mark.parametrize(("setup", "words", "argv"), [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_a_hostile_file_is_refused_in_one_line_naming_it_at_once_and_nothing_is_written(
        setup, words: list[str], argv: list[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    setup(tmp_path)
    before = snapshot(tmp_path)
    started = time.perf_counter()
    code, err = refusal(argv)
    seconds = time.perf_counter() - started
    assert code == cli.EXIT_USAGE, err
    assert "Traceback" not in err
    lines = err.splitlines()
    assert len(lines) == 1 and err.endswith("\n") and len(lines[0]) < 600, err
    assert lines[0].startswith(f"robotstadium {argv[0]}: error: ")
    for word in words:
        assert word in lines[0], (word, lines[0])
    assert snapshot(tmp_path) == before
    assert seconds < SECONDS_PER_CASE, seconds


def peak_megabytes(root: Path) -> tuple[float, float]:
    """The peak resident memory (MB) of this process (a fresh one) with every reader imported, and after
    every case was refused in turn."""
    import resource

    import scenarios.localization.batch  # noqa: F401 - what the commands import when they run
    import scenarios.replay.record  # noqa: F401
    import scenarios.tournament.run  # noqa: F401

    def peak() -> float:
        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024

    imported = peak()
    for index, (_, setup, _, argv) in enumerate(CASES):
        place = root / str(index)
        place.mkdir()
        os.chdir(place)
        setup(place)
        code, err = refusal(argv)
        assert code == cli.EXIT_USAGE, err
    return imported, peak()


def test_all_hostile_files_together_cost_little_memory(tmp_path: Path) -> None:
    program = ("import sys; from pathlib import Path; from tests.test_hostile_files import peak_megabytes; "
               "print(*peak_megabytes(Path(sys.argv[1])))")
    done = subprocess.run([sys.executable, "-c", program, str(tmp_path)], capture_output=True, text=True,
                          cwd=Path(__file__).parents[1], timeout=120, check=False)
    assert done.returncode == 0, done.stderr[-2000:]
    imported, peak = map(float, done.stdout.split()[-2:])
    assert peak - imported < GROWTH_MB, (imported, peak)
