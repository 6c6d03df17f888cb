"""The team agent's tunable numbers: thresholds, distances and timings, typed and bounded, read from TOML.

The defaults ship as ``agents/team/params.toml`` (package data), one table per concern; a file of
one's own (``robotstadium match --home team:fast.toml``) need only name the keys it changes, the
rest keep their defaults. A bad file or value is refused with a :class:`ParameterError` that names
the file, the key, the value and what was expected. Numbers the thesis names, the radio's budget
and the control step stay in code.

Units are in the key names: ``_m`` metres, ``_s`` seconds, ``_deg`` degrees (read as radians by the
``*_rad`` properties), ``_mps`` metres per second, ``_radps`` radians per second, ``_per_s`` gains.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import tomllib
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

from agents.toml_text import load_toml, read_toml_file

DEFAULT_FILE = "params.toml"


class ParameterError(ValueError):
    """A parameter file that cannot be read, or a key or value in it that is not one of the agent's."""

    def __init__(self, path: str, key: str, value: object, expected: str):
        self.path, self.key, self.value, self.expected = path, key, value, expected
        shown = "" if value is _MISSING else f" = {value!r}"
        super().__init__(f"{path}: {key}{shown}: expected {expected}")


_MISSING = object()


def bounded(low: float, high: float) -> Any:
    """A field that holds a number from ``low`` to ``high`` (inclusive)."""
    return field(metadata={"low": low, "high": high})


def switch() -> Any:
    """A field that turns a behaviour on or off (TOML ``true`` or ``false``)."""
    return field(metadata={"switch": True})


@dataclass(frozen=True)
class BallParams:
    """Believing in a ball: the own sighting, a throw-in's spot, a ball believed just out."""

    lost_s: float = bounded(0.1, 30.0)  # the own ball is trusted this long without a sighting
    drop_in_spot_s: float = bounded(0.0, 60.0)  # after a throw-in, the ball is believed at the rule's spot this
    # long, until someone sees it ...
    drop_in_spot_sigma_m: float = bounded(0.0, 5.0)  # ... this sure (one standard deviation)
    in_field_margin_m: float = bounded(0.0, 0.5)  # a ball believed beyond a line is played this far inside it


@dataclass(frozen=True)
class PostureParams:
    """Upright, falling, lying still: from the accelerometer and the gyro."""

    upright_acceleration_mps2: float = bounded(0.0, 9.81)  # torso z reads g cos(tilt): below this it is falling
    upright_smoothing: float = bounded(0.0, 1.0)  # the low-pass weight of a new accelerometer reading
    settled_gyro_radps: float = bounded(0.0, 20.0)  # a fallen robot turning slower lies still: it may stand up
    fall_sigma_m: float = bounded(0.0, 2.0)  # a fall adds this much position uncertainty ...
    fall_sigma_deg: float = bounded(0.0, 180.0)  # ... and this much heading uncertainty

    @functools.cached_property
    def fall_sigma_rad(self) -> float:
        return math.radians(self.fall_sigma_deg)


@dataclass(frozen=True)
class HeadParams:
    """Where the head looks and which camera takes the frame."""

    track_ball_s: float = bounded(0.0, 10.0)  # a ball seen more recently is tracked; older, searched for ...
    look_at_near_ball_m: float = bounded(0.0, 10.0)  # ... but one believed this near is looked at where a frame
    # would show it
    glance_every_s: float = bounded(0.1, 60.0)  # with an uncertain pose, glance at a goal this often ...
    glance_s: float = bounded(0.0, 10.0)  # ... for this long
    uncertain_m: float = bounded(0.0, 5.0)  # a pose less sure than this (one standard deviation) is uncertain
    penalty_look_s: float = bounded(0.0, 10.0)  # a penalty kicker looks at the goal this long, then at the ball
    look_for_team_ball_s: float = bounded(0.0, 60.0)  # without its own ball: of every search cycle, look this
    # long where the team believes it ...
    search_cycle_s: float = bounded(0.1, 60.0)  # ... and sweep the head for the rest
    shot_top_frame_every: int = bounded(1, 100)  # lining up a kick, every this many frames are the top camera's


@dataclass(frozen=True)
class KickParams:
    """When the striker kicks, and where."""

    align_deg: float = bounded(0.0, 180.0)  # kick only when facing the goal within this (pose estimate)
    own_goal_ahead_deg: float = bounded(0.0, 180.0)  # never kick with the own goal seen within this of ahead ...
    own_goal_memory_s: float = bounded(0.0, 60.0)  # ... in the last seconds
    contest_ball_m: float = bounded(0.0, 5.0)  # a striker this near its ball does not step around robots
    shooting_range_m: float = bounded(0.0, 10.0)  # nearer the goal, kick only into the open part of its mouth ...
    post_margin_m: float = bounded(0.0, 1.0)  # ... or, without one, between the posts this far inside them
    kick_past_near_m: float = bounded(0.0, 5.0)  # this near its ball in open play, kick past the robots in the way
    follow_kick_s: float = bounded(0.0, 30.0)  # after its kick, a striker that lost the ball walks ahead this long
    follow_kick_mps: float = bounded(0.0, 0.5)  # ... this fast

    @functools.cached_property
    def align_rad(self) -> float:
        return math.radians(self.align_deg)

    @functools.cached_property
    def own_goal_ahead_rad(self) -> float:
        return math.radians(self.own_goal_ahead_deg)


