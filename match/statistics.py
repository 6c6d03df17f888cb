"""Match statistics: what each team did in one match, from its events, its log and its summary.

:func:`match_statistics` is pure: it reads the events as written to ``events.jsonl`` (dicts
with ``time_s``, ``kind`` and the details), the arrays of ``match_log.npz`` and the
summary's ``radio`` and ``faults`` blocks, and returns one dict per team. Teams are named by
side (``home``, ``away``), never by colour: colours and goals swap at half-time.

Definitions (playing time is the game state PLAYING before the penalty shoot-out; the
shoot-out's kicks count for nothing here):

- ``goals``: goals the team scored in playing time (an opponent's own goal included);
  ``own_goals``: goals into the team's own goal that one of its robots touched last, unless
  the scoring team's last touch before was a shot on target (a save that failed, or any
  deflection of a shot that was going in, leaves the goal to the shooter, as in football);
- ``shots_on_target``: touches of the team after which (before the next touch) the ball
  moves toward the goal line inside the goal area the team attacks (the 0.6 x 2.2 m area
  and the goal behind it), or leaves on a line that crosses that goal line between the
  posts fast enough to roll there (its motion over :data:`SHOT_WINDOW_S` after the touch,
  or until another robot's touch; so a shot deflected at once still counts); one per
  touch, so a shot that scores counts once; of those, ``shots_scored`` (the team scored
  before one of its robots touched the ball again: a deflection by the other team still
  scores), ``shots_saved`` (not scored, and the other team's goalkeeper touched it first) and
  ``shots_blocked`` (not scored, and another robot of the other team touched it first); the
  rest went out or were played on by the shooter's team;
- ``touches``: ball touches in playing time (the referee's touch events);
- ``possession``: share of playing time in which the team touched the ball last (time
  before the first touch counts for neither team; NaN-free: None when nobody touched it);
- ``balls_out``: balls out of the field the team touched last;
- ``falls``, ``robots_replaced`` (off the carpet or down too long), ``faults`` (policy
  failures): over the whole match;
- ``radio_sent``, ``radio_dropped`` (over the send budget), ``radio_received`` (packets in
  the team's inboxes): over the whole match, from the runner's per-team radio counts;
- ``position_error_mean_m``, ``position_error_p95_m``, ``orientation_error_mean_deg``,
  ``orientation_error_p95_deg``: over every control step of playing time and every robot
  of the team whose policy reported a pose estimate (None when none did), while the robot
  was up (a lying robot's torso gives it no heading, and the point under it is not where it
  stands: its steps from the fall until it stood again do not count);
  ``pose_estimates`` counts those robot-steps; ``lost_share``: the share of them more than
  :data:`LOST_M` off; the same with a ``field_`` prefix over the field players alone (every
  robot but the goalkeeper, player 0);
- ``longest_still_s``: the longest stretch of playing time in which one of the team's robots
  stayed within :data:`STILL_M` and :data:`STILL_RAD` of where it was (a stuck robot; a
  goalkeeper with the ball far away may also stand); ``longest_still_field_s``: the same
  over the field players alone (every robot but the goalkeeper, player 0);
- ``longest_stuck_s``: the most playing time, within one such still stretch of one robot of
  the team, in which the robot's own policy asked it to move (a motion other than a stand, a
  walk command other than zero): a robot that wants to move and does not, jammed or dithering
  (a robot that stands on purpose, a defender holding its place, is still but not stuck);
  ``longest_stuck_field_s``: the same over the field players alone; both None for a log
  without actions;

and for the match, ``restart_waits_s``: the time from each kick-off and throw-in to the next
touch of the ball, in order (a restart nobody touched counts until the next restart,
half-time or the end of play); ``restart_max_s``, the longest of them (None without
restarts); ``restarts_slow``, how many took longer than :data:`RESTART_SLOW_S`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np

from match.protocol.actions import Action
from match.protocol.game_control import GameState
from match.protocol.ids import AgentId
from world.field import FIELD
from world.motions import Motion

SIDES = ("home", "away")
PLAYING = int(GameState.PLAYING)
SHOOTOUT = "PENALTY_SHOOTOUT"  # the secondary state of the shoot-out's state events
PLACED_STEP_M = 0.3  # a ball moving this far in one 40 ms step (7.5 m/s) was placed, not played
GOALWARD_STEP_M = 1e-3  # moving toward the goal line: at least this far in one step (2.5 cm/s)
TIME_TOLERANCE_S = 1e-3  # event times are rounded to the millisecond
LOST_M = 0.5  # a pose estimate farther off than this is lost
STILL_M = 0.1  # a robot that stays within this of a place ...
STILL_RAD = math.radians(15.0)  # ... and of a heading, stands still
RESTART_KINDS = ("kickoff", "throw_in")
RESTART_SLOW_S = 10.0  # ours: a restart not touched within this long is slow (the team agents' target)
SHOT_WINDOW_S = 0.4  # a shot's line: the ball's motion over this long after the touch ...
BALL_DECEL_MPS2 = 0.4  # ... and its reach at this rolling deceleration (measured: 1.25 m/s rolls 2 m)

TEAM_KEYS = (
    "goals",
    "own_goals",
    "shots_on_target",
    "shots_scored",
    "shots_saved",
    "shots_blocked",
    "touches",
    "possession",
    "balls_out",
    "falls",
    "robots_replaced",
    "radio_sent",
    "radio_dropped",
    "radio_received",
    "faults",
    "pose_estimates",
    "position_error_mean_m",
    "position_error_p95_m",
    "orientation_error_mean_deg",
    "orientation_error_p95_deg",
    "lost_share",
    "field_pose_estimates",
    "field_position_error_mean_m",
    "field_position_error_p95_m",
    "field_orientation_error_mean_deg",
    "field_orientation_error_p95_deg",
    "field_lost_share",
    "longest_still_s",
    "longest_still_field_s",
    "longest_stuck_s",
    "longest_stuck_field_s",
)


def side_of(robot: object) -> str | None:
    """``home`` or ``away`` for a robot id such as ``home_2``; None for anything else."""
    if isinstance(robot, str):
        side = robot.partition("_")[0]
        if side in SIDES:
            return side
    return None


def attack_direction(side: str, half: int) -> int:
    """+1 when ``side`` attacks the goal at x = +3 in ``half``, else -1 (home defends blue, x = -3, first)."""
    first = 1 if side == "home" else -1
    return first if half == 1 else -first


def match_statistics(events: Sequence[Mapping], log: Mapping[str, np.ndarray], summary: Mapping) -> dict:
    """``{"playing_seconds": s, "home": {...}, "away": {...}}`` with the keys of :data:`TEAM_KEYS`."""
    cut = _shootout_index(events)
    play_events = events[:cut]
    shootout_s = float(events[cut]["time_s"]) if cut < len(events) else math.inf
    teams = {side: dict.fromkeys(TEAM_KEYS, 0) for side in SIDES}
    touch_rows = [i for i, event in enumerate(play_events) if event["kind"] == "touch"]
    touch_events = [play_events[i] for i in touch_rows]
    touches = [(float(e["time_s"]), side_of(e.get("robot"))) for e in touch_events]
    rows = _playing_rows(log, shootout_s)
    last = _last_touches(touches, np.asarray(log["time_s"], dtype=float)[rows])
    owner = np.array([touches[k][1] if k >= 0 else None for k in last], dtype=object)
    shots = _shots_on_target(log, rows, last, owner) | _shots_by_line(log, touch_events)

    for event in play_events:
        kind = event["kind"]
        if kind == "goal":
            teams[event["team"]]["goals"] += 1
            toucher = side_of(event.get("last_toucher"))
            if toucher is not None and toucher != event["team"] and not _deflected_shot(event, touches, shots):
                teams[toucher]["own_goals"] += 1
        elif kind == "touch" and side_of(event.get("robot")):
            teams[side_of(event["robot"])]["touches"] += 1
        elif kind == "ball_out" and side_of(event.get("last_toucher")):
            teams[side_of(event["last_toucher"])]["balls_out"] += 1
    for event in events:
        counter = {"fall": "falls", "robot_replaced": "robots_replaced"}.get(event["kind"])
        if counter and side_of(event.get("robot")):
            teams[side_of(event["robot"])][counter] += 1

    for agent, count in (summary.get("faults") or {}).get("by_agent", {}).items():
        if side_of(agent):
            teams[side_of(agent)]["faults"] += int(count)
    by_side = (summary.get("radio") or {}).get("by_side")
    for side in SIDES:
        radio = (by_side or {}).get(side)
        for key in ("sent", "dropped", "received"):
            teams[side][f"radio_{key}"] = int(radio[key]) if radio else None

    for side in SIDES:
        teams[side]["shots_on_target"] = sum(touches[k][1] == side for k in shots)
    for k in shots:
        outcome = _shot_outcome(play_events, touch_rows[k])
        if outcome is not None:
            teams[touches[k][1]][f"shots_{outcome}"] += 1
    playing_seconds = _from_log(teams, log, rows, owner)
    waits = _restart_waits_s(play_events)
    return {"playing_seconds": round(playing_seconds, 3), "restart_waits_s": waits,
            "restart_max_s": max(waits) if waits else None,
            "restarts_slow": sum(1 for wait in waits if wait > RESTART_SLOW_S), **teams}


def _restart_waits_s(play_events: Sequence[Mapping]) -> list[float]:
    """Each kick-off's and throw-in's time to the next touch (or the next restart, half-time or the end), s."""
    waits = []
    restart_s = None
    for event in play_events:
        kind = event["kind"]
        if restart_s is not None and (kind == "touch" or kind in RESTART_KINDS or kind in ("half_time", "end")):
            waits.append(round(float(event["time_s"]) - restart_s, 3))
            restart_s = None
        if kind in RESTART_KINDS:
            restart_s = float(event["time_s"])
    return waits


def _shootout_index(events: Sequence[Mapping]) -> int:
    """The index of the first event of the penalty shoot-out (len(events) without one)."""
    for i, event in enumerate(events):
        if event["kind"] == "state" and event.get("secondary") == SHOOTOUT:
            return i
    return len(events)


def _playing_rows(log: Mapping[str, np.ndarray], shootout_s: float) -> np.ndarray:
    """The log rows (from 1 on) in playing time before the shoot-out."""
    time_s = np.asarray(log["time_s"], dtype=float)
    state = np.asarray(log["state"])
    rows = np.arange(1, time_s.size)
    return rows[(state[rows] == PLAYING) & (time_s[rows] <= shootout_s + TIME_TOLERANCE_S)]


def _last_touches(touches: Sequence[tuple[float, str | None]], time_s: np.ndarray) -> np.ndarray:
    """The index of the touch each time's ball was last touched by (-1: none yet)."""
    touch_times = np.array([t for t, _ in touches], dtype=float)
    return np.searchsorted(touch_times, time_s + TIME_TOLERANCE_S, side="right") - 1


