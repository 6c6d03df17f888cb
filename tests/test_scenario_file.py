"""Scenario files: the built-in scenarios load, and every malformed file is a precise error."""

from __future__ import annotations

import dataclasses
import math
import pickle

import pytest

from agents.localization import LOCALIZERS
from scenarios.localization.file import (
    BUILTIN_SCENARIOS,
    ScenarioFileError,
    builtin_path,
    load_scenario,
    parse_scenario,
)
from scenarios.localization.batch import with_overrides
from scenarios.localization.spec import RobotEntry, ThesisReference

ALL_METHODS = ("thesis", "particle", "hybrid", "odometry")


def robot(agent: str, policy: str = "scan_localize", measured: bool = False, start: str | None = None) -> str:
    """One ``[[robots]]`` table as TOML text."""
    lines = ["[[robots]]", f'id = "{agent}"', f'policy = "{policy}"']
    if measured:
        lines.append("measured = true")
    if start is not None:
        lines.append(f"start = {start}")
    return "\n".join(lines) + "\n"


SOLO = robot("home_1", measured=True)
REFEREE_PAIR = robot("home_0", measured=True) + robot("away_0", "scripted")


def doc(top: str = "samples = 10", tables: str = "", robots: str = SOLO) -> str:
    """A scenario file: ``name``, the ``top`` lines, the ``tables`` and the robots."""
    return f'name = "test"\n{top}\n{tables}\n{robots}'


# --- the built-in scenarios ---------------------------------------------------------------

# name: (runs, referee, measured ids, number of robots, thesis row)
BUILTIN_EXPECTED = {
    "1": (5, False, ("home_1",), 1, (12.39, 2.83, 3.53, 2.86)),
    "2": (5, True, ("home_1",), 5, (27.83, 9.62, 16.32, 4.53)),
    "3": (2, True, ("home_1", "home_2", "home_3"), 8, (43.09, 12.69, 22.91, 11.20)),
}


@pytest.mark.parametrize("name", BUILTIN_SCENARIOS)
def test_builtin_scenarios_load_with_the_thesis_values(name):
    runs, referee, measured, n_robots, thesis = BUILTIN_EXPECTED[name]
    spec = load_scenario(name)
    assert builtin_path(name).is_file()
    assert spec.name == f"scenario {name}"
    assert spec.description
    assert (spec.samples, spec.runs, spec.seed) == (50, runs, 0)
    assert spec.methods == ALL_METHODS
    assert spec.camera_model == "exact"
    assert spec.referee is referee
    assert spec.measured == measured
    assert len(spec.robots) == n_robots
    assert spec.thesis == ThesisReference(*thesis)
    assert (spec.half_seconds, spec.motion_noise_scale, spec.max_sim_seconds_per_run) == (600.0, 1.0, 1200.0)
    assert all(r.policy == "scan_localize" for r in spec.robots if r.measured)
    assert all(r.start is None for r in spec.robots)
    assert load_scenario(builtin_path(name)) == spec


def test_builtin_robots_in_file_order():
    assert load_scenario("1").robots == (RobotEntry("home_1", "scan_localize", True, None),)
    spec = load_scenario("2")
    assert [r.id for r in spec.robots] == ["home_0", "home_1", "away_0", "away_1", "away_2"]
    assert [r.policy for r in spec.robots] == ["scripted", "scan_localize"] + ["scripted"] * 3
    spec = load_scenario("3")
    assert [r.id for r in spec.robots] == [f"home_{p}" for p in range(4)] + [f"away_{p}" for p in range(4)]


@pytest.mark.parametrize("name", BUILTIN_SCENARIOS)
def test_run_samples_and_seeds(name):
    spec = load_scenario(name)
    assert sum(spec.run_samples()) == spec.samples
    assert len(spec.run_samples()) == spec.runs
    assert max(spec.run_samples()) - min(spec.run_samples()) <= 1
    seeds = spec.run_seeds()
    assert seeds == load_scenario(name).run_seeds()
    assert len(seeds) == spec.runs and len(set(seeds)) == spec.runs
    # a run's seed does not depend on how many runs there are
    more = dataclasses.replace(spec, runs=spec.runs + 3)
    assert more.run_seeds()[: spec.runs] == seeds
    assert spec.fingerprint() == load_scenario(name).fingerprint()


# --- malformed files ----------------------------------------------------------------------

