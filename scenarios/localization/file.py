"""Scenario files: the TOML format of thesis chapter 6's scenarios and its strict loader.

A scenario file names the robots, which of them are measured, the localization methods
and how many samples to take. ``scenario_1.toml`` .. ``scenario_3.toml`` in the
:mod:`scenarios` package are the built-in scenarios and, commented, the format's documentation;
``scenario_3_match.toml`` (name ``3-match``) is scenario 3 in its literal sense, team agents
measured while they play a refereed game, sampled every second of PLAYING time (its
``[sampling]`` table). :func:`load_scenario` reads a built-in name or a path;
:func:`parse_scenario` validates already-parsed data. Every mistake is a
:class:`ScenarioFileError` naming the file, the key, what was expected and what was found;
unknown keys are mistakes too.

Every value is bounded, so that a file that loads also runs: a file is at most
:data:`MAX_FILE_BYTES` and has keys of at most :data:`~agents.toml_text.MAX_KEY_PARTS` dotted
parts (both checked before it is parsed), nested no deeper than the TOML parser can follow;
``samples`` at most :data:`~scenarios.common.limits.MAX_SAMPLES`;
``name`` at most :data:`MAX_NAME_CHARS` characters, ``description`` :data:`MAX_DESCRIPTION_CHARS`,
a policy name :data:`MAX_POLICY_CHARS`; ``half_seconds`` 1 s .. 1 day; ``motion_scale``
0 .. :data:`MAX_MOTION_SCALE`; ``max_sim_seconds_per_run`` in :data:`SIM_SECONDS_RANGE`,
``warmup_seconds`` from 0 to below it; ``period_seconds`` in :data:`PERIOD_SECONDS_RANGE`;
the thesis' figures 0 .. :data:`MAX_THESIS_FIGURE`; a start heading within ±360 degrees.
"""

from __future__ import annotations

import functools
import logging
import math
import reprlib
import tomllib
from pathlib import Path
from typing import NoReturn

from agents.localization import LOCALIZERS
from agents.policies import PolicyNameError, known_policies, policy_factory
from agents.toml_text import MAX_KEY_PARTS, TomlBoundsError, load_toml
from agents.vision.camera_models import CAMERA_MODELS
from match.protocol.ids import MAX_PLAYERS_PER_TEAM, AgentId, Side
from scenarios.common.untrusted import SmallFileError, read_small_file
from scenarios.common.limits import HALF_SECONDS_MAX, HALF_SECONDS_MIN, MAX_SAMPLES
from scenarios.localization.spec import MEASURABLE_POLICIES, RobotEntry, ScenarioSpec, ThesisReference
from world.field import FIELD, Pose2D
from world.camera_profiles import CAMERA_PROFILES, DEFAULT_CAMERA_PROFILE

log = logging.getLogger(__name__)

BUILTIN_SCENARIOS: tuple[str, ...] = ("1", "2", "3")  # the thesis' scenarios as the thesis ran them
PLAYING_SCENARIOS: tuple[str, ...] = ("3-match",)  # measured while they play (periodic sampling)
NAMED_SCENARIOS: tuple[str, ...] = BUILTIN_SCENARIOS + PLAYING_SCENARIOS  # every name load_scenario knows

