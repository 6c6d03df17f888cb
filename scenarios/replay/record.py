"""What a match left in its directory, read and checked: :func:`load_match` gives a :class:`MatchRecord`.

A match directory holds ``match_log.npz`` (:mod:`match.log`), ``events.jsonl``
(:mod:`match.events`, one event per line) and ``summary.json`` (:mod:`match.runner`; it is
missing when a match was interrupted, and then the defaults of the referee stand in). Every
problem (a missing file, an archive that does not open, a truncated line, arrays of
mismatched lengths, a value out of its range) is a :class:`ReplayInputError`: one line naming
the file, the field and what is wrong.

The files are read as untrusted (:mod:`scenarios.common.untrusted`): regular files only, of a
bounded size; JSON of a bounded depth; the log's array headers checked against its layout (at
most :data:`MAX_LOG_STEPS` steps of at most eight robots, numbers of the dtypes it writes)
before any array is loaded, so that a header claiming terabytes allocates nothing; then every
value within its range, and the summary's winner in agreement with its score.

Besides the arrays every log has, the log may carry per-robot per-step extras that the team
agents report (see :data:`EXTRAS`); an extra that is absent is simply not shown.
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from match.protocol.ids import MAX_PLAYERS_PER_TEAM, AgentId
from match.protocol.spaces import MAX_SCORE
from scenarios.common.untrusted import (
    ArrayHeader,
    LongNumber,
    NpzArchive,
    SmallFileError,
    check_json_depth,
    json_int,
    load_json,
    read_small_file,
)

LOG_FILE = "match_log.npz"
EVENTS_FILE = "events.jsonl"
SUMMARY_FILE = "summary.json"
MAX_LOG_BYTES = 4 << 30
MAX_EVENTS_BYTES = 64 << 20
MAX_SUMMARY_BYTES = 4 << 20
MAX_LOG_STEPS = 5_000_000  # two halves of the longest allowed length (86,400 s) at 25 steps a second, and pauses
MAX_TIME_S = 1e7
MAX_ROBOTS = 2 * MAX_PLAYERS_PER_TEAM
MAX_ROLE_NAMES = 64  # match.log keeps at most this many
MAX_NAME_CHARS = 64  # an agent id, a role name, an event's kind
MAX_COORDINATE = 1000.0  # a logged position (m) or heading (rad): the field is a few metres
MAX_EXTRA = 1e6  # a reported value (m, rad, a role index, landmark bits)
MAX_SEED = 2**64 - 1
MAX_LANDMARK_FLAGS = 62  # landmarks as flags become the bits of one int64


class ReplayInputError(ValueError):
    """A match directory whose files are missing, unreadable or inconsistent (one line: file and fault)."""


@dataclass(frozen=True)
class Extra:
    """A per-robot per-step array the log may carry beside the estimates.

    ``key``: its name in ``match_log.npz``; ``channel``: its name in the page; ``dims``: the
    values per robot and step (an array of shape (T, N) has 1); ``scale``: the page keeps
    ``round(value * scale)`` (NaN: none that step); ``labels``: the npz key of the names an
    integer channel indexes, if any.
    """

    key: str
    channel: str
    dims: int
    scale: float
    labels: str | None = None


# Per-robot per-step extras, shown when the log has them (NaN where a robot reports none):
# the agent's own pose estimate (x, y, theta), its ball estimate (x, y), the team's shared
# ball (x, y), its role (index into the names in ``role_names``) and the landmarks it saw
# (a bit mask over ``world.field.FIELD.landmarks``, bit i for landmark i; also accepted as a
# (T, N, 17) boolean array).
EXTRAS = (
    Extra("estimates", "estimate", 3, 1000.0),
    Extra("ball_estimates", "ball_estimate", 2, 1000.0),
    Extra("team_ball", "team_ball", 2, 1000.0),
    Extra("roles", "role", 1, 1.0, labels="role_names"),
    Extra("landmarks_seen", "landmarks", 1, 1.0),
)
REQUIRED = ("agents", "time_s", "state", "half", "ball", "robots", "fallen")


@dataclass(frozen=True)
class MatchRecord:
    """One match as logged. Arrays over T steps and N robots (``agents`` order)."""

    directory: Path
    agents: tuple[str, ...]
    time_s: np.ndarray  # (T,) float64
    state: np.ndarray  # (T,) int: match.protocol.game_control.GameState
    half: np.ndarray  # (T,) int: 1 or 2
    ball: np.ndarray  # (T, 3) float
    robots: np.ndarray  # (T, N, 3) x, y, theta
    fallen: np.ndarray  # (T, N) bool
    extras: dict[str, np.ndarray]  # channel -> (T, N, dims) float, NaN where none
    labels: dict[str, tuple[str, ...]]  # channel -> names an integer channel indexes
    events: tuple[dict, ...]  # events.jsonl, in file order
    summary: dict | None  # summary.json, None when the match left none
    half_seconds: float

    @property
    def steps(self) -> int:
        return len(self.time_s)

    @property
    def estimates(self) -> np.ndarray:
        """(T, N, 3) the agents' own pose estimates, NaN where none."""
        return self.extras.get("estimate", np.full((self.steps, len(self.agents), 3), np.nan))

    def has_estimates(self, robot: int) -> bool:
        return bool(np.isfinite(self.estimates[:, robot, :2]).all(axis=1).any())