@dataclass(frozen=True)
class KeeperParams:
    """When the goalkeeper leaves its line."""

    clear_ball_within_m: float = bounded(0.0, 5.0)  # for a ball this near it ...
    clear_area_depth_m: float = bounded(0.0, 4.5)  # ... while it stands this near its goal line


@dataclass(frozen=True)
class BallOutParams:
    """A ball going out: who touched it last, and where the striker waits for it."""

    throw_in_wait_back_m: float = bounded(0.0, 3.0)  # the striker waits this far on its side of the rule's spot ...
    out_wait_s: float = bounded(0.0, 30.0)  # ... the ball believed out this long at most (longer: it is in)
    teammate_kick_heard_s: float = bounded(0.0, 5.0)  # a teammate's message this fresh saying it kicks: own touch


@dataclass(frozen=True)
class ThrowInParams:
    """A throw-in's first touch: the quickest one that sends the ball neither back nor out."""

    quick_touch_s: float = bounded(0.0, 60.0)  # this long after a throw-in, with the ball near the line, ...
    quick_untouched_s: float = bounded(0.0, 120.0)  # ... or up to this long with it still where it was first seen
    quick_untouched_m: float = bounded(0.0, 2.0)  # ... within this, ...
    quick_touch_band_m: float = bounded(0.0, 2.0)  # ... (this near the throw-in line) the quick first touch
    quick_push_deg: float = bounded(0.0, 180.0)  # push when facing the touch's aim within this and it may not kick,
    quick_push_s: float = bounded(0.0, 10.0)  # ... for this long; then it plays on as in open play
    quick_step_within_m: float = bounded(0.0, 3.0)  # nearer the ball, the touch goes the way the robot faces ...
    quick_step_deg: float = bounded(0.0, 180.0)  # ... and facing it within this, it steps to the ball
    quick_go_behind_beyond_m: float = bounded(0.0, 3.0)  # else it walks round behind the ball until this near it
    late_touch_after_s: float = bounded(0.0, 60.0)  # a striker this late near the ball ...
    late_touch_bearing_deg: float = bounded(0.0, 180.0)  # ... this near straight ahead walks on through it

    @functools.cached_property
    def quick_push_rad(self) -> float:
        return math.radians(self.quick_push_deg)

    @functools.cached_property
    def quick_step_rad(self) -> float:
        return math.radians(self.quick_step_deg)

    @functools.cached_property
    def late_touch_bearing_rad(self) -> float:
        return math.radians(self.late_touch_bearing_deg)


@dataclass(frozen=True)
class SideTapParams:
    """A throw-in's first touch from the field side of the ball: a side-step along the line."""

    approach_deg: float = bounded(0.0, 180.0)  # coming at the ball within this of square to the line, or facing it
    beyond_m: float = bounded(0.0, 3.0)  # not when standing farther than this past the ball the way the tap goes
    back_tap_clear_m: float = bounded(0.0, 9.0)  # from this far from the own goal line on, tap it back instead
    forward_m: float = bounded(0.0, 0.5)  # the ball this far ahead ...
    side_m: float = bounded(0.0, 0.5)  # ... and this far to the side the tap goes
    within_m: float = bounded(0.0, 0.5)  # once the ball lies this near that spot ...
    face_deg: float = bounded(0.0, 180.0)  # ... and the robot faces the line within this, it side-steps
    keep_s: float = bounded(0.0, 10.0)  # ... and keeps side-stepping while it did so this recently
    near_m: float = bounded(0.0, 3.0)  # nearer the ball, the spot is reached by the ball's sighting
    lined_up_m: float = bounded(0.0, 0.5)  # sideways first, the ball kept ahead until it lies within this ...
    clear_m: float = bounded(0.0, 1.0)  # ... (kept this far ahead until then)
    touch_m: float = bounded(0.0, 0.5)  # the ball this near the robot's centre line, sideways: the tap touched it
    gain_per_s: float = bounded(0.0, 10.0)

    @functools.cached_property
    def approach_rad(self) -> float:
        return math.radians(self.approach_deg)

    @functools.cached_property
    def face_rad(self) -> float:
        return math.radians(self.face_deg)


@dataclass(frozen=True)
class KickOffParams:
    """The other team's kick-off: its lane is kept clear."""

    free_s: float = bounded(0.0, 60.0)  # the ball is free this long after PLAYING began at most (rules) ...
    played_m: float = bounded(0.0, 3.0)  # ... or once believed this far from the centre spot; until then and ...
    lane_s: float = bounded(0.0, 30.0)  # ... this long after, the defender and the supporter hold their places


