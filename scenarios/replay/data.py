"""The data a replay page embeds: :func:`replay_data` turns a :class:`MatchRecord` into plain JSON values.

Format ``robotstadium-replay/1`` (times in integer milliseconds of simulated time):

- ``field``: every dimension of ``world.field.FIELD`` in metres, its painted ``lines``
  ([x0, y0, x1, y1] centre lines), the centre ``circle`` and the 17 ``landmarks``;
  ``colors``: the palette (team colours ``blue`` and ``red``, goals, carpet, ball);
- ``match``: ``steps`` logged, ``dt_ms`` between them, ``stride`` (every stride-th step is a
  frame), ``half_seconds``, the ``summary`` of the match (score, shoot-out, winner, seed),
  the ``states`` names that ``state`` values index;
- ``frames``: ``t`` (ms, one per frame), and channels ``clock`` (seconds left in the half)
  and ``ball`` (x, y);
- ``robots``: one object per robot, ``id``, ``side``, ``player`` and ``channels``:
  ``pose`` (x, y, theta, the truth), ``fallen`` (0 or 1), and whichever per-robot extras the
  log has (:data:`scenarios.replay.record.EXTRAS`: ``estimate``, ``ball_estimate``,
  ``team_ball``, ``role``, ``landmarks``); a channel a robot never reports is left out;
- a **channel** is ``{"dims": d, "scale": s, "data": [...]}``: ``d`` values per frame, flat
  (frame-major), each ``round(value * s)`` or ``null`` where there is none;
- ``labels``: names that integer channels index (``role``);
- ``status``: the score board as segments, each from ``t`` on until the next: ``state``
  (index into ``match.states``), ``half``, ``shootout`` (bool), ``score`` [home, away],
  ``pens`` [home, away] and ``home_color`` (``blue`` or ``red``: the home team starts blue
  and the teams swap colours at half-time);
- ``events``: every event of ``events.jsonl`` (exact, not sampled) as ``t`` (ms), ``kind``
  and its details.

Per-step data is sampled (every ``stride``-th step and the last) so that a full match stays
at most :data:`MAX_FRAMES` frames; events and the score board are exact.

Adding a per-robot per-step extra: log it in ``match_log.npz`` as an array of shape (T, N)
or (T, N, d), NaN where a robot reports nothing, and name it in
:data:`scenarios.replay.record.EXTRAS` (npz key, channel name, d, scale). It is then
embedded as a channel of the robots that report it; the page (``assets/replay.js``) shows a
toggle column for each channel it lists in its ``EXTRAS`` and draws it in ``drawExtras``.
"""

from __future__ import annotations

import math

import numpy as np

from match.protocol.game_control import GameState
from scenarios.replay.record import EXTRAS, MatchRecord
from world.field import FIELD

FORMAT = "robotstadium-replay/1"
MAX_FRAMES = 8000  # a full match (about 32 000 steps) is sampled every 4th step
POSE_SCALE = 1000.0  # millimetres and milliradians
CLOCK_SCALE = 10.0  # tenths of a second

COLORS = {
    "blue": "#1f5fe0",  # the blue team (its waistbands are cyan in the simulator)
    "red": "#e0282e",  # the red team (magenta waistbands)
    "blue_goal": "#2a6df4",
    "yellow_goal": "#f2c615",
    "carpet": "#3f8f45",
    "line": "#ffffff",
    "floor": "#6b6f76",
    "ball": "#ff7a00",
}


