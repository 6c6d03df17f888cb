"""Play a match again from its ``summary.json`` alone, and say whether it came out the same.

:func:`rerun_plan` reads what a rerun needs (who played, the seeds and settings, the versions)
and refuses, with :class:`RerunError` naming what differs, a record this installation would
not play the same way: a policy file whose content changed, other package versions or numpy SIMD
kernels, other world settings; ``force`` plays it all the same. :func:`compare_matches` then compares the
new ``events.jsonl`` and ``match_log.npz`` with the original's and finds the first
difference: the event line, or the log's step, robot and field.
"""

from __future__ import annotations

import dataclasses
import enum
import math
import os
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from match.controllers import ControllerLimits
from match.game import MatchConfig
from match.referee import RefereeConfig
from match.runner import numpy_simd_features, package_versions, plain_json
from scenarios.matches.play import Lineup
from scenarios.common.untrusted import SmallFileError, load_json, read_small_file
from scenarios.matches.provenance import file_hash
from world.camera_profiles import CAMERA_PROFILES

SUMMARY = "summary.json"
EVENTS = "events.jsonl"
MATCH_LOG = "match_log.npz"
SUMMARY_MAX_BYTES = 16 * 2**20
# the match log's arrays indexed (step, robot, ...), and those that are not per step (match.log.MatchLog.save)
PER_ROBOT_FIELDS = frozenset({"robots", "fallen", "estimates", "ball_estimates", "team_ball", "roles",
                              "landmarks_seen", "motions", "walks"})
PER_MATCH_FIELDS = frozenset({"agents", "role_names", "motion_names"})


class RerunError(ValueError):
    """A match record that cannot be played again (as it is, or at all)."""


@dataclass(frozen=True)
class RerunPlan:
    """What :func:`scenarios.matches.play.run_lineup_match` needs to play a recorded match again."""

    lineup: Lineup
    home: int
    away: int
    half_seconds: float
    shootout: bool
    seed: int
    referee: Mapping[str, object]
    controllers: ControllerLimits | None
    warnings: tuple[str, ...] = ()  # differences played through with force
    camera_profile: str = "clean"


@dataclass(frozen=True)
class Difference:
    """Where a rerun first differs from the original: ``file``, and the event ``line`` or the log's
    ``field``, ``step`` and ``robot`` (None where it does not apply), in words in ``text``."""

    file: str
    text: str
    line: int | None = None
    field: str | None = None
    step: int | None = None
    robot: str | None = None


def read_summary(match_dir: Path) -> dict:
    """``MATCH_DIR/summary.json`` as a dict; :class:`RerunError` naming the file if it is not one."""
    path = Path(match_dir) / SUMMARY
    try:
        summary = load_json(read_small_file(path, SUMMARY_MAX_BYTES))
    except SmallFileError as error:
        raise RerunError(f"{path}: not a match summary ({error})") from None
    if not isinstance(summary, dict):
        raise RerunError(f"{path}: expected a JSON object")
    return summary