_TOP_KEYS = (
    "name",
    "description",
    "samples",
    "runs",
    "seed",
    "methods",
    "camera_model",
    "camera_profile",
    "referee",
    "match",
    "noise",
    "limits",
    "thesis",
    "sampling",
    "robots",
)
_MATCH_KEYS = ("half_seconds",)
_NOISE_KEYS = ("motion_scale",)
_LIMITS_KEYS = ("max_sim_seconds_per_run", "warmup_seconds")
_SAMPLING_KEYS = ("period_seconds",)
_EVENT_ONLY_KEYS = ("methods", "camera_model")  # they configure the scan-localize robots' side-by-side methods
_THESIS_KEYS = ("position_mean_cm", "position_ci95_cm", "orientation_mean_deg", "orientation_ci95_deg")
_ROBOT_KEYS = ("id", "policy", "measured", "start")
_SEED_LIMIT = 2**63
MAX_FILE_BYTES = 1_000_000
MAX_NAME_CHARS = 200
MAX_DESCRIPTION_CHARS = 4_000
MAX_POLICY_CHARS = 200  # a built-in name or package.module:ClassName
MAX_MOTION_SCALE = 5.0  # the noise's truncation (12.5 % at 1) reaches 62.5 % of a motion
SIM_SECONDS_RANGE = (10.0, 172_800.0)  # a run's simulated time: a move, a scan and a localization .. 2 days
PERIOD_SECONDS_RANGE = (0.04, 3_600.0)  # one control step .. an hour
MAX_THESIS_FIGURE = 10_000.0  # cm or degrees
MAX_START_DEG = 360.0
_SHOWN = reprlib.Repr()  # how a message shows a value: long strings, lists and deep nesting cut short
_SHOWN.maxstring = _SHOWN.maxother = 80
_SHOWN.maxlist = _SHOWN.maxdict = 10
_ID_TEXT = f"an agent id: home_0..home_{MAX_PLAYERS_PER_TEAM - 1} or away_0..away_{MAX_PLAYERS_PER_TEAM - 1}"


class ScenarioFileError(ValueError):
    """A scenario file that cannot be used: ``"{path}: {key}: expected {expected}, got {got!r}"``."""

    def __init__(self, path: str | Path, key: str, expected: str, got: object) -> None:
        super().__init__(f"{path}: {key}: expected {expected}, got {_SHOWN.repr(got)}")
        self.path = path
        self.key = key
        self.expected = expected
        self.got = got

    def __reduce__(self):
        return type(self), (self.path, self.key, self.expected, self.got)


class _Missing:
    """Stands for a key the file does not give."""

    def __repr__(self) -> str:
        return "nothing (the key is missing)"


_MISSING = _Missing()


def builtin_path(name: str) -> Path:
    """The file of the built-in scenario ``name`` (one of :data:`NAMED_SCENARIOS`): ``scenario_1.toml``,
    ..., ``scenario_3_match.toml`` for ``3-match``."""
    if name not in NAMED_SCENARIOS:
        raise ValueError(f"built-in scenario {name!r} is not one of {', '.join(NAMED_SCENARIOS)}")
    return Path(__file__).parents[1] / f"scenario_{name.replace('-', '_')}.toml"  # package data of scenarios


def load_scenario(name_or_path: str | Path) -> ScenarioSpec:
    """The scenario of a built-in name (``"1"``, ``"2"``, ``"3"``, ``"3-match"``) or of a TOML file's path."""
    if isinstance(name_or_path, str) and name_or_path in NAMED_SCENARIOS:
        path = builtin_path(name_or_path)
    else:
        path = Path(name_or_path)
    data = _read_toml(path, str(name_or_path))
    spec = parse_scenario(data, str(path))
    log.info(
        "scenario %r from %s: %d samples over %d runs, measured %s",
        spec.name,
        path,
        spec.samples,
        spec.runs,
        ", ".join(spec.measured),
    )
    return spec


def _read_toml(path: Path, given: str) -> dict:
    """The parsed TOML of ``path``: a regular file of at most :data:`MAX_FILE_BYTES`, UTF-8, valid, with keys
    of a bounded number of parts and not nested deeper than the parser can follow
    (:func:`agents.toml_text.load_toml`); a :class:`ScenarioFileError` naming the file otherwise."""
    expected_file = f"an existing scenario file or one of {', '.join(NAMED_SCENARIOS)}"
    try:
        raw = read_small_file(path, MAX_FILE_BYTES)
    except SmallFileError as exc:
        if exc.too_big:
            raise ScenarioFileError(path, "<file>", f"a scenario file of at most {MAX_FILE_BYTES} bytes",
                                    exc.reason) from None
        raise ScenarioFileError(path, "<file>", expected_file, given if exc.missing else exc.reason) from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ScenarioFileError(path, "<syntax>", "a UTF-8 text file", str(exc)) from exc
    try:
        return load_toml(text)
    except TomlBoundsError as exc:
        raise ScenarioFileError(path, "<syntax>", f"arrays and tables nested a few levels deep, keys of at most "
                                f"{MAX_KEY_PARTS} dotted parts", str(exc)) from None
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioFileError(path, "<syntax>", "valid TOML", str(exc)) from None