# (id, file text, the error's key, a fragment of the message showing the bad value)
MALFORMED = [
    ("unknown top-level key", doc('samples = 10\ncolour = "red"'), "colour", "got 'red'"),
    ("unknown key in noise", doc(tables="[noise]\nmotion_sigma = 0.5"), "noise.motion_sigma", "motion_scale"),
    ("samples zero", doc("samples = 0"), "samples", "got 0"),
    ("samples string", doc('samples = "50"'), "samples", "got '50'"),
    ("samples bool", doc("samples = true"), "samples", "got True"),
    ("samples float", doc("samples = 1.5"), "samples", "got 1.5"),
    ("samples missing", doc("runs = 1"), "samples", "missing"),
    ("runs above samples", doc("samples = 3\nruns = 4"), "runs", "got 4"),
    ("unknown method", doc('samples = 10\nmethods = ["thesis", "kalman"]'), "methods[1]", "got 'kalman'"),
    ("duplicate method", doc('samples = 10\nmethods = ["thesis", "hybrid", "thesis"]'), "methods[2]", "got 'thesis'"),
    ("empty methods", doc("samples = 10\nmethods = []"), "methods", "got []"),
    ("bad camera model", doc('samples = 10\ncamera_model = "fisheye"'), "camera_model", "got 'fisheye'"),
    ("bad camera profile", doc('samples = 10\ncamera_profile = "webcam"'), "camera_profile", "got 'webcam'"),
    ("camera profile not a string", doc("samples = 10\ncamera_profile = 1"), "camera_profile", "got 1"),
    ("nan half_seconds", doc(tables="[match]\nhalf_seconds = nan"), "match.half_seconds", "got nan"),
    ("negative motion_scale", doc(tables="[noise]\nmotion_scale = -0.5"), "noise.motion_scale", "got -0.5"),
    ("negative warmup", doc(tables="[limits]\nwarmup_seconds = -1"), "limits.warmup_seconds", "got -1"),
    (
        "warmup beyond the run",
        doc(tables="[limits]\nmax_sim_seconds_per_run = 100\nwarmup_seconds = 100"),
        "limits.warmup_seconds",
        "got 100.0",
    ),
    ("bad robot id", doc(robots=robot("home_7", measured=True)), "robots[0].id", "got 'home_7'"),
    ("duplicate robot id", doc(robots=SOLO + robot("home_1")), "robots[1].id", "got 'home_1'"),
    ("unknown policy", doc(robots=robot("home_1", "dance", measured=True)), "robots[0].policy", "got 'dance'"),
    ("no measured robot", doc(robots=robot("home_1")), "robots", "got ['home_1']"),
    (
        "measured scripted robot",
        doc("samples = 10\nreferee = true", robots=robot("home_0", "scripted", measured=True) + robot("away_0", "scripted")),
        "robots[0].measured",
        "got True",
    ),
    (
        "start with referee",
        doc("samples = 10\nreferee = true", robots=robot("home_0", measured=True, start="[1.0, 0.0, 0.0]")),
        "robots[0].start",
        "got [1.0, 0.0, 0.0]",
    ),
    (
        "start off the field",
        doc(robots=robot("home_1", measured=True, start="[3.5, 0.0, 0.0]")),
        "robots[0].start",
        "got [3.5, 0.0, 0.0]",
    ),
    ("start with 2 numbers", doc(robots=robot("home_1", measured=True, start="[0.5, 1.0]")), "robots[0].start", "got [0.5, 1.0]"),
    ("start other text", doc(robots=robot("home_1", measured=True, start='"centre"')), "robots[0].start", "got 'centre'"),
    (
        "policy path that does not import",
        doc(robots=SOLO + robot("away_0", "tests.no_such_module:Striker")),
        "robots[1].policy",
        "got 'tests.no_such_module:Striker'",
    ),
    (
        "referee numbering gap",
        doc(
            "samples = 10\nreferee = true", robots=robot("home_0", measured=True) + robot("home_2") + robot("away_0", "scripted")
        ),
        "robots",
        "got ['home_0', 'home_2', 'away_0']",
    ),
    (
        "referee only home robots",
        doc("samples = 10\nreferee = true", robots=robot("home_0", measured=True) + robot("home_1", "scripted")),
        "robots",
        "got ['home_0', 'home_1']",
    ),
    (
        "thesis missing a key",
        doc(tables="[thesis]\nposition_mean_cm = 1.0\nposition_ci95_cm = 1.0\norientation_mean_deg = 1.0"),
        "thesis.orientation_ci95_deg",
        "missing",
    ),
    ("unknown robot key", doc(robots=SOLO + "colour = 'red'\n"), "robots[0].colour", "got 'red'"),
    ("no robots", doc(robots=""), "robots", "got nothing"),
    ("toml syntax error", "name = 'test'\nsamples = \n", "<syntax>", "line 2"),
]


@pytest.mark.parametrize(("text", "key", "fragment"), [case[1:] for case in MALFORMED], ids=[case[0] for case in MALFORMED])
def test_malformed_file_is_a_precise_error(tmp_path, text, key, fragment):
    path = tmp_path / "bad.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(ScenarioFileError) as caught:
        load_scenario(path)
    error = caught.value
    assert error.key == key
    message = str(error)
    assert message.startswith(f"{path}: {key}: expected ")
    assert fragment in message


