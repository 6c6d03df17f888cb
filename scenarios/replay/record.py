"""What a match left in its directory, read and checked: :func:`load_match` gives a :class:`MatchRecord`.

A match directory holds ``match_log.npz`` (:mod:`match.log`), ``events.jsonl``
(:mod:`match.events`, one event per line) and ``summary.json`` (:mod:`match.runner`; it is
missing when a match was interrupted, and then the defaults of the referee stand in). Every
problem (a missing file, an archive that does not open, a truncated line, arrays of
mismatched lengths) is a :class:`ReplayInputError`: one line naming the file and what is wrong.

Besides the arrays every log has, the log may carry per-robot per-step extras that the team
agents report (see :data:`EXTRAS`); an extra that is absent is simply not shown.
"""

from __future__ import annotations

import json
import math
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from match.protocol.ids import AgentId

LOG_FILE = "match_log.npz"
EVENTS_FILE = "events.jsonl"
SUMMARY_FILE = "summary.json"


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
    elif isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value) and value > 0:
        half_seconds = float(value)
    else:
        raise ReplayInputError(f"{directory / SUMMARY_FILE}: config.half_seconds = {value!r}; expected a number > 0")
    return MatchRecord(directory=directory, events=events, summary=summary, half_seconds=half_seconds, **arrays)


# ---- match_log.npz ---------------------------------------------------------------------------


def _read_log(path: Path) -> dict:
    if not path.is_file():
        raise ReplayInputError(f"{path}: missing (a match writes it when it ends)")
    try:
        with np.load(path, allow_pickle=False) as npz:
            raw = {key: npz[key] for key in npz.files}
    except (zipfile.BadZipFile, EOFError, OSError, ValueError, KeyError) as error:
        raise ReplayInputError(f"{path}: not a readable .npz archive ({type(error).__name__}: {_one_line(error)})") from None
    missing = [key for key in REQUIRED if key not in raw]
    if missing:
        raise ReplayInputError(f"{path}: no array {', '.join(missing)} (has {', '.join(sorted(raw)) or 'none'})")

    agents = raw["agents"]
    if agents.ndim != 1 or agents.dtype.kind not in "US" or len(agents) == 0:
        raise ReplayInputError(f"{path}: agents has shape {agents.shape} and type {agents.dtype}; expected robot ids")
    names = tuple(str(a) for a in agents)
    try:
        distinct = len({AgentId.parse(name) for name in names}) == len(names)
    except ValueError as error:
        raise ReplayInputError(f"{path}: agents: {error}") from None
    if not distinct:
        raise ReplayInputError(f"{path}: agents names a robot twice: {', '.join(names)}")
    n = len(names)
    steps = len(raw["time_s"]) if raw["time_s"].ndim == 1 else -1
    if steps <= 0:
        raise ReplayInputError(f"{path}: time_s has shape {raw['time_s'].shape}; expected one time per step")
    shapes = {"state": (steps,), "half": (steps,), "ball": (steps, 3), "robots": (steps, n, 3), "fallen": (steps, n)}
    for key, shape in shapes.items():
        if raw[key].shape != shape:
            raise ReplayInputError(
                f"{path}: arrays of mismatched lengths: {key} has shape {raw[key].shape}, expected {shape} "
                f"for {steps} steps (time_s) and {n} robots (agents)"
            )
    time_s = raw["time_s"].astype(np.float64)
    if not np.isfinite(time_s).all() or (len(time_s) > 1 and (np.diff(time_s) <= 0).any()):
        raise ReplayInputError(f"{path}: time_s is not finite and strictly increasing")
    for key in ("ball", "robots"):
        bad = ~np.isfinite(raw[key]).all(axis=tuple(range(1, raw[key].ndim)))
        if bad.any():
            raise ReplayInputError(f"{path}: {key} is not finite at step {int(np.argmax(bad))}")
    half = raw["half"].astype(np.int64)
    if not np.isin(half, (1, 2)).all():
        raise ReplayInputError(f"{path}: half has values other than 1 and 2: {sorted(set(half.tolist()) - {1, 2})}")
    state = raw["state"].astype(np.int64)
    if ((state < 0) | (state > 4)).any():
        raise ReplayInputError(f"{path}: state has values outside 0-4 (INITIAL..FINISHED)")
    extras, labels = {}, {}
    for extra in EXTRAS:
        if extra.key in raw:
            extras[extra.channel] = _extra(path, raw, extra, steps, n)
            if extra.labels is not None and extra.labels in raw:
                labels[extra.channel] = tuple(str(v) for v in np.asarray(raw[extra.labels]).ravel())
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


def _extra(path: Path, raw: dict, extra: Extra, steps: int, n: int) -> np.ndarray:
    values = raw[extra.key]
    if extra.channel == "landmarks" and values.ndim == 3 and values.shape[:2] == (steps, n):
        bits = 1 << np.arange(values.shape[2], dtype=np.int64)
        values = (np.nan_to_num(values.astype(np.float64)) != 0).astype(np.int64) @ bits
    if values.ndim == 2 and extra.dims == 1:
        values = values[:, :, None]
    if values.shape != (steps, n, extra.dims) or values.dtype.kind not in "biuf":
        raise ReplayInputError(
            f"{path}: arrays of mismatched lengths: {extra.key} has shape {values.shape} and type {values.dtype}, "
            f"expected {(steps, n, extra.dims)} numbers for {steps} steps (time_s) and {n} robots (agents)"
        )
    return values.astype(np.float64)


# ---- events.jsonl and summary.json ---------------------------------------------------------


def _read_events(path: Path) -> tuple[dict, ...]:
    if not path.is_file():
        raise ReplayInputError(f"{path}: missing (a match writes it as it plays)")
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as error:
        raise ReplayInputError(f"{path}: unreadable ({_one_line(error)})") from None
    events = []
    lines = text.split("\n")
    for number, line in enumerate(lines, start=1):
        if not line.strip():
            continue
        try:
            event = json.loads(line)
        except json.JSONDecodeError as error:
            hint = ", truncated?" if number >= len(lines) - 1 else ""
            raise ReplayInputError(f"{path}: line {number}: not valid JSON ({error.msg}{hint})") from None
        if not isinstance(event, dict):
            raise ReplayInputError(f"{path}: line {number}: expected an object, found {type(event).__name__}")
        t, kind = event.get("time_s"), event.get("kind")
        if not (isinstance(t, (int, float)) and not isinstance(t, bool) and math.isfinite(t)) or not isinstance(kind, str):
            raise ReplayInputError(f"{path}: line {number}: an event needs a number time_s and a text kind")
        events.append(event)
    return tuple(events)


def _read_summary(path: Path) -> dict | None:
    if not path.exists():
        return None
    try:
        summary = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as error:
        raise ReplayInputError(f"{path}: not valid JSON ({_one_line(error)})") from None
    if not isinstance(summary, dict):
        raise ReplayInputError(f"{path}: expected a JSON object, found {type(summary).__name__}")
    return summary


def _one_line(error: BaseException) -> str:
    return " ".join(str(error).split()) or type(error).__name__