def load_match(directory: Path) -> MatchRecord:
    """Read and check the match in ``directory``; :class:`ReplayInputError` at the first fault."""
    directory = Path(directory)
    if not directory.is_dir():
        raise ReplayInputError(f"{directory}: not a directory (expected a match directory with {LOG_FILE}, {EVENTS_FILE})")
    arrays = _read_log(directory / LOG_FILE)
    events = _read_events(directory / EVENTS_FILE)
    summary = _read_summary(directory / SUMMARY_FILE)
    config = summary.get("config") if summary is not None else None
    value = config.get("half_seconds") if isinstance(config, dict) else None
    if value is None:
        from match.referee import RefereeConfig  # loads the simulator: only when the summary does not say

        half_seconds = RefereeConfig().half_seconds
    elif _is_number(value) and 0 < value <= MAX_TIME_S:
        half_seconds = float(value)
    else:
        raise ReplayInputError(f"{directory / SUMMARY_FILE}: config.half_seconds = {_short(value)}; "
                               f"expected a number of seconds > 0, at most {MAX_TIME_S:g}")
    return MatchRecord(directory=directory, events=events, summary=summary, half_seconds=half_seconds, **arrays)


# ---- match_log.npz ---------------------------------------------------------------------------


def _read_log(path: Path) -> dict:
    if not os.path.lexists(path):
        raise ReplayInputError(f"{path}: missing (a match writes it when it ends)")
    try:
        with NpzArchive(path, MAX_LOG_BYTES) as archive:
            steps, n = _check_layout(path, archive.headers)
            wanted = [*REQUIRED, *(e.key for e in EXTRAS), *(e.labels for e in EXTRAS if e.labels)]
            raw = {key: archive.array(key) for key in wanted if key in archive.headers}
    except SmallFileError as error:
        reason = error.reason if error.reason.startswith(("array ", "not a readable")) else \
            f"not a readable .npz archive ({error.reason})"
        raise ReplayInputError(f"{path}: {reason}") from None
    names = tuple(str(a) for a in raw["agents"])
    try:
        distinct = len({AgentId.parse(name) for name in names}) == len(names)
    except ValueError as error:
        raise ReplayInputError(f"{path}: agents: {error}") from None
    if not distinct:
        raise ReplayInputError(f"{path}: agents names a robot twice: {', '.join(names)}")
    time_s = raw["time_s"].astype(np.float64)
    if not np.isfinite(time_s).all() or (len(time_s) > 1 and (np.diff(time_s) <= 0).any()):
        raise ReplayInputError(f"{path}: time_s is not finite and strictly increasing")
    if time_s[0] < 0 or time_s[-1] > MAX_TIME_S:
        raise ReplayInputError(f"{path}: time_s runs from {time_s[0]:g} to {time_s[-1]:g} s; expected 0 to {MAX_TIME_S:g}")
    for key in ("ball", "robots"):
        values = raw[key].astype(np.float64)
        bad = ~(np.abs(values) <= MAX_COORDINATE).all(axis=tuple(range(1, values.ndim)))  # NaN is bad too
        if bad.any():
            raise ReplayInputError(f"{path}: {key} is not finite, or beyond {MAX_COORDINATE:g} m, at step "
                                   f"{int(np.argmax(bad))}")
    half = raw["half"].astype(np.int64)
    if not np.isin(half, (1, 2)).all():
        raise ReplayInputError(f"{path}: half has values other than 1 and 2: {sorted(set(half.tolist()) - {1, 2})[:5]}")
    state = raw["state"].astype(np.int64)
    if ((state < 0) | (state > 4)).any():
        raise ReplayInputError(f"{path}: state has values outside 0-4 (INITIAL..FINISHED)")
    extras, labels = {}, {}
    for extra in EXTRAS:
        if extra.key in raw:
            extras[extra.channel] = _extra(path, raw, extra, steps, n)
            if extra.labels is not None and extra.labels in raw:
                labels[extra.channel] = tuple(str(v) for v in raw[extra.labels])
    return {
        "agents": names,
        "time_s": time_s,
        "state": state,
        "half": half,
        "ball": raw["ball"].astype(np.float64),
        "robots": raw["robots"].astype(np.float64),
        "fallen": raw["fallen"].astype(bool),
        "extras": extras,
        "labels": labels,
    }


