"""The obstacle model: the other robots (and whatever the sonars hear) around the robot.

Entries live in the robot's torso frame (x forward, y left; metres), where walking around
them needs them, and are moved by the robot's own odometry every step, as the ball model's
state is (:mod:`agents.modelling.ball_model`); obstacles are taken to stand still. They come
from two sources:

- robots seen by their waistbands (:mod:`agents.vision.robots`): teammate or opponent;
- sonar echoes: the four sonars (upper-left, upper-right, lower-left, lower-right) look
  20 degrees to each side, each over a cone about 50 degrees wide; an echo nearer than
  :data:`HEAR_BELOW_M` is an obstacle of unknown kind on its sonar's axis, or straight ahead
  when both sides hear it at about the same range (the cones overlap there). A silent sonar
  clears nothing: what it misses between its few rays may still be there.

An observation near an entry (within :data:`MERGE_GATE_M` plus :data:`MERGE_GATE_PER_M` of
its distance) refreshes that entry, moved part way toward it; entries that come to lie
within :data:`MERGE_DISTANCE_M` of each other merge. A seen robot is forgotten after
:data:`EXPIRY_S` unseen, an echo after :data:`ECHO_EXPIRY_S` unheard.
"""

from __future__ import annotations

import enum
import logging
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, replace

from agents.vision.robots import BODY_RADIUS_M, RobotKind, RobotPercept
from match.protocol import Displacement

LOG = logging.getLogger(__name__)

DEFAULT_STEP_S = 0.04  # one control step of the match
EXPIRY_S = 3.0  # ours: a robot unseen this long may have walked away
ECHO_EXPIRY_S = 1.0  # ours: sonars are read every step, so an echo not heard for a second is gone
MERGE_GATE_M = 0.3  # ours: a sighting this near an entry (plus the next, per metre of its
MERGE_GATE_PER_M = 0.1  # distance: vision's range error grows with it) is that entry again
MERGE_DISTANCE_M = 0.25  # ours: two entries nearer than this are one obstacle (robots are 0.15 m wide)
UPDATE_GAIN = 0.6  # ours: how far an entry moves toward a new sighting (robots walk about)
MAX_OBSTACLES = 16  # ours: the oldest entries go beyond this
# The sonars (docs/design/world.md section 4.2; tests/test_robot_perception.py checks them against
# the world's sensor configuration): 20 degrees to each side, 0.25-2.55 m, mounted about
# 0.06 m ahead of the torso centre.
SONAR_YAW_RAD = math.radians(20.0)
SONAR_MIN_RANGE_M = 0.25
SONAR_FORWARD_M = 0.06
SONAR_COUNT = 4
HEAR_BELOW_M = 1.2  # ours: farther echoes (goal frames, walls, distant robots) are not obstacles yet
AHEAD_WITHIN_M = 0.1  # ours: both sides hearing echoes this close in range hear one obstacle ahead
CORRIDOR_HALF_WIDTH_M = 0.25  # ours: half a robot with its arms (0.12 m) and half another, with margin


class ObstacleModelError(ValueError):
    """An input the obstacle model does not accept (names the value)."""


class ObstacleKind(enum.Enum):
    """What an obstacle is: a robot of the own team, one of the other team, or only an echo."""

    TEAMMATE = "teammate"
    OPPONENT = "opponent"
    UNKNOWN = "unknown"


@dataclass(frozen=True)
class Obstacle:
    """One obstacle: its centre ``x_m`` (forward), ``y_m`` (left) in the torso frame (m), its
    kind, and ``age_s``, the time since it was last seen or heard (s)."""

    x_m: float
    y_m: float
    kind: ObstacleKind
    age_s: float

    @property
    def distance_m(self) -> float:
        return math.hypot(self.x_m, self.y_m)

    @property
    def bearing_rad(self) -> float:
        return math.atan2(self.y_m, self.x_m)


def kind_of_percept(percept: RobotPercept) -> ObstacleKind:
    return ObstacleKind.TEAMMATE if percept.kind is RobotKind.TEAMMATE else ObstacleKind.OPPONENT


def first_in_path(
    obstacles: Iterable[Obstacle],
    direction_rad: float,
    within_m: float,
    half_width_m: float = CORRIDOR_HALF_WIDTH_M,
) -> Obstacle | None:
    """The nearest obstacle whose centre lies in the corridor ``half_width_m`` wide to each
    side of the ray from the robot toward ``direction_rad`` (torso frame, CCW), at most
    ``within_m`` ahead along it; None when the corridor is clear."""
    c, s = math.cos(direction_rad), math.sin(direction_rad)
    best: Obstacle | None = None
    best_along = math.inf
    for obstacle in obstacles:
        along = c * obstacle.x_m + s * obstacle.y_m
        across = -s * obstacle.x_m + c * obstacle.y_m
        if 0.0 < along <= within_m and abs(across) < half_width_m and along < best_along:
            best, best_along = obstacle, along
    return best