def parse_scenario(data: dict, path: str) -> ScenarioSpec:
    """The scenario of a parsed file's ``data``; :class:`ScenarioFileError` for any mistake.

    ``path`` only names the file in the messages.
    """
    if not isinstance(data, dict):
        raise ScenarioFileError(path, "<file>", "a table of keys", data)
    top = _Table(data, "", path, "the top level", _TOP_KEYS)
    name = top.string("name", nonempty=True, max_chars=MAX_NAME_CHARS)
    description = top.string("description", default="", max_chars=MAX_DESCRIPTION_CHARS)
    samples = top.integer("samples", low=1, high=MAX_SAMPLES)
    runs = top.integer("runs", default=1, low=1, high=samples, high_text="samples")
    seed = top.integer("seed", default=0, low=0, high=_SEED_LIMIT - 1)
    period = _sample_period(top)
    if period is None:
        methods = _methods(top)
        camera_model = top.string("camera_model", default="exact", choices=tuple(CAMERA_MODELS))
    else:
        for key in _EVENT_ONLY_KEYS:
            if top.has(key):
                top.fail(key, "no methods or camera_model with [sampling]: each measured robot's policy localizes "
                         "its own way", top.get(key))
        methods, camera_model = (), "exact"
    camera_profile = top.string("camera_profile", default=DEFAULT_CAMERA_PROFILE, choices=tuple(CAMERA_PROFILES))
    referee = top.boolean("referee", default=False)
    half_seconds = top.table("match", _MATCH_KEYS).number("half_seconds", default=600.0, low=HALF_SECONDS_MIN,
                                                          high=HALF_SECONDS_MAX)
    motion_scale = top.table("noise", _NOISE_KEYS).number("motion_scale", default=1.0, high=MAX_MOTION_SCALE)
    limits = top.table("limits", _LIMITS_KEYS)
    limit = limits.number("max_sim_seconds_per_run", default=1200.0, low=SIM_SECONDS_RANGE[0],
                          high=SIM_SECONDS_RANGE[1])
    warmup = limits.number("warmup_seconds", default=0.0, high=SIM_SECONDS_RANGE[1])
    if warmup >= limit:
        limits.fail("warmup_seconds", f"a number of seconds below max_sim_seconds_per_run ({limit:g})", warmup)
    thesis = _thesis(top)
    robots = _robots(top, referee, periodic=period is not None)
    return ScenarioSpec(
        name,
        description,
        samples,
        runs,
        seed,
        methods,
        camera_model,
        referee,
        robots,
        half_seconds,
        motion_scale,
        limit,
        thesis,
        warmup,
        period,
        camera_profile,
    )