def _shots_on_target(log: Mapping[str, np.ndarray], rows: np.ndarray, last: np.ndarray,
                     owner: np.ndarray) -> set[int]:
    """The indices of the touches that were shots on target (see the module); ``rows``: the playing
    rows, ``last``: the touch each of them was last touched by (-1: none), ``owner``: its team."""
    half = np.asarray(log["half"])
    ball = np.asarray(log["ball"], dtype=float)
    step = ball[rows, :2] - ball[rows - 1, :2]
    played = np.hypot(step[:, 0], step[:, 1]) < PLACED_STEP_M
    x, y = ball[rows, 0], ball[rows, 1]
    shots: set[int] = set()
    for side in SIDES:
        g = np.array([attack_direction(side, int(h)) for h in half[rows]], dtype=float)
        in_area = (g * x >= FIELD.goal_area_x) & (g * x <= FIELD.half_length + FIELD.goal_depth) & (
            np.abs(y) <= FIELD.goal_area_half_width)
        shot_rows = in_area & (g * step[:, 0] > GOALWARD_STEP_M) & played & (owner == side)
        shots.update(int(k) for k in np.unique(last[shot_rows]))
    return shots


def _shots_by_line(log: Mapping[str, np.ndarray], touch_events: Sequence[Mapping]) -> set[int]:
    """The indices of the touches after which the ball's line crosses the attacked goal line between the
    posts, fast enough to roll there (see the module)."""
    time_s = np.asarray(log["time_s"], dtype=float)
    ball = np.asarray(log["ball"], dtype=float)
    half = np.asarray(log["half"])
    state = np.asarray(log["state"])
    shots: set[int] = set()
    for k, touch in enumerate(touch_events):
        side, robot, t0 = side_of(touch.get("robot")), touch.get("robot"), float(touch["time_s"])
        end_s = t0 + SHOT_WINDOW_S
        for later in touch_events[k + 1:]:
            if float(later["time_s"]) >= end_s:
                break
            if later.get("robot") != robot:
                end_s = float(later["time_s"])
                break
        first = int(np.searchsorted(time_s, t0 + TIME_TOLERANCE_S, side="right")) - 1
        last = int(np.searchsorted(time_s, end_s + TIME_TOLERANCE_S, side="right")) - 1
        if side is None or first < 0 or last <= first or not (state[first:last + 1] == PLAYING).all():
            continue
        moved = ball[last, :2] - ball[first, :2]
        speed = math.hypot(*moved) / (time_s[last] - time_s[first])
        g = attack_direction(side, int(half[first]))
        steps = np.diff(ball[first:last + 1, :2], axis=0)
        if g * moved[0] <= 0.0 or (np.hypot(steps[:, 0], steps[:, 1]) >= PLACED_STEP_M).any():
            continue
        to_line = (g * FIELD.half_length - ball[last, 0]) / moved[0]  # in units of ``moved``
        cross_y = ball[last, 1] + to_line * moved[1]
        reach = speed * speed / (2.0 * BALL_DECEL_MPS2)
        if abs(cross_y) <= FIELD.goal_inner_width / 2.0 and to_line * math.hypot(*moved) <= reach:
            shots.add(k)
    return shots