def replay_data(record: MatchRecord, stride: int | None = None) -> dict:
    """The page's data for ``record``; ``stride``: keep every stride-th step (default: at most MAX_FRAMES)."""
    steps = record.steps
    stride = stride or max(1, math.ceil(steps / MAX_FRAMES))
    frames = np.arange(0, steps, stride)
    if frames[-1] != steps - 1:
        frames = np.append(frames, steps - 1)
    t_ms = np.round(record.time_s * 1000.0).astype(np.int64)
    dt_ms = int(np.median(np.diff(t_ms))) if steps > 1 else 40
    status, clock = _status_and_clock(record, t_ms)
    robots = []
    for i, agent in enumerate(record.agents):
        side, _, player = agent.partition("_")
        channels = {
            "pose": channel(record.robots[frames, i, :], POSE_SCALE),
            "fallen": channel(record.fallen[frames, i, None].astype(np.float64), 1.0),
        }
        for extra in EXTRAS:
            values = record.extras.get(extra.channel)
            if values is not None and np.isfinite(values[:, i]).any():
                channels[extra.channel] = channel(values[frames, i, :], extra.scale)
        robots.append({"id": agent, "side": side, "player": int(player), "channels": channels})
    summary = record.summary or {}
    return {
        "format": FORMAT,
        "title": f"{record.directory.resolve().name}" + (f": {teams}" if (teams := teams_by_policy(summary)) else ""),
        "field": field_data(),
        "colors": COLORS,
        "match": {
            "steps": steps,
            "dt_ms": dt_ms,
            "stride": stride,
            "half_seconds": record.half_seconds,
            "states": [s.name for s in GameState],
            "summary": {key: summary.get(key) for key in ("score", "shootout", "winner", "seed", "sim_seconds")},
        },
        "frames": {
            "t": t_ms[frames].tolist(),
            "clock": channel(clock[frames, None], CLOCK_SCALE),
            "ball": channel(record.ball[frames, :2], POSE_SCALE),
        },
        "robots": robots,
        "settings": match_settings(summary),
        "labels": {name: list(values) for name, values in record.labels.items()},
        "status": status,
        "events": [_event(e) for e in record.events],
    }


def channel(values: np.ndarray, scale: float) -> dict:
    """A channel of F frames x d values: ``{"dims", "scale", "data"}``, NaN as ``None``."""
    values = np.asarray(values, dtype=np.float64)
    flat = values.reshape(len(values), -1)
    scaled = np.round(flat * scale)
    finite = np.isfinite(scaled)
    data = np.where(finite, scaled, 0).astype(np.int64).astype(object)
    data[~finite] = None
    return {"dims": flat.shape[1], "scale": scale, "data": data.ravel().tolist()}


def field_data() -> dict:
    """Every dimension of the field (metres), its lines, circle and landmarks, from ``world.field.FIELD``."""
    f = FIELD
    return {
        "length": f.length,
        "width": f.width,
        "line_width": f.line_width,
        "carpet_margin": f.carpet_margin,
        "center_circle_radius": f.center_circle_radius,
        "goal_area_depth": f.goal_area_depth,
        "goal_area_width": f.goal_area_width,
        "goal_inner_width": f.goal_inner_width,
        "goal_post_y": f.goal_post_y,
        "goal_post_radius": f.goal_post_radius,
        "goal_depth": f.goal_depth,
        "penalty_mark_x": f.penalty_mark_x,
        "penalty_mark_size": f.penalty_mark_size,
        "ball_radius": f.ball_radius,
        "lines": [[s.x0, s.y0, s.x1, s.y1] for s in f.line_segments],
        "circle": {"x": f.center_circle.cx, "y": f.center_circle.cy, "r": f.center_circle.radius},
        "landmarks": [{"id": lm.id.value, "kind": lm.kind.value, "x": lm.x, "y": lm.y} for lm in f.landmarks],
    }


def _status_and_clock(record: MatchRecord, t_ms: np.ndarray) -> tuple[list[dict], np.ndarray]:
    """The score board as segments (state and half from the log, scores from the events) and the clock per step.

    The half clock runs down while the game is PLAYING outside a shoot-out (the referee
    counts the time of each step that began in PLAYING) and starts again at each half.
    """
    events = sorted(record.events, key=lambda e: e["time_s"])
    score, pens, shootout = [0, 0], [0, 0], False
    segments: list[dict] = []
    clock = np.empty(record.steps)
    remaining = record.half_seconds
    k = 0
    for i in range(record.steps):
        if i > 0:
            if record.half[i] != record.half[i - 1]:
                remaining = record.half_seconds
            elif record.state[i - 1] == GameState.PLAYING and not shootout:
                remaining = max(0.0, remaining - (record.time_s[i] - record.time_s[i - 1]))
        while k < len(events) and round(events[k]["time_s"] * 1000) <= t_ms[i]:
            score, pens, shootout = _apply(events[k], score, pens, shootout)
            k += 1
        clock[i] = remaining
        half = int(record.half[i])
        now = {"state": int(record.state[i]), "half": half, "shootout": shootout, "score": list(score),
               "pens": list(pens), "home_color": "blue" if half == 1 else "red"}
        if not segments or any(segments[-1][key] != value for key, value in now.items()):
            segments.append({"t": int(t_ms[i]), **now})
    return segments, clock