class _Table:
    """One table of the file, its keys checked against ``allowed``; typed getters that raise on mistakes.

    ``prefix`` is put before a key in messages (``"noise."``, ``"robots[1]."``).
    """

    def __init__(self, data: dict, prefix: str, path: str, title: str, allowed: tuple[str, ...]) -> None:
        self.data, self.prefix, self.path = data, prefix, path
        for key, value in data.items():
            if key not in allowed:
                self.fail(key, f"a known key ({title} allows only {', '.join(allowed)})", value)

    def fail(self, key: str, expected: str, got: object) -> NoReturn:
        raise ScenarioFileError(self.path, f"{self.prefix}{key}", expected, got)

    def has(self, key: str) -> bool:
        return key in self.data

    def get(self, key: str, default: object = _MISSING) -> object:
        return self.data.get(key, default)

    def string(self, key: str, default: object = _MISSING, nonempty: bool = False, choices: tuple[str, ...] = (),
               max_chars: int = MAX_NAME_CHARS) -> str:
        """A string of at most ``max_chars`` characters; non-empty if asked; one of ``choices`` if given."""
        value = self.get(key, default)
        if choices:
            expected = f"one of {', '.join(repr(c) for c in choices)}"
            if not isinstance(value, str) or value not in choices:
                self.fail(key, expected, value)
        elif not isinstance(value, str) or (nonempty and not value.strip()) or len(value) > max_chars:
            self.fail(key, f"{'a non-empty string' if nonempty else 'a string'} of at most {max_chars} characters",
                      value)
        return value

    def integer(self, key: str, default: object = _MISSING, low: int = 0, high: int | None = None, high_text: str = "") -> int:
        """An integer (not a bool, not a float) in ``[low, high]``."""
        value = self.get(key, default)
        if high is None:
            expected = f"an integer >= {low}"
        else:
            expected = f"an integer in [{low}, {high}]" + (f" (at most {high_text})" if high_text else "")
        if not _is_int(value) or value < low or (high is not None and value > high):
            self.fail(key, expected, value)
        return value

    def number(self, key: str, default: object = _MISSING, low: float = 0.0, high: float = math.inf) -> float:
        """A finite number (int or float, not bool) in ``[low, high]``."""
        value = self.get(key, default)
        if not _is_number(value) or not low <= value <= high:
            expected = f"a finite number in [{low:g}, {high:g}]" if high < math.inf else f"a finite number >= {low:g}"
            self.fail(key, expected, value)
        return float(value)

    def boolean(self, key: str, default: object = _MISSING) -> bool:
        value = self.get(key, default)
        if not isinstance(value, bool):
            self.fail(key, "true or false", value)
        return value

    def table(self, key: str, allowed: tuple[str, ...]) -> _Table:
        """The sub-table ``[key]`` (empty when absent), its keys checked against ``allowed``."""
        value = self.get(key, {})
        if not isinstance(value, dict):
            self.fail(key, f"a table [{key}]", value)
        return _Table(value, f"{self.prefix}{key}.", self.path, f"[{key}]", allowed)


def _is_int(value: object) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _is_number(value: object) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def _methods(top: _Table) -> tuple[str, ...]:
    """``methods``: distinct names of :data:`agents.localization.LOCALIZERS`, all of them by default."""
    allowed = ", ".join(LOCALIZERS)
    value = top.get("methods", list(LOCALIZERS))
    if not isinstance(value, list) or not value:
        top.fail("methods", f"a non-empty array of method names from {allowed}", value)
    for i, method in enumerate(value):
        if not isinstance(method, str) or method not in LOCALIZERS:
            top.fail(f"methods[{i}]", f"one of {allowed}", method)
        if method in value[:i]:
            top.fail(f"methods[{i}]", "a method not listed before", method)
    return tuple(value)


def _sample_period(top: _Table) -> float | None:
    """``[sampling] period_seconds``: seconds of PLAYING time between samples (> 0); None without ``[sampling]``."""
    if not top.has("sampling"):
        return None
    low, high = PERIOD_SECONDS_RANGE
    return top.table("sampling", _SAMPLING_KEYS).number("period_seconds", low=low, high=high)


def _thesis(top: _Table) -> ThesisReference | None:
    """The optional ``[thesis]`` row: all four figures, numbers 0 .. :data:`MAX_THESIS_FIGURE`."""
    if not top.has("thesis"):
        return None
    table = top.table("thesis", _THESIS_KEYS)
    return ThesisReference(*(table.number(key, high=MAX_THESIS_FIGURE) for key in _THESIS_KEYS))


