"""The move-scan-localize cycle of thesis chapter 6: a motion, a five-frame head scan, a localization.

The agent decides only from its observation (:mod:`match.protocol.spaces`). It repeats:

1. MOVE: one predefined motion, random (seeded) but kept on the field by its own belief:
   when its estimate is within ``EDGE_MARGIN_M`` of the field's edge, it turns toward the
   centre until it faces it, then walks forward. When the motion finishes
   (``last_motion_sequence`` grows with ``last_motion`` being it; the stand it interrupted
   finishes first), every localizer is told its nominal displacement (``odometry``).
2. SCAN: the head follows :class:`agents.vision.head_scan.HeadScan` with the top camera.
3. LOCALIZE: the scan's fused percepts go to every localizer (the methods run side by side
   on the same percepts and motions, so their errors are paired), and a
   :class:`LocalizationEvent` is recorded.

The harness (never the agent) pairs each event with the true pose at that moment.
"""

from __future__ import annotations

import enum
import logging
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from agents.localization import PoseEstimate, localizer
from agents.vision.frame import CameraFrame
from agents.vision.head_scan import HeadScan
from agents.vision.percepts import LandmarkPercept
from agents.vision.pipeline import VisionPipeline
from match.protocol import MOTIONS, CameraChoice, Displacement, Motion, make_action
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


class Phase(enum.Enum):
    MOVE = "move"
    SCAN = "scan"


@dataclass(frozen=True)
class LocalizationEvent:
    """One localization after a scan: what every method estimated, from the same percepts.

    ``index``: the event's number (0, 1, ...); ``step``: the agent's control step count;
    ``estimates``: (method name, estimate or None for "no estimate") in the order of the
    agent's methods; ``percepts``: the fused percepts of the scan; ``compute_ms``: the
    wall time each method's ``localize`` took, same order.
    """

    index: int
    step: int
    estimates: tuple[tuple[str, PoseEstimate | None], ...]
    percepts: tuple[LandmarkPercept, ...]
    compute_ms: tuple[float, ...] = ()


class ScanLocalizeAgent:
    """A policy (``act(observation) -> action``) running the cycle with several localizers.

    ``methods``: localizer names (see :func:`agents.localization.localizer`); the first one
    steers the motion choice. ``start``: the pose the robot is placed at (a kick-off
    position: the thesis resets the odometer there). ``seed`` seeds the motion choice and
    the particle filters.
    """

    def __init__(
        self,
        methods: Sequence[str],
        start: Pose2D,
        seed: int = 0,
        camera_model: str = "exact",
    ):
        if not methods:
            raise ValueError("methods must name at least one localizer")
        seeds = np.random.SeedSequence(seed).spawn(len(methods) + 1)
        self.methods = tuple(methods)
        self.localizers = {
            name: localizer(name, seed=int(s.generate_state(1)[0])) for name, s in zip(self.methods, seeds[1:])
        }
        for loc in self.localizers.values():
            loc.reset(start)
        self.rng = np.random.default_rng(seeds[0])
        self.pipeline = VisionPipeline(camera_model)
        self.belief = start
        self.events: list[LocalizationEvent] = []
        self.phase = Phase.MOVE
        self.step = 0
        self._motion: Motion | None = None
        self._sequence: int | None = None
        self._scan: HeadScan | None = None

    def act(self, observation: dict) -> dict:
        self.step += 1
        sequence = int(observation["last_motion_sequence"])
        if self._sequence is None:
            self._sequence = sequence
        if self.phase is Phase.MOVE:
            return self._move(observation, sequence)
        return self._scan_step(observation)

    # ---- phases --------------------------------------------------------------------------

    def _move(self, observation: dict, sequence: int) -> dict:
        finished = int(observation["last_motion"]) == MOTIONS.index(self._motion) if self._motion else False
        if self._motion is not None and sequence != self._sequence and finished:
            self._sequence = sequence
            forward, left, turn = (float(v) for v in np.asarray(observation["odometry"], float))
            for loc in self.localizers.values():
                loc.move(Displacement(forward, left, turn))
            self._motion = None
            self._scan = HeadScan(self.pipeline)
            self.phase = Phase.SCAN
            return self._scan_step(observation)
        if self._motion is None:
            self._motion = self._choose_motion()
            self._sequence = sequence
        return make_action(self._motion, head=(0.0, 0.3), camera=CameraChoice.OFF)  # no image needed while moving

    def _scan_step(self, observation: dict) -> dict:
        scan = self._scan
        assert scan is not None
        if int(observation["camera"]) != int(CameraChoice.OFF):
            scan.feed(CameraFrame.from_observation(observation))
        if scan.done:
            self._localize(scan.result().percepts)
            self.phase = Phase.MOVE
            return self._move(observation, int(observation["last_motion_sequence"]))
        target = scan.target
        return make_action(Motion.STAND, head=(target.yaw_rad, target.pitch_rad), camera=CameraChoice.TOP)

    def _localize(self, percepts: tuple[LandmarkPercept, ...]) -> None:
        results, compute_ms = [], []
        for name in self.methods:
            started = time.perf_counter()
            results.append((name, self.localizers[name].localize(percepts)))
            compute_ms.append((time.perf_counter() - started) * 1e3)
        estimates = tuple(results)
        guide = estimates[0][1]
        if guide is not None:
            self.belief = Pose2D(guide.x_m, guide.y_m, guide.theta_rad)
        self.events.append(LocalizationEvent(len(self.events), self.step, estimates, percepts, tuple(compute_ms)))
        LOG.debug("localization %d: %d percepts, %s", len(self.events) - 1, len(percepts), estimates)

    def _choose_motion(self) -> Motion:
        """A random motion, or a turn toward the centre when the belief is near the edge heading out."""
        b = self.belief
        near_x = abs(b.x) > FIELD.half_length - EDGE_MARGIN_M
        near_y = abs(b.y) > FIELD.half_width - EDGE_MARGIN_M
        if near_x or near_y:
            inward = math.atan2(-b.y, -b.x)
            off = normalize_angle(inward - b.theta)
            if abs(off) > HEADING_OUT_RAD:
                return Motion.TURN_LEFT_60 if off > 0 else Motion.TURN_RIGHT_60
            return Motion.FORWARD
        return RANDOM_MOTIONS[int(self.rng.integers(len(RANDOM_MOTIONS)))]
