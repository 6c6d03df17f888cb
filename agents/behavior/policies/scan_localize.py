"""The move-scan-localize cycle of thesis chapter 6: a motion, a five-frame head scan, a localization.

The agent decides only from its observation (:mod:`match.protocol.spaces`). It repeats:

1. MOVE: one predefined motion. The robot roams the field: it walks toward a random
   (seeded) waypoint by its own belief, turning to face it first, and one motion in
   ``RANDOM_MOTION_SHARE`` is a random one of :data:`RANDOM_MOTIONS` instead (thesis 6.2:
   "an agent is let to freely choose a random motion and move in the field"). When its
   estimate is within ``EDGE_MARGIN_M`` of the field's edge and it heads out, it turns
   toward the centre first. When the motion finishes
   (``last_motion_sequence`` grows with ``last_motion`` being it; the stand it interrupted
   finishes first), every localizer is told its nominal displacement (``odometry``).
2. SCAN: the head follows :class:`agents.vision.head_scan.HeadScan` with the top camera.
3. LOCALIZE: the scan's fused percepts go to every localizer (the methods run side by side
   on the same percepts and motions, so their errors are paired), and a
   :class:`LocalizationEvent` is recorded.

In a match (``game.state`` from the referee), the thesis' odometer rule applies: the
localizers are reset to the robot's kick-off position at every kick-off (thesis 5.5), and
at the start when no start pose is given. In READY the robot walks to that position by
its own belief (as SPL robots must); in INITIAL, SET and FINISHED it stands. A fallen robot
stands up first and then scans again; a motion a fall cut short still counts with the
nominal displacement of the part played.

The harness (never the agent) pairs each event with the true pose at that moment.
"""

from __future__ import annotations

import enum
import logging
import math
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from agents.localization import LOCALIZERS, PoseEstimate, localizer
from agents.localization.estimate import EstimateSource
from agents.observation import Observation
from agents.vision.frame import CameraFrame
from agents.vision.head_scan import HeadScan
from agents.vision.percepts import LandmarkPercept
from agents.vision.pipeline import VisionPipeline
from match.protocol import CameraChoice, GameState, KickOff, Motion, kickoff_pose, make_action
from world.field import FIELD, Pose2D, normalize_angle

LOG = logging.getLogger(__name__)

# The random motions of scenario 1 (thesis 6.2 names walks, side steps and turns).
RANDOM_MOTIONS: tuple[Motion, ...] = (
    Motion.FORWARD,
    Motion.FORWARD,
    Motion.BACKWARD,
    Motion.SIDE_STEP_LEFT,
    Motion.SIDE_STEP_RIGHT,
    Motion.TURN_LEFT_40,
    Motion.TURN_RIGHT_40,
    Motion.TURN_LEFT_60,
    Motion.TURN_RIGHT_60,
)
EDGE_MARGIN_M = 0.6  # nearer the field's edge than this (by the agent's belief), turn inward
HEADING_OUT_RAD = math.radians(60.0)  # near the edge, walk on only when facing within this of the centre
# Ours: the thesis does not say how its robot chose motions. Pure random motions keep the
# robot within about a square metre in 50 motions; walking to waypoints makes it roam the
# field, as the traces of thesis figures 6.1-6.6 do.
RANDOM_MOTION_SHARE = 0.3
WAYPOINT_MARGIN_M = 0.5  # waypoints are drawn at least this far inside the field lines
WAYPOINT_REACHED_M = 0.35  # by the belief; then a new waypoint is drawn
WAYPOINT_FACING_RAD = math.radians(25.0)  # walk forward when the waypoint is within this of the heading
KICKOFF_HEADING_RAD = math.radians(30.0)  # in READY, at the kick-off position, turn until facing within this
WIDE_TURN_RAD = math.radians(50.0)  # farther off than this, turn 60 degrees; nearer, 40
_HELD_STATES = (GameState.INITIAL, GameState.SET, GameState.FINISHED)  # the referee holds robots still

DEFAULT_METHODS: tuple[str, ...] = tuple(LOCALIZERS)  # every method side by side; the first steers
NO_PERCEPTS = "no usable percepts in the scan"  # the reason of an estimate kept from before the scan


class Phase(enum.Enum):
    MOVE = "move"
    SCAN = "scan"


@dataclass(frozen=True)
class LocalizationEvent:
    """One localization after a scan: what every method estimated, from the same percepts.

    ``index``: the event's number (0, 1, ...); ``step``: the agent's control step count;
    ``estimates``: (method name, estimate) in the order of the agent's methods; when a
    method found nothing usable in the scan, its estimate is the pose it goes on with
    (source ``odometer``, reason :data:`NO_PERCEPTS`), None only if it has none;
    ``percepts``: the fused percepts of the scan; ``compute_ms``: the wall time each
    method's ``localize`` took, same order.
    """

    index: int
    step: int
    estimates: tuple[tuple[str, PoseEstimate | None], ...]
    percepts: tuple[LandmarkPercept, ...]
    compute_ms: tuple[float, ...] = ()