class ObstacleModel:
    """``predict(moved)`` every step, ``see(percepts)`` with every frame's robots,
    ``hear_sonar(sonar_m)`` with every step's sonars; ``obstacles()`` and ``blocking()`` to read."""

    def __init__(self) -> None:
        self._entries: list[Obstacle] = []

    def reset(self) -> None:
        self._entries = []

    def obstacles(self) -> tuple[Obstacle, ...]:
        """The obstacles believed now, nearest first."""
        return tuple(sorted(self._entries, key=lambda o: o.distance_m))

    def blocking(self, direction_rad: float, within_m: float) -> Obstacle | None:
        """The nearest obstacle in the robot's way toward ``direction_rad`` (rad, torso frame)
        within ``within_m`` metres (see :func:`first_in_path`), or None."""
        return first_in_path(self._entries, direction_rad, within_m)

    def predict(self, moved: Displacement, dt_s: float = DEFAULT_STEP_S) -> None:
        """Let ``dt_s`` seconds pass while the robot moved by ``moved`` (its frame at the start
        of the step): every entry ages and is carried into the robot's new frame."""
        if not (math.isfinite(dt_s) and dt_s >= 0.0):
            raise ObstacleModelError(f"dt_s must be a finite number of seconds >= 0; got {dt_s!r}")
        c, s = math.cos(moved.turn_rad), math.sin(moved.turn_rad)
        kept = []
        for entry in self._entries:
            dx, dy = entry.x_m - moved.forward_m, entry.y_m - moved.left_m
            moved_entry = Obstacle(c * dx + s * dy, -s * dx + c * dy, entry.kind, entry.age_s + dt_s)
            if moved_entry.age_s <= _expiry_s(moved_entry.kind):
                kept.append(moved_entry)
        self._entries = kept

    def see(self, percepts: Iterable[RobotPercept]) -> None:
        """The robots of one camera frame (robot-relative percepts of :mod:`agents.vision.robots`)."""
        for percept in percepts:
            self._observe(percept.x_m, percept.y_m, kind_of_percept(percept))
        self._merge()

    def hear_sonar(self, sonar_m: Sequence[float]) -> None:
        """One step's sonar ranges (m): upper-left, upper-right, lower-left, lower-right."""
        readings = tuple(map(float, sonar_m))
        if len(readings) != SONAR_COUNT or not all(map(math.isfinite, readings)):
            raise ObstacleModelError(
                f"sonar_m must be {SONAR_COUNT} finite ranges (upper-left, upper-right, lower-left, lower-right); got {sonar_m!r}"
            )
        left, right = min(readings[0], readings[2]), min(readings[1], readings[3])
        # A sonar reads no nearer than its minimum range: an echo there is at least that near.
        left, right = max(left, SONAR_MIN_RANGE_M), max(right, SONAR_MIN_RANGE_M)
        heard = [(side, r) for side, r in ((1.0, left), (-1.0, right)) if r < HEAR_BELOW_M]
        if len(heard) == 2 and abs(left - right) <= AHEAD_WITHIN_M:
            heard = [(0.0, min(left, right))]
        for side, reading in heard:
            yaw = side * SONAR_YAW_RAD
            reach = reading + BODY_RADIUS_M  # the echo comes from the near side of the obstacle
            self._observe(SONAR_FORWARD_M + reach * math.cos(yaw), reach * math.sin(yaw), ObstacleKind.UNKNOWN)
        self._merge()

    # ---- internals -----------------------------------------------------------------------

    def _observe(self, x_m: float, y_m: float, kind: ObstacleKind) -> None:
        """Refresh the nearest entry that fits an observation at (x, y), or add one."""
        distance = math.hypot(x_m, y_m)
        gate = MERGE_GATE_M + MERGE_GATE_PER_M * distance
        nearest, nearest_d = None, math.inf
        for i, entry in enumerate(self._entries):
            d = math.hypot(entry.x_m - x_m, entry.y_m - y_m)
            if d < gate and d < nearest_d and _compatible(entry.kind, kind):
                nearest, nearest_d = i, d
        if nearest is None:
            self._entries.append(Obstacle(x_m, y_m, kind, 0.0))
            LOG.debug("new %s obstacle at (%.2f, %.2f) m", kind.value, x_m, y_m)
            if len(self._entries) > MAX_OBSTACLES:
                self._entries.remove(max(self._entries, key=lambda o: o.age_s))
            return
        entry = self._entries[nearest]
        if kind is ObstacleKind.UNKNOWN and entry.kind is not ObstacleKind.UNKNOWN:
            # An echo confirms a seen robot is still there; its bearing is vaguer than vision's.
            self._entries[nearest] = replace(entry, age_s=0.0)
            return
        self._entries[nearest] = Obstacle(
            entry.x_m + UPDATE_GAIN * (x_m - entry.x_m), entry.y_m + UPDATE_GAIN * (y_m - entry.y_m), kind, 0.0
        )

    def _merge(self) -> None:
        """Merge entries nearer than :data:`MERGE_DISTANCE_M` to each other: the fresher one's
        position, the known kind, the smaller age."""
        merged: list[Obstacle] = []
        for entry in sorted(self._entries, key=lambda o: o.age_s):
            for i, kept in enumerate(merged):
                near = math.hypot(kept.x_m - entry.x_m, kept.y_m - entry.y_m) < MERGE_DISTANCE_M
                if near and _compatible(kept.kind, entry.kind):
                    kind = kept.kind if kept.kind is not ObstacleKind.UNKNOWN else entry.kind
                    merged[i] = replace(kept, kind=kind)
                    break
            else:
                merged.append(entry)
        self._entries = merged


def _compatible(a: ObstacleKind, b: ObstacleKind) -> bool:
    """Whether two kinds can be one obstacle: equal, or one of them unknown."""
    return a is b or ObstacleKind.UNKNOWN in (a, b)


def _expiry_s(kind: ObstacleKind) -> float:
    return ECHO_EXPIRY_S if kind is ObstacleKind.UNKNOWN else EXPIRY_S