def _robots(top: _Table, referee: bool, periodic: bool) -> tuple[RobotEntry, ...]:
    """``[[robots]]`` in file order, each checked, then the checks across robots."""
    value = top.get("robots")
    if not isinstance(value, list) or not value or not all(isinstance(r, dict) for r in value):
        top.fail("robots", "a non-empty array of tables [[robots]]", value)
    robots: list[RobotEntry] = []
    for i, data in enumerate(value):
        robot = _robot(_Table(data, f"robots[{i}].", top.path, "[[robots]]", _ROBOT_KEYS), referee, periodic)
        if any(r.id == robot.id for r in robots):
            top.fail(f"robots[{i}].id", "a robot id not listed before", data["id"])
        robots.append(robot)
    ids = [r.id for r in robots]
    if not any(r.measured for r in robots):
        top.fail("robots", "at least one robot with measured = true", ids)
    if referee:
        _check_teams(top, ids)
    return tuple(robots)


def _robot(table: _Table, referee: bool, periodic: bool) -> RobotEntry:
    """One ``[[robots]]`` entry; its id in the canonical ``home_1`` spelling."""
    raw_id = table.get("id")
    try:
        agent = AgentId.parse(raw_id)
    except ValueError as exc:
        raise ScenarioFileError(table.path, f"{table.prefix}id", _ID_TEXT, raw_id) from exc
    policy = table.string("policy", max_chars=MAX_POLICY_CHARS)
    try:
        factory = policy_factory(policy)
    except PolicyNameError as error:
        table.fail("policy", f"{known_policies()} [{error}]", policy)
    measured = table.boolean("measured", default=False)
    if measured and periodic and not reports_pose(factory):
        table.fail("measured", "measured = true with [sampling] only with a policy that reports its pose "
                   "(pose_estimate(), match.protocol.PoseReporter)", measured)
    if measured and not periodic and policy not in MEASURABLE_POLICIES:
        table.fail("measured", f"measured = true only with policy = {' or '.join(map(repr, MEASURABLE_POLICIES))}",
                   measured)
    start = None
    if table.has("start"):
        if referee:
            table.fail("start", "no start: with the referee robots begin at their kick-off positions", table.get("start"))
        start = _start(table)
    return RobotEntry(str(agent), policy, measured, start)


def reports_pose(factory: object) -> bool:
    """Whether the policies a factory builds report their pose (a ``pose_estimate`` method).

    A class (or a ``functools.partial`` of one) is checked here; any other factory is taken
    at its word, and the run checks the policy it builds.
    """
    while isinstance(factory, functools.partial):
        factory = factory.func
    if isinstance(factory, type):
        return callable(getattr(factory, "pose_estimate", None))
    return True


def _start(table: _Table) -> Pose2D | None:
    """``start``: ``"random"`` (None) or ``[x_m, y_m, theta_deg]`` on the field."""
    value = table.get("start")
    if value == "random":
        return None
    x_max, y_max = FIELD.half_length, FIELD.half_width
    ok = isinstance(value, list) and len(value) == 3 and all(_is_number(v) for v in value)
    if not ok or abs(value[0]) > x_max or abs(value[1]) > y_max or abs(value[2]) > MAX_START_DEG:
        expected = (f"'random' or [x_m, y_m, theta_deg]: three finite numbers, |x_m| <= {x_max:g}, |y_m| <= {y_max:g}, "
                    f"|theta_deg| <= {MAX_START_DEG:g}")
        table.fail("start", expected, value)
    x, y, theta_deg = (float(v) for v in value)
    return Pose2D(x, y, math.radians(theta_deg))


def _check_teams(top: _Table, ids: list[str]) -> None:
    """With the referee: both sides present, each numbered 0..n-1 without gaps (1 <= n <= 4)."""
    for side in Side:
        players = sorted(AgentId.parse(i).player for i in ids if AgentId.parse(i).side is side)
        if not players or players != list(range(len(players))):
            expected = (
                "with the referee, both sides present and each side's players numbered 0..n-1 "
                f"without gaps (1 <= n <= {MAX_PLAYERS_PER_TEAM})"
            )
            top.fail("robots", expected, ids)