class ScanLocalizeAgent:
    """A policy (:class:`match.protocol.policy.Policy`) running the cycle with several localizers.

    ``methods``: localizer names (see :func:`agents.localization.localizer`); the first one
    steers the motion choice and is the pose :meth:`pose_estimate` reports. ``start``: the
    pose the robot is placed at, known to it (the thesis resets the odometer there);
    ``None``: its kick-off position, read from the first observation's game-control view.
    The seed of :meth:`reset` seeds the motion choice and the particle filters.
    """

    def __init__(
        self,
        methods: Sequence[str] = DEFAULT_METHODS,
        start: Pose2D | None = None,
        camera_model: str = "exact",
    ):
        if not methods:
            raise ValueError("methods must name at least one localizer")
        for name in methods:
            localizer(name)  # raises on an unknown name now, not at reset
        self.methods = tuple(methods)
        self.start = start
        self.pipeline = VisionPipeline(camera_model)
        self.reset("", 0)

    def reset(self, agent_id: str, seed: int) -> None:
        """Forget every estimate and event; seed the motion choice and the localizers."""
        seeds = np.random.SeedSequence(seed).spawn(len(self.methods) + 1)
        self.agent_id = agent_id
        self.localizers = {
            name: localizer(name, seed=int(s.generate_state(1)[0])) for name, s in zip(self.methods, seeds[1:])
        }
        self.rng = np.random.default_rng(seeds[0])
        start = self.start
        self.belief = start if start is not None else Pose2D(0.0, 0.0, 0.0)
        if start is not None:
            self._reset_localizers(start)
        self.waypoint = self._draw_waypoint()
        self.events: list[LocalizationEvent] = []
        self.phase = Phase.MOVE
        self.step = 0
        self._motion: Motion | None = None
        self._sequence: int | None = None
        self._scan: HeadScan | None = None
        self._needs_start = start is None
        self._state: GameState | None = None

    def pose_estimate(self) -> tuple[float, float, float] | None:
        """The guiding method's pose as of the last localization or kick-off (m, m, rad; field frame)."""
        return (self.belief.x, self.belief.y, self.belief.theta)

    def act(self, observation: Observation | Mapping[str, Any]) -> dict:
        obs = Observation.of(observation)
        self.step += 1
        sequence = obs.last_motion_sequence
        if self._sequence is None:
            self._sequence = sequence
        state = obs.game.state
        if self._needs_start or (self._state is GameState.SET and state is GameState.PLAYING):
            self._needs_start = False
            self._reset_localizers(self._kickoff_pose(obs))  # thesis 5.5: reset at kick-off
        self._state = state
        self._take_finished_motion(obs, sequence)
        if obs.fallen or self._standing_up(obs):
            return self._stand_up(obs)
        if self.phase is Phase.MOVE:
            return self._move(obs, sequence, state)
        return self._scan_step(obs)

    # ---- phases --------------------------------------------------------------------------

    def _take_finished_motion(self, obs: Observation, sequence: int) -> None:
        """Feed the chosen motion's nominal displacement to every localizer once it finished, then scan.

        A motion cut short (a fall) finishes too, with the displacement of the part played.
        """
        if self._motion is None or sequence == self._sequence:
            return
        if obs.last_motion is not self._motion:
            return  # the stand it interrupted, or a stand-up, finished first
        self._sequence = sequence
        for loc in self.localizers.values():
            loc.move(obs.odometry)
        self._motion = None
        self._start_scan()

    def _move(self, obs: Observation, sequence: int, state: GameState) -> dict:
        if state in _HELD_STATES:
            self._motion = None
            return make_action(Motion.STAND, head=(0.0, 0.3), camera=CameraChoice.OFF)
        if self._motion is None:
            if state is GameState.READY:
                self._motion = self._ready_motion(self._kickoff_pose(obs))
                if self._motion is None:
                    return make_action(Motion.STAND, head=(0.0, 0.3), camera=CameraChoice.OFF)
            else:
                self._motion = self._choose_motion()
            self._sequence = sequence
        return make_action(self._motion, head=(0.0, 0.3), camera=CameraChoice.OFF)  # no image needed while moving

    @staticmethod
    def _standing_up(obs: Observation) -> bool:
        return obs.motion is not None and obs.motion.is_stand_up

    def _stand_up(self, obs: Observation) -> dict:
        """Get up; afterwards scan again (frames taken while falling are of no use)."""
        self._motion = None
        self._start_scan()
        if obs.motion is not None and obs.motion.is_stand_up:
            motion = obs.motion
        else:  # lying on the back reads about +9.81 m/s^2 on torso x, on the front about -9.81
            back = obs.accelerometer_mps2[0] > 0.0
            motion = Motion.STAND_UP_FROM_BACK if back else Motion.STAND_UP_FROM_FRONT
        return make_action(motion, head=(0.0, 0.0), camera=CameraChoice.OFF)

    def _start_scan(self) -> None:
        self._scan = HeadScan(self.pipeline)
        self.phase = Phase.SCAN

    def _scan_step(self, obs: Observation) -> dict:
        scan = self._scan
        assert scan is not None
        if obs.image is not None:
            scan.feed(CameraFrame.from_observation(obs))
        if scan.done:
            self._localize(scan.result().percepts)
            self.phase = Phase.MOVE
            return self._move(obs, obs.last_motion_sequence, self._state or GameState.PLAYING)
        target = scan.target
        return make_action(Motion.STAND, head=(target.yaw_rad, target.pitch_rad), camera=CameraChoice.TOP)

    def _localize(self, percepts: tuple[LandmarkPercept, ...]) -> None:
        results, compute_ms = [], []
        for name in self.methods:
            loc = self.localizers[name]
            started = time.perf_counter()
            estimate = loc.localize(percepts)
            compute_ms.append((time.perf_counter() - started) * 1e3)
            if estimate is None and loc.pose is not None:
                # Nothing usable in the scan: the robot goes on with the pose it has (thesis 5.5).
                pose = loc.pose
                estimate = PoseEstimate(pose.x, pose.y, pose.theta, name, EstimateSource.ODOMETER, reason=NO_PERCEPTS)
            results.append((name, estimate))
        estimates = tuple(results)
        guide = estimates[0][1]
        if guide is not None:
            self.belief = Pose2D(guide.x_m, guide.y_m, guide.theta_rad)
        self.events.append(LocalizationEvent(len(self.events), self.step, estimates, percepts, tuple(compute_ms)))
        LOG.debug("localization %d: %d percepts, %s", len(self.events) - 1, len(percepts), estimates)

    def _choose_motion(self) -> Motion:
        """Turn inward when heading out near the edge; else a random motion or a step toward the waypoint."""
        b = self.belief
        near_x = abs(b.x) > FIELD.half_length - EDGE_MARGIN_M
        near_y = abs(b.y) > FIELD.half_width - EDGE_MARGIN_M
        if near_x or near_y:
            off = normalize_angle(math.atan2(-b.y, -b.x) - b.theta)
            if abs(off) > HEADING_OUT_RAD:
                return Motion.TURN_LEFT_60 if off > 0 else Motion.TURN_RIGHT_60
        if self.rng.random() < RANDOM_MOTION_SHARE:
            return RANDOM_MOTIONS[int(self.rng.integers(len(RANDOM_MOTIONS)))]
        if math.hypot(self.waypoint[0] - b.x, self.waypoint[1] - b.y) < WAYPOINT_REACHED_M:
            self.waypoint = self._draw_waypoint()
        off = normalize_angle(math.atan2(self.waypoint[1] - b.y, self.waypoint[0] - b.x) - b.theta)
        return Motion.FORWARD if abs(off) <= WAYPOINT_FACING_RAD else _turn_toward(off)

    def _ready_motion(self, target: Pose2D) -> Motion | None:
        """In READY: a step toward the kick-off position by the belief, a turn to its heading, or None there."""
        b = self.belief
        if math.hypot(target.x - b.x, target.y - b.y) >= WAYPOINT_REACHED_M:
            off = normalize_angle(math.atan2(target.y - b.y, target.x - b.x) - b.theta)
            if abs(off) <= WAYPOINT_FACING_RAD:
                return Motion.FORWARD
        else:
            off = normalize_angle(target.theta - b.theta)
            if abs(off) <= KICKOFF_HEADING_RAD:
                return None
        return _turn_toward(off)

    def _reset_localizers(self, pose: Pose2D) -> None:
        for loc in self.localizers.values():
            loc.reset(pose)
        self.belief = pose

    @staticmethod
    def _kickoff_pose(obs: Observation) -> Pose2D:
        """This robot's kick-off position from the game-control view of its observation."""
        return kickoff_pose(obs.player, obs.game.kickoff is KickOff.OWN_TEAM, obs.game.defended_goal)

    def _draw_waypoint(self) -> tuple[float, float]:
        """A uniform point on the field, ``WAYPOINT_MARGIN_M`` inside its lines (m, field frame)."""
        x = self.rng.uniform(-FIELD.half_length + WAYPOINT_MARGIN_M, FIELD.half_length - WAYPOINT_MARGIN_M)
        y = self.rng.uniform(-FIELD.half_width + WAYPOINT_MARGIN_M, FIELD.half_width - WAYPOINT_MARGIN_M)
        return (float(x), float(y))


def _turn_toward(off_rad: float) -> Motion:
    """The predefined turn that brings a direction ``off_rad`` away (CCW positive) nearer the heading."""
    if abs(off_rad) > WIDE_TURN_RAD:
        return Motion.TURN_LEFT_60 if off_rad > 0 else Motion.TURN_RIGHT_60
    return Motion.TURN_LEFT_40 if off_rad > 0 else Motion.TURN_RIGHT_40