def _apply(event: dict, score: list[int], pens: list[int], shootout: bool) -> tuple[list[int], list[int], bool]:
    kind = event["kind"]
    if kind in ("goal", "half_time", "end") and isinstance(event.get("score"), dict):
        score = [_count(event["score"], "home", score[0]), _count(event["score"], "away", score[1])]
    elif kind == "goal" and event.get("team") in ("home", "away"):
        score = [score[0] + (event["team"] == "home"), score[1] + (event["team"] == "away")]
    if kind in ("shootout_kick", "end") and isinstance(event.get("shootout"), dict):
        pens = [_count(event["shootout"], "home", pens[0]), _count(event["shootout"], "away", pens[1])]
    if kind == "state" and event.get("secondary") is not None:
        shootout = event["secondary"] == "PENALTY_SHOOTOUT"
    if kind == "shootout_kick":
        shootout = True
    return score, pens, shootout


def _count(tally: dict, side: str, default: int) -> int:
    value = tally.get(side)
    return value if isinstance(value, int) and not isinstance(value, bool) else default


def _event(event: dict) -> dict:
    details = {key: value for key, value in event.items() if key not in ("time_s", "kind")}
    return {"t": int(round(event["time_s"] * 1000)), "kind": event["kind"], **details}


def teams_by_policy(summary: dict) -> str | None:
    """The teams named by their policies, "team vs scripted" (a team whose robots play several policies:
    "team+stand"), from a summary's ``played_by``; None where the summary does not say who played."""
    played_by = summary.get("played_by")
    policies = played_by.get("policies") if isinstance(played_by, dict) else None
    if not isinstance(policies, dict):
        return None
    sides: dict[str, list[str]] = {"home": [], "away": []}
    for agent, record in policies.items():
        name = record.get("policy") if isinstance(record, dict) else None
        side = str(agent).split("_")[0]
        if isinstance(name, str) and side in sides and name not in sides[side]:
            sides[side].append(name[:80])
    if not sides["home"] or not sides["away"]:
        return None
    return " vs ".join("+".join(names) for names in sides.values())


SETTING_CHARS = 600  # a setting's text on the page is cut to this many characters


def match_settings(summary: dict) -> list[list[str]]:
    """The settings a match was played with, as ``[name, value]`` rows of text for the page's settings
    panel, from its summary (rows whose value the summary lacks are left out; values cut to
    :data:`SETTING_CHARS` characters)."""
    config = summary.get("config") if isinstance(summary.get("config"), dict) else {}
    world = config.get("world") if isinstance(config.get("world"), dict) else {}
    played_by = summary.get("played_by") if isinstance(summary.get("played_by"), dict) else {}
    rows: list[tuple[str, object]] = []
    policies = played_by.get("policies")
    if isinstance(policies, dict):
        for agent, record in policies.items():
            if isinstance(record, dict):
                details = {key: item for key, item in record.items() if key != "policy"}
                rows.append((str(agent), ", ".join(filter(None, (str(record.get("policy")), _plain(details))))))
    rows += [
        ("seed", summary.get("seed")),
        ("players", _pair(config.get("home_players"), config.get("away_players"))),
        ("half", None if config.get("half_seconds") is None else f"{config['half_seconds']:g} s"),
        ("shoot-out", config.get("shootout")),
        ("controllers", _plain(played_by.get("controllers"))),
        ("camera profile", world.get("camera_profile")),
        ("renderer", (world.get("render") or {}).get("renderer") if isinstance(world.get("render"), dict) else None),
        ("referee", _plain(config.get("referee"))),
        ("radio", _plain(config.get("radio"))),
        ("versions", _plain(summary.get("versions"))),
        ("machine", _plain(summary.get("machine"))),
        ("command", " ".join(str(part) for part in summary["command_line"])
         if isinstance(summary.get("command_line"), list) else None),
    ]
    return [[name, str(value)[:SETTING_CHARS]] for name, value in rows if value is not None]


def _pair(home: object, away: object) -> str | None:
    return None if home is None or away is None else f"{home} v {away}"


def _plain(value: object) -> str | None:
    """A mapping as "key value, key value" text (None stays None)."""
    if isinstance(value, dict):
        return ", ".join(f"{key} {_plain(item) if isinstance(item, dict) else item}" for key, item in value.items())
    return None if value is None else str(value)