def rerun_plan(summary: Mapping[str, object], *, force: bool = False, origin: str = SUMMARY) -> RerunPlan:
    """The plan of a rerun of the match ``summary`` records; :class:`RerunError` if it records too little, or
    (unless ``force``) something this installation would play otherwise."""
    played_by = _field(summary, "played_by", dict, origin)
    config = _field(summary, "config", dict, origin)
    policies = _field(played_by, "policies", dict, origin, "played_by.")
    names, problems = {}, []
    for agent, record in policies.items():
        name = _field(record, "policy", str, origin, f"played_by.policies.{agent}.")
        names[str(agent)] = name
        recorded = record.get("file_hash")
        if recorded is not None and file_hash(Path(str(record.get("file")))) != recorded:
            problems.append(f"{agent}'s policy file {record.get('file')} is not the one that played (its hash differs)")
    versions = summary.get("versions")
    now = package_versions()
    if isinstance(versions, dict):
        for package, version in versions.items():
            if now.get(package) != version:
                problems.append(f"{package} {now.get(package)} here, {version} in the record")
    machine = summary.get("machine")
    recorded_simd = machine.get("numpy_simd") if isinstance(machine, dict) else None
    if isinstance(recorded_simd, list) and recorded_simd != numpy_simd_features():
        problems.append(f"numpy's SIMD kernels here are {numpy_simd_features()}, {recorded_simd} in the record "
                        "(their last bits differ)")
    if isinstance(machine, dict) and "blas_core" in machine and machine["blas_core"] != os.environ.get(
            "OPENBLAS_CORETYPE"):
        problems.append(f"OpenBLAS kernels {os.environ.get('OPENBLAS_CORETYPE')} here, {machine['blas_core']} in the "
                        "record")
    world = config.get("world")
    if isinstance(world, dict):
        defaults = MatchConfig().world
        for part in ("physics", "render"):
            if part in world and world[part] != plain_json(dataclasses.asdict(getattr(defaults, part))):
                problems.append(f"the record's world {part} settings are not this installation's defaults")
    if problems and not force:
        raise RerunError(f"{origin}: would not play the same match: {'; '.join(problems)} (--force plays it anyway)")
    home = _field(config, "home_players", int, origin, "config.")
    away = _field(config, "away_players", int, origin, "config.")
    return RerunPlan(
        lineup=Lineup(overrides=names), home=home, away=away,
        half_seconds=float(_field(config, "half_seconds", (int, float), origin, "config.")),
        shootout=bool(_field(config, "shootout", bool, origin, "config.")),
        seed=_field(summary, "seed", int, origin), referee=_referee(config.get("referee"), origin),
        controllers=_controllers(_field(played_by, "controllers", dict, origin, "played_by."), origin),
        warnings=tuple(problems), camera_profile=_camera_profile(world, origin),
    )


def _camera_profile(world: object, origin: str) -> str:
    """The recorded cameras' image profile (``clean`` in a record that names none)."""
    name = world.get("camera_profile", "clean") if isinstance(world, dict) else "clean"
    if not isinstance(name, str) or name not in CAMERA_PROFILES:
        raise RerunError(f"{origin}: config.world.camera_profile {str(name)[:40]!r}; expected one of "
                         f"{', '.join(CAMERA_PROFILES)}")
    return name


def import_roots(summary: Mapping[str, object]) -> tuple[Path, ...]:
    """The directories from which the recorded users' policy modules were imported (each module's file
    less its dotted path), for ``sys.path``: a rerun imports them from where they played."""
    roots = []
    policies = summary.get("played_by", {}).get("policies", {}) if isinstance(summary.get("played_by"), dict) else {}
    for record in policies.values() if isinstance(policies, dict) else ():
        name, file = (record.get("policy"), record.get("file")) if isinstance(record, dict) else (None, None)
        if not isinstance(name, str) or not isinstance(file, str) or name.endswith(".toml") or ":" not in name:
            continue
        parts = name.partition(":")[0].split(".")
        path = Path(file)
        depth = len(parts) if path.name == "__init__.py" else len(parts) - 1
        if depth < len(path.parents):
            roots.append(path.parents[depth])
    return tuple(dict.fromkeys(roots))