_INTEGERS, _NUMBERS, _FLAGS = "iu", "iuf", "biu"


def _check_layout(path: Path, headers: dict[str, ArrayHeader]) -> tuple[int, int]:
    """The steps T and robots N the log's array headers describe, checked before any array is loaded: every
    array the layout of :mod:`match.log` gives it (T at most :data:`MAX_LOG_STEPS`, N at most
    :data:`MAX_ROBOTS`), of the dtypes it writes."""
    missing = [key for key in REQUIRED if key not in headers]
    if missing:
        raise ReplayInputError(f"{path}: no array {', '.join(missing)} (has {', '.join(sorted(headers)) or 'none'})")
    agents = headers["agents"]
    if (len(agents.shape) != 1 or agents.dtype.kind not in "US" or not 0 < agents.shape[0] <= MAX_ROBOTS
            or agents.dtype.itemsize > 4 * MAX_NAME_CHARS):
        raise ReplayInputError(f"{path}: agents has shape {agents.shape} and type {agents.dtype}; expected robot ids")
    n = agents.shape[0]
    time = headers["time_s"]
    steps = time.shape[0] if len(time.shape) == 1 else -1
    if not 0 < steps <= MAX_LOG_STEPS or time.dtype.kind not in _NUMBERS:
        raise ReplayInputError(f"{path}: time_s has shape {time.shape} and type {time.dtype}; expected one time per "
                               f"step, at most {MAX_LOG_STEPS} steps")
    shapes = {"state": (steps,), "half": (steps,), "ball": (steps, 3), "robots": (steps, n, 3), "fallen": (steps, n)}
    kinds = {"state": _INTEGERS, "half": _INTEGERS, "ball": _NUMBERS, "robots": _NUMBERS, "fallen": _FLAGS}
    for key, shape in shapes.items():
        if headers[key].shape != shape:
            raise ReplayInputError(
                f"{path}: arrays of mismatched lengths: {key} has shape {headers[key].shape}, expected {shape} "
                f"for {steps} steps (time_s) and {n} robots (agents)"
            )
        if headers[key].dtype.kind not in kinds[key] or headers[key].dtype.itemsize > 8:
            what = "integers" if kinds[key] == _INTEGERS else "numbers"
            raise ReplayInputError(f"{path}: {key} has type {headers[key].dtype}; expected {what}")
    for extra in EXTRAS:
        header = headers.get(extra.key)
        if header is None:
            continue
        allowed = [(steps, n, extra.dims)] + ([(steps, n)] if extra.dims == 1 else [])
        if extra.channel == "landmarks":  # also one flag per landmark
            allowed += [(steps, n, k) for k in range(2, MAX_LANDMARK_FLAGS + 1)]
        if header.shape not in allowed or header.dtype.kind not in "biuf" or header.dtype.itemsize > 8:
            raise ReplayInputError(
                f"{path}: arrays of mismatched lengths: {extra.key} has shape {header.shape} and type {header.dtype}, "
                f"expected {(steps, n, extra.dims)} numbers for {steps} steps (time_s) and {n} robots (agents)"
            )
        names = headers.get(extra.labels) if extra.labels else None
        if names is not None and (len(names.shape) != 1 or names.dtype.kind not in "US"
                                  or names.shape[0] > MAX_ROLE_NAMES or names.dtype.itemsize > 4 * MAX_NAME_CHARS):
            raise ReplayInputError(f"{path}: {extra.labels} has shape {names.shape} and type {names.dtype}; expected "
                                   f"at most {MAX_ROLE_NAMES} names of at most {MAX_NAME_CHARS} characters")
    return steps, n