def _shot_outcome(play_events: Sequence[Mapping], row: int) -> str | None:
    """``scored``, ``saved``, ``blocked`` or None for the shot whose touch is ``play_events[row]`` (see the module)."""
    shot = play_events[row]
    side, robot, shot_s = side_of(shot.get("robot")), shot.get("robot"), float(shot["time_s"])
    first_other = None  # what the other team's first touch made of it
    for event in play_events[row + 1:]:
        kind = event["kind"]
        if kind == "goal":
            return "scored" if event["team"] == side else first_other
        if kind == "touch":
            toucher = event.get("robot")
            if toucher == robot and float(event["time_s"]) <= shot_s + SHOT_WINDOW_S:
                continue  # the kick's own contacts
            if side_of(toucher) == side:
                return first_other
            if first_other is None:
                is_keeper = isinstance(toucher, str) and AgentId.parse(toucher).is_goalkeeper
                first_other = "saved" if is_keeper else "blocked"
        elif kind in ("ball_out", "half_time", "end") or kind in RESTART_KINDS:
            return first_other
    return first_other


def _deflected_shot(goal: Mapping, touches: Sequence[tuple[float, str | None]], shots: set[int]) -> bool:
    """Whether the scoring team's last touch before ``goal`` was a shot on target."""
    scorer = goal["team"]
    before = [k for k, (t, side) in enumerate(touches) if t <= float(goal["time_s"]) + TIME_TOLERANCE_S
              and side == scorer]
    return bool(before) and before[-1] in shots