def compare_matches(original: Path, rerun: Path) -> Difference | None:
    """The first difference of the rerun's events and match log from the original's (the log's earliest step
    at which any array differs); None if both are the same, byte for byte."""
    old_events = (Path(original) / EVENTS).read_text(encoding="utf-8").splitlines()
    new_events = (Path(rerun) / EVENTS).read_text(encoding="utf-8").splitlines()
    for line, (old, new) in enumerate(zip(old_events, new_events), start=1):
        if old != new:
            return Difference(EVENTS, f"{EVENTS} line {line}: {old[:160]!r} became {new[:160]!r}", line=line)
    if len(old_events) != len(new_events):
        return Difference(EVENTS, f"{EVENTS}: {len(old_events)} events, the rerun {len(new_events)}",
                          line=min(len(old_events), len(new_events)) + 1)
    if (Path(original) / MATCH_LOG).read_bytes() == (Path(rerun) / MATCH_LOG).read_bytes():
        return None
    with np.load(Path(original) / MATCH_LOG, allow_pickle=False) as old, \
            np.load(Path(rerun) / MATCH_LOG, allow_pickle=False) as new:
        agents = [str(a) for a in old["agents"]]
        first: tuple[int, str, tuple[int, ...], np.ndarray, np.ndarray] | None = None
        for key in sorted(set(old.files) | set(new.files)):
            if key not in old.files or key not in new.files:
                return Difference(MATCH_LOG, f"{MATCH_LOG}: {key} is in only one of the two logs", field=key)
            a, b = old[key], new[key]
            if a.shape != b.shape:
                return Difference(MATCH_LOG, f"{MATCH_LOG} {key}: shape {a.shape}, the rerun {b.shape}", field=key)
            differs = a != b
            if a.dtype.kind == "f":
                differs &= ~(np.isnan(a) & np.isnan(b))
            where = np.argwhere(differs)
            if len(where) and (first is None or int(where[0][0]) < first[0]):
                first = (int(where[0][0]), key, tuple(int(i) for i in where[0]), a, b)
        if first is None:
            return Difference(MATCH_LOG, f"{MATCH_LOG}: the same arrays, stored otherwise")
        step, key, index, a, b = first
        per_step = key not in PER_MATCH_FIELDS
        robot = agents[index[1]] if key in PER_ROBOT_FIELDS else None
        where_text = f" (step {step}{', ' + robot if robot else ''})" if per_step else ""
        change = f"{a[index].item()!r} became {b[index].item()!r}"
        return Difference(MATCH_LOG, f"{MATCH_LOG} {key}{list(index)}: {change}{where_text}", field=key,
                          step=step if per_step else None, robot=robot)
    return None


def _field(record: object, name: str, kind, origin: str, prefix: str = ""):
    if not isinstance(record, dict) or name not in record:
        raise RerunError(f"{origin}: no {prefix}{name}: recorded before matches said who played, it cannot be "
                         "played again from its summary")
    value = record[name]
    if not isinstance(value, kind) or (isinstance(value, bool) and kind in (int, (int, float))):
        raise RerunError(f"{origin}: {prefix}{name} = {str(value)[:60]!r}; expected {getattr(kind, '__name__', kind)}")
    if isinstance(value, float) and not math.isfinite(value):
        raise RerunError(f"{origin}: {prefix}{name} = {value!r}; expected a finite number")
    return value


def _referee(recorded: object, origin: str) -> dict:
    """The recorded referee settings but the half and the shoot-out (passed apart), in their types."""
    if recorded is None:
        return {}
    if not isinstance(recorded, dict):
        raise RerunError(f"{origin}: config.referee; expected an object")
    defaults = RefereeConfig()
    settings = {}
    for field in dataclasses.fields(RefereeConfig):
        if field.name in ("half_seconds", "shootout") or field.name not in recorded:
            continue
        value, default = recorded[field.name], getattr(defaults, field.name)
        try:
            settings[field.name] = type(default)(value) if isinstance(default, enum.Enum) else value
        except ValueError:
            raise RerunError(f"{origin}: config.referee.{field.name} = {value!r} is not a known value") from None
    try:
        dataclasses.replace(defaults, **settings)
    except (TypeError, ValueError) as error:
        raise RerunError(f"{origin}: config.referee: {error}") from None
    return settings


def _controllers(recorded: dict, origin: str) -> ControllerLimits | None:
    if recorded.get("in_process") is True:
        return None
    limits = {f.name: recorded[f.name] for f in dataclasses.fields(ControllerLimits) if f.name in recorded}
    try:
        return ControllerLimits(**limits)
    except (TypeError, ValueError) as error:
        raise RerunError(f"{origin}: played_by.controllers: {error}") from None