@dataclass(frozen=True)
class ClearLineParams:
    """A ball at the own goal line beside the goal: cleared along the line toward the side line
    (:mod:`agents.team.behavior.set_plays.clear_line`)."""

    enabled: bool = switch()
    depth_m: float = bounded(0.0, 1.0)  # a ball nearer the own goal line than this ...
    beside_post_m: float = bounded(0.0, 1.0)  # ... beside a post by this at least (nearer, it is held off) ...
    outer_y_m: float = bounded(0.0, 2.0)  # ... and nearer the field's long axis than this is cleared ...
    turn_deg: float = bounded(0.0, 90.0)  # ... toward its side line, turned this far from the goal line into the field

    @functools.cached_property
    def turn_rad(self) -> float:
        return math.radians(self.turn_deg)


@dataclass(frozen=True)
class TeamParams:
    """Every tunable number of the team agent, by concern (one TOML table each)."""

    ball: BallParams
    posture: PostureParams
    head: HeadParams
    kick: KickParams
    keeper: KeeperParams
    ball_out: BallOutParams
    throw_in: ThrowInParams
    side_tap: SideTapParams
    kickoff: KickOffParams
    clear_line: ClearLineParams

    @staticmethod
    def default() -> TeamParams:
        """The shipped parameters (``agents/team/params.toml``)."""
        return _default()

    @staticmethod
    def load(path: str | Path) -> TeamParams:
        """The defaults with the keys of the TOML file at ``path`` changed; :class:`ParameterError` if it
        cannot be read or holds a key or value that is not one of the agent's."""
        shown = str(path)
        try:
            data = read_toml_file(path)
        except OSError as error:
            raise ParameterError(shown, "(file)", _MISSING, f"a readable TOML file ({error.strerror})") from None
        except (tomllib.TOMLDecodeError, UnicodeDecodeError) as error:
            raise ParameterError(shown, "(file)", _MISSING, f"TOML ({error})") from None
        return from_tables(data, shown, base=_default())

    def replace(self, **changes: dict[str, Any]) -> TeamParams:
        """A copy with some keys changed, by table: ``params.replace(kick={"align_deg": 20.0})``, checked
        as a file's would be."""
        return from_tables(changes, "(replace)", base=self)


def from_tables(data: dict[str, Any], path: str, base: TeamParams | None = None) -> TeamParams:
    """The parameters of TOML ``data`` (its tables by concern) read as from the file ``path``; a key it
    lacks keeps ``base``'s value (every key is needed without a base)."""
    tables = {f.name: f.type for f in dataclasses.fields(TeamParams)}
    for name, table in data.items():
        if name not in tables:
            raise ParameterError(path, name, _MISSING, f"one of the tables {', '.join(tables)}")
        if not isinstance(table, dict):
            raise ParameterError(path, name, table, "a table")
    sections = {}
    for name in tables:
        cls = _SECTIONS[name]
        old = None if base is None else getattr(base, name)
        sections[name] = _section(cls, data.get(name, {}), path, name, old)
    return TeamParams(**sections)


_SECTIONS: dict[str, type] = {
    "ball": BallParams, "posture": PostureParams, "head": HeadParams, "kick": KickParams, "keeper": KeeperParams,
    "ball_out": BallOutParams, "throw_in": ThrowInParams, "side_tap": SideTapParams, "kickoff": KickOffParams,
    "clear_line": ClearLineParams,
}


def _section(cls: type, table: dict[str, Any], path: str, name: str, old: Any) -> Any:
    """One table's dataclass: each value checked against its field's type and bounds."""
    fields = {f.name: f for f in dataclasses.fields(cls)}
    for key in table:
        if key not in fields:
            raise ParameterError(path, f"{name}.{key}", _MISSING, f"one of the keys {', '.join(fields)}")
    values = {}
    for key, f in fields.items():
        if key not in table:
            if old is None:
                raise ParameterError(path, f"{name}.{key}", _MISSING, "a value (the key is missing)")
            values[key] = getattr(old, key)
            continue
        values[key] = _checked(table[key], f, path, f"{name}.{key}")
    return cls(**values)


def _checked(value: Any, f: dataclasses.Field, path: str, key: str) -> float | int | bool:
    if f.metadata.get("switch"):
        if not isinstance(value, bool):
            raise ParameterError(path, key, value, "true or false")
        return value
    low, high = f.metadata["low"], f.metadata["high"]
    whole = f.type in (int, "int")
    kind = "an integer" if whole else "a number"
    if isinstance(value, bool) or not isinstance(value, int if whole else (int, float)):
        raise ParameterError(path, key, value, f"{kind} from {low} to {high}")
    if not (math.isfinite(value) and low <= value <= high):
        raise ParameterError(path, key, value, f"{kind} from {low} to {high}")
    return int(value) if whole else float(value)


@functools.lru_cache(maxsize=1)
def _default() -> TeamParams:
    text = resources.files(__package__).joinpath(DEFAULT_FILE).read_text(encoding="utf-8")
    return from_tables(load_toml(text), f"agents/team/{DEFAULT_FILE}")