def _from_log(teams: dict, log: Mapping[str, np.ndarray], rows: np.ndarray, owner: np.ndarray) -> float:
    """Possession and pose-estimate errors into ``teams``; returns the playing seconds (``rows`` and
    ``owner`` as for :func:`_shots_on_target`)."""
    time_s = np.asarray(log["time_s"], dtype=float)
    dt = time_s[rows] - time_s[rows - 1]
    held = {side: float(dt[owner == side].sum()) for side in SIDES}
    total = held["home"] + held["away"]
    for side in SIDES:
        teams[side]["possession"] = round(held[side] / total, 4) if total > 0 else None
    _pose_errors(teams, log, rows)
    _stillness(teams, log, rows)
    return float(dt.sum())


def _stillness(teams: dict, log: Mapping[str, np.ndarray], rows: np.ndarray) -> None:
    """The longest stretch of playing time any robot, and any field player, of each team stood still, and
    the longest time one was stuck (see the module)."""
    agents = [str(a) for a in np.asarray(log["agents"])]
    time_s = np.asarray(log["time_s"], dtype=float)
    robots = np.asarray(log["robots"], dtype=float)
    asked = _asked_to_move(log)
    for side in SIDES:
        teams[side]["longest_still_s"] = teams[side]["longest_still_field_s"] = 0.0
        teams[side]["longest_stuck_s"] = teams[side]["longest_stuck_field_s"] = None if asked is None else 0.0
    for i, agent in enumerate(agents):
        side = side_of(agent)
        if side is None or rows.size == 0:
            continue
        moving = np.zeros(rows.size, dtype=bool) if asked is None else asked[rows, i]
        still, stuck = _longest_still_s(robots[rows, i], rows, time_s[rows], moving)
        keys = [("longest_still_s", still), ("longest_stuck_s", stuck)]
        if not AgentId.parse(agent).is_goalkeeper:
            keys += [("longest_still_field_s", still), ("longest_stuck_field_s", stuck)]
        for key, seconds in keys:
            if teams[side][key] is not None:
                teams[side][key] = round(max(teams[side][key], seconds), 3)