def _extra(path: Path, raw: dict, extra: Extra, steps: int, n: int) -> np.ndarray:
    values = raw[extra.key]
    if extra.channel == "landmarks" and values.ndim == 3 and values.shape[2] != 1:
        bits = 1 << np.arange(values.shape[2], dtype=np.int64)
        values = (np.nan_to_num(values.astype(np.float64)) != 0).astype(np.int64) @ bits
    if values.ndim == 2:
        values = values[:, :, None]
    values = values.astype(np.float64)
    known = values[~np.isnan(values)]
    if not (np.abs(known) <= MAX_EXTRA).all():
        raise ReplayInputError(f"{path}: {extra.key} has values that are infinite or beyond {MAX_EXTRA:g}")
    return values


# ---- events.jsonl and summary.json ---------------------------------------------------------


def _read_events(path: Path) -> tuple[dict, ...]:
    if not os.path.lexists(path):
        raise ReplayInputError(f"{path}: missing (a match writes it as it plays)")
    try:
        raw = read_small_file(path, MAX_EVENTS_BYTES)
        check_json_depth(raw, lines=True)
        text = raw.decode("utf-8")
    except SmallFileError as error:
        raise ReplayInputError(f"{path}: {error.reason}") from None
    except UnicodeDecodeError as error:
        raise ReplayInputError(f"{path}: unreadable ({_one_line(error)})") from None
    events = []
    lines = text.split("\n")
    for number, line in enumerate(lines, start=1):
        if not line.strip():
            continue
        try:
            event = json.loads(line, parse_int=json_int)
        except json.JSONDecodeError as error:
            hint = ", truncated?" if number >= len(lines) - 1 else ""
            raise ReplayInputError(f"{path}: line {number}: not valid JSON ({error.msg}{hint})") from None
        if not isinstance(event, dict):
            raise ReplayInputError(f"{path}: line {number}: expected an object, found {type(event).__name__}")
        problem = _event_problem(event)
        if problem is not None:
            raise ReplayInputError(f"{path}: line {number}: {problem}")
        events.append(event)
    return tuple(events)


def _event_problem(event: dict) -> str | None:
    """What is wrong with an event the page reads (its time, kind, half and tallies), or None."""
    t, kind = event.get("time_s"), event.get("kind")
    if not (_is_number(t) and 0 <= t <= MAX_TIME_S):
        return f"time_s = {_short(t)}; expected a number of seconds from 0 to {MAX_TIME_S:g}"
    if not (isinstance(kind, str) and 0 < len(kind) <= MAX_NAME_CHARS):
        return f"kind = {_short(kind)}; expected a text of 1 to {MAX_NAME_CHARS} characters"
    if "half" in event and not (type(event["half"]) is int and event["half"] in (1, 2)):
        return f"half = {_short(event['half'])}; expected 1 or 2"
    for tally in ("score", "shootout"):
        value = event.get(tally)
        if isinstance(value, dict):
            for side in ("home", "away"):
                if side in value and not _is_count(value[side]):
                    return f"{tally}.{side} = {_short(value[side])}; expected a count from 0 to {MAX_SCORE}"
    return _not_finite(event, "")