def test_unknown_key_lists_the_allowed_keys(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(doc('samples = 10\ncolour = "red"'), encoding="utf-8")
    with pytest.raises(ScenarioFileError, match="colour") as caught:
        load_scenario(path)
    assert all(k in caught.value.expected for k in ("name", "samples", "methods", "robots", "thesis"))


def test_unknown_method_lists_the_methods(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(doc('samples = 10\nmethods = ["kalman"]'), encoding="utf-8")
    with pytest.raises(ScenarioFileError) as caught:
        load_scenario(path)
    assert all(name in caught.value.expected for name in LOCALIZERS)


@pytest.mark.parametrize("name", ["missing.toml", "4"])
def test_missing_file(tmp_path, monkeypatch, name):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(ScenarioFileError) as caught:
        load_scenario(name)
    assert caught.value.key == "<file>"
    assert caught.value.got == name
    assert name in str(caught.value) and "1, 2, 3" in str(caught.value)


def test_missing_file_by_path(tmp_path):
    path = tmp_path / "nowhere" / "scenario.toml"
    with pytest.raises(ScenarioFileError) as caught:
        load_scenario(path)
    assert caught.value.key == "<file>"
    assert str(path) in str(caught.value)


def test_error_attributes_and_pickling():
    error = ScenarioFileError("f.toml", "samples", "an integer >= 1", 0)
    assert str(error) == "f.toml: samples: expected an integer >= 1, got 0"
    assert isinstance(error, ValueError)
    again = pickle.loads(pickle.dumps(error))
    assert (again.path, again.key, again.expected, again.got, str(again)) == (
        "f.toml",
        "samples",
        "an integer >= 1",
        0,
        str(error),
    )


# --- valid files written by a user ------------------------------------------------------


def test_user_file_with_fixed_start(tmp_path):
    path = tmp_path / "mine.toml"
    text = doc(
        "samples = 7\nruns = 3\nseed = 12345\nmethods = ['odometry', 'thesis']\ncamera_model = 'thesis'",
        tables="[noise]\nmotion_scale = 0\n[limits]\nmax_sim_seconds_per_run = 300",
        robots=robot("away_2", measured=True, start="[0.5, -1.0, 90]") + robot("home_0", "stand"),
    )
    path.write_text(text, encoding="utf-8")
    spec = load_scenario(str(path))
    assert (spec.samples, spec.runs, spec.seed) == (7, 3, 12345)
    assert spec.methods == ("odometry", "thesis")
    assert spec.camera_model == "thesis"
    assert spec.motion_noise_scale == 0.0 and isinstance(spec.motion_noise_scale, float)
    assert spec.max_sim_seconds_per_run == 300.0
    assert spec.thesis is None
    start = spec.robots[0].start
    assert (start.x, start.y) == (0.5, -1.0)
    assert start.theta == pytest.approx(math.pi / 2)
    assert spec.robots[1] == RobotEntry("home_0", "stand", False, None)
    assert spec.run_samples() == (3, 2, 2)
    assert spec.camera_profile == "robotstadium"  # the default


def test_a_file_chooses_the_camera_profile_and_the_command_line_overrides_it(tmp_path):
    path = tmp_path / "nao.toml"
    path.write_text(doc('samples = 5\ncamera_profile = "nao"'), encoding="utf-8")
    spec = load_scenario(path)
    assert spec.camera_profile == "nao"
    assert spec.fingerprint() != dataclasses.replace(spec, camera_profile="clean").fingerprint()
    assert with_overrides(spec, camera_profile="robotstadium").camera_profile == "robotstadium"
    assert with_overrides(spec).camera_profile == "nao"


def test_defaults_of_a_minimal_file():
    spec = parse_scenario(
        {"name": "min", "samples": 4, "robots": [{"id": "home_3", "policy": "scan_localize", "measured": True}]},
        "min.toml",
    )
    assert spec.description == ""
    assert (spec.runs, spec.seed, spec.referee, spec.camera_model) == (1, 0, False, "exact")
    assert spec.methods == tuple(LOCALIZERS)
    assert (spec.half_seconds, spec.motion_noise_scale, spec.max_sim_seconds_per_run) == (600.0, 1.0, 1200.0)
    assert spec.thesis is None
    assert spec.robots == (RobotEntry("home_3", "scan_localize", True, None),)


@pytest.mark.parametrize(("seed", "ok"), [(0, True), (2**63 - 1, True), (-1, False), (2**63, False), (1.0, False)])
def test_seed_range(seed, ok):
    data = {"name": "s", "samples": 1, "seed": seed, "robots": [{"id": "home_1", "policy": "scan_localize", "measured": True}]}
    if ok:
        assert parse_scenario(data, "s.toml").seed == seed
    else:
        with pytest.raises(ScenarioFileError) as caught:
            parse_scenario(data, "s.toml")
        assert caught.value.key == "seed"


@pytest.mark.parametrize("value", [float("inf"), True, "600", 0, -1.0])
def test_half_seconds_rejects(value):
    data = {
        "name": "h",
        "samples": 1,
        "match": {"half_seconds": value},
        "robots": [{"id": "home_1", "policy": "scan_localize", "measured": True}],
    }
    with pytest.raises(ScenarioFileError) as caught:
        parse_scenario(data, "h.toml")
    assert caught.value.key == "match.half_seconds"
    assert caught.value.got is value


def test_full_referee_teams_load():
    robots = [{"id": "home_0", "policy": "scan_localize", "measured": True}]
    robots += [{"id": f"away_{p}", "policy": "scripted"} for p in range(4)]
    spec = parse_scenario({"name": "r", "samples": 2, "referee": True, "robots": robots}, "r.toml")
    assert spec.referee and len(spec.robots) == 5