def _asked_to_move(log: Mapping[str, np.ndarray]) -> np.ndarray | None:
    """(T, N) bool: the robot's action that led to the row asked it to move (a motion other than a stand, a walk
    command other than zero); None for a log without actions."""
    if not {"motions", "walks", "motion_names"} <= set(log):
        return None
    motions = np.asarray(log["motions"], dtype=int)
    index = {str(name): k for k, name in enumerate(np.asarray(log["motion_names"]))}
    stand, walk = index.get(Motion.STAND.value, -2), index.get(Motion.WALK.value, -2)
    walking = np.any(np.abs(np.asarray(log["walks"], dtype=float)) > 0.0, axis=-1)
    return (motions >= 0) & (motions != stand) & ((motions != walk) | walking)


def _longest_still_s(poses: np.ndarray, rows: np.ndarray, time_s: np.ndarray,
                     asked: np.ndarray) -> tuple[float, float]:
    """The longest stretch (s) of consecutive ``rows`` in which ``poses`` (x, y, theta) stayed put, and the most
    time within one such stretch in which the robot was ``asked`` to move (per row: the step up to it)."""
    longest = stuck = stuck_here = 0.0
    start = 0
    anchor = poses[0]
    for k in range(1, rows.size):
        pose = poses[k]
        gap = rows[k] != rows[k - 1] + 1  # play stopped in between: a new stretch
        moved = (math.hypot(pose[0] - anchor[0], pose[1] - anchor[1]) > STILL_M
                 or abs(math.remainder(pose[2] - anchor[2], math.tau)) > STILL_RAD)
        if gap or moved:
            start, anchor, stuck_here = k, pose, 0.0
        elif asked[k]:
            stuck_here += time_s[k] - time_s[k - 1]
        longest = max(longest, time_s[k] - time_s[start])
        stuck = max(stuck, stuck_here)
    return longest, stuck