def _not_finite(value: object, where: str) -> str | None:
    """The first number of a JSON value that is not finite (the page's JSON has no NaN), as a problem, or None."""
    if isinstance(value, float) and not math.isfinite(value):
        return f"{where} = {_short(value)}; expected a finite number"
    if isinstance(value, LongNumber):
        return f"{where} = {_short(value)}; expected a number of at most a few hundred digits"
    items = value.items() if isinstance(value, dict) else enumerate(value) if isinstance(value, list) else ()
    for key, item in items:
        problem = _not_finite(item, f"{where}.{key}" if where else str(key))
        if problem is not None:
            return problem
    return None


def _read_summary(path: Path) -> dict | None:
    if not os.path.lexists(path):
        return None
    try:
        summary = load_json(read_small_file(path, MAX_SUMMARY_BYTES))
    except SmallFileError as error:
        reason = error.reason
        if not (error.missing or error.too_big or reason.startswith("nested")):
            reason = f"not valid JSON ({reason})"
        raise ReplayInputError(f"{path}: {reason}") from None
    if not isinstance(summary, dict):
        raise ReplayInputError(f"{path}: expected a JSON object, found {type(summary).__name__}")
    problem = _summary_problem(summary)
    if problem is not None:
        raise ReplayInputError(f"{path}: {problem}")
    return summary


def _summary_problem(summary: dict) -> str | None:
    """What is wrong with the fields of a summary the page shows (score, shoot-out, winner, seed, simulated
    time), or None; a field that is absent is not shown."""
    tallies = {}
    for tally in ("score", "shootout"):
        value = summary.get(tally)
        if value is None and tally == "shootout":
            continue
        if tally not in summary:
            continue
        if not (isinstance(value, dict) and all(_is_count(value.get(side)) for side in ("home", "away"))):
            return f"{tally} = {_short(value)}; expected home and away counts from 0 to {MAX_SCORE}"
        tallies[tally] = (value["home"], value["away"])
    winner = summary.get("winner")
    if winner not in (None, "home", "away"):
        return f"winner = {_short(winner)}; expected home, away or null"
    if winner is not None and "score" in tallies:
        score, shootout = tallies["score"], tallies.get("shootout")
        decider = shootout if score[0] == score[1] and shootout is not None else score
        if decider[0] == decider[1] or (decider[0] > decider[1]) != (winner == "home"):
            shown = f"{score[0]}-{score[1]}" + (f" ({shootout[0]}-{shootout[1]} in the shoot-out)" if shootout else "")
            return f"winner = {winner!r} after {shown}; expected the side that scored more"
    seed = summary.get("seed")
    if "seed" in summary and not (isinstance(seed, int) and not isinstance(seed, bool) and 0 <= seed <= MAX_SEED):
        return f"seed = {_short(seed)}; expected an integer from 0 to {MAX_SEED}"
    seconds = summary.get("sim_seconds")
    if "sim_seconds" in summary and not (_is_number(seconds) and 0 <= seconds <= MAX_TIME_S):
        return f"sim_seconds = {_short(seconds)}; expected a number of seconds from 0 to {MAX_TIME_S:g}"
    return None


def _is_number(value: object) -> bool:
    """A finite int or float (not a bool); an int past float's range is finite too."""
    if isinstance(value, bool):
        return False
    return isinstance(value, int) or (isinstance(value, float) and math.isfinite(value))


def _is_count(value: object) -> bool:
    return isinstance(value, int) and not isinstance(value, bool) and 0 <= value <= MAX_SCORE


def _short(value: object) -> str:
    """A value as a message shows it: its JSON text, at most 40 characters."""
    if isinstance(value, LongNumber):
        return repr(value)
    try:
        text = json.dumps(value)
    except (TypeError, ValueError):
        text = type(value).__name__
    return text if len(text) <= 40 else text[:37] + "..."


def _one_line(error: BaseException) -> str:
    return " ".join(str(error).split()) or type(error).__name__