def _pose_errors(teams: dict, log: Mapping[str, np.ndarray], rows: np.ndarray) -> None:
    """Pose-estimate errors of every robot, and of the field players alone (``field_`` keys)."""
    agents = [str(a) for a in np.asarray(log["agents"])]
    truth = np.asarray(log["robots"], dtype=float)[rows]
    estimates = np.asarray(log["estimates"], dtype=float)[rows]
    up = ~np.asarray(log["fallen"], dtype=bool)[rows]
    for side in SIDES:
        columns = [i for i, agent in enumerate(agents) if side_of(agent) == side]
        field = [i for i in columns if not AgentId.parse(agents[i]).is_goalkeeper]
        for prefix, chosen in (("", columns), ("field_", field)):
            _estimate_errors(teams[side], prefix, truth[:, chosen].reshape(-1, 3), estimates[:, chosen].reshape(-1, 3),
                             up[:, chosen].reshape(-1))


def _estimate_errors(team: dict, prefix: str, true: np.ndarray, est: np.ndarray, up: np.ndarray) -> None:
    """Means, 95th percentiles and the lost share of (N, 3) estimates against the truth, into ``team``,
    over the rows where the robot was ``up`` (N,) bool."""
    known = np.isfinite(est).all(axis=1) & up
    true, est = true[known], est[known]
    position = np.hypot(est[:, 0] - true[:, 0], est[:, 1] - true[:, 1])
    turn = np.angle(np.exp(1j * (est[:, 2] - true[:, 2])))  # wrapped to [-pi, pi]
    orientation = np.degrees(np.abs(turn))
    team[f"{prefix}pose_estimates"] = int(known.sum())
    for name, errors in (("position_error", position), ("orientation_error", orientation)):
        unit = "m" if name == "position_error" else "deg"
        empty = errors.size == 0
        team[f"{prefix}{name}_mean_{unit}"] = None if empty else round(float(np.mean(errors)), 4)
        team[f"{prefix}{name}_p95_{unit}"] = None if empty else round(float(np.percentile(errors, 95)), 4)
    team[f"{prefix}lost_share"] = None if position.size == 0 else round(float(np.mean(position > LOST_M)), 4)


class TeamRadio:
    """Per-team radio counts of one match, fed by the runner every step.

    ``sent``: packets the radio accepted; ``dropped``: packets over the send budget (each
    robot reads its own in its next observation); ``received``: packets in the team's inboxes.
    """

    def __init__(self) -> None:
        self._handed = dict.fromkeys(SIDES, 0)
        self._dropped = dict.fromkeys(SIDES, 0)
        self._received = dict.fromkeys(SIDES, 0)

    def actions(self, actions: Mapping[str, Action | None]) -> None:
        """The packets handed to the radio with this step's actions."""
        for agent, action in actions.items():
            if action is not None and action.radio and side_of(agent):
                self._handed[side_of(agent)] += 1

    def observations(self, observations: Mapping[str, Mapping]) -> None:
        """The drops and inboxes the step's observations report."""
        for agent, observation in observations.items():
            side = side_of(agent)
            radio = observation.get("radio") if side else None
            if radio is not None:
                self._dropped[side] += int(radio["dropped"])
                self._received[side] += int(radio["count"])

    def to_json(self) -> dict:
        return {
            side: {"sent": self._handed[side] - self._dropped[side], "dropped": self._dropped[side],
                   "received": self._received[side]}
            for side in SIDES
        }
