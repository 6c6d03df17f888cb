"""The head scan of thesis chapter 5: five frames from left to right, merged into one set.

The head pitches 17 degrees down and pans over five yaws 40 degrees apart, so five 46-degree
frames with little overlap cover about 206 degrees (thesis Figure 5.1). A goal post seen
alone has no side until its crossbar is seen (thesis 4.4 step 4); with the head pitched
down the crossbar is above the image, so for each such post the scan adds a frame with the
head tilted up at the same yaw, where the crossbar leaving the post's top tells the side.

The scan is driven by the agent: it sends :attr:`HeadScan.target` as its head action and
feeds each observation's frame to :meth:`HeadScan.feed`; frames taken while the head is
still moving are skipped. Percepts of all frames are then fused: the same landmark seen in
two frames (same kind and compatible identity, closer than a gate) becomes one percept at
the mean of their ground points.
"""

from __future__ import annotations

import dataclasses
import enum
import logging
import math
from dataclasses import dataclass

import numpy as np

from agents.vision.errors import VisionConfigError
from agents.vision.frame import CameraFrame
from agents.vision.goals import crossbar_sides, post_id
from agents.vision.percepts import LandmarkPercept, PostSide
from agents.vision.pipeline import FrameResult, VisionPipeline
from world.camera_model import NAO_CAMERA, NAO_HEAD, CameraPosition
from world.field import LandmarkKind

LOG = logging.getLogger(__name__)

SCAN_YAWS_RAD = tuple(math.radians(d) for d in (80.0, 40.0, 0.0, -40.0, -80.0))  # thesis 5: left to right
SCAN_PITCH_RAD = math.radians(17.0)  # thesis 4: HeadPitchAngle 17 degrees down, top camera
CROSSBAR_PITCH_RAD = math.radians(-12.0)  # ours: head up; the crossbar (0.8 m) is in view from 0.8 m on
HEAD_SETTLED_RAD = math.radians(1.0)  # a frame counts once the head is this close to its target ...
SETTLE_FRAMES = 3  # ... in this many frames in a row: the torso sways for a while after a head swing
FUSE_GATE_M = 0.35  # two percepts of one landmark closer than max(gate, FUSE_GATE_RELATIVE * distance)
FUSE_GATE_RELATIVE = 0.15
CROSSBAR_MATCH_PX = 10.0  # a post in the tilted frame is the lone post if its column is this close


class ScanPurpose(enum.StrEnum):
    """What a frame of a scan is for."""

    LANDMARKS = "scan"  # a frame of the sweep: its landmark percepts are kept
    CROSSBAR = "crossbar"  # the head tilted up at a lone post's yaw: only the post's side is read


@dataclass(frozen=True)
class HeadTarget:
    """Where the head should point for the next frame of a scan.

    Head joint angles in rad: ``yaw_rad`` CCW positive from the torso's forward,
    ``pitch_rad`` positive down.
    """

    yaw_rad: float
    pitch_rad: float
    purpose: ScanPurpose


@dataclass(frozen=True, eq=False)
class ScanResult:
    """The fused percepts of one scan and the results of every frame it used."""

    percepts: tuple[LandmarkPercept, ...]
    frames: tuple[FrameResult, ...]


class HeadScan:
    """One scan: head targets to send, frames to feed, fused percepts when done."""

    def __init__(
        self,
        pipeline: VisionPipeline,
        yaws_rad: tuple[float, ...] = SCAN_YAWS_RAD,
        pitch_rad: float = SCAN_PITCH_RAD,
        look_for_crossbars: bool = True,
    ):
        low, high = NAO_HEAD.yaw_limits_rad
        if not yaws_rad or not all(low <= y <= high for y in yaws_rad):
            raise VisionConfigError(f"scan yaws must be 1 or more angles within {low:.3f}..{high:.3f} rad; got {yaws_rad}")
        low, high = NAO_HEAD.pitch_limits_rad
        if not low <= pitch_rad <= high:
            raise VisionConfigError(f"scan pitch must be within {low:.3f}..{high:.3f} rad; got {pitch_rad}")
        self.pipeline = pipeline
        self.look_for_crossbars = look_for_crossbars
        self._queue = [HeadTarget(y, pitch_rad, ScanPurpose.LANDMARKS) for y in yaws_rad]
        self._frames: list[FrameResult] = []
        self._percepts: list[list[LandmarkPercept]] = []
        self._lone_posts: list[tuple[int, int, HeadTarget]] = []  # (frame, percept index, target)
        self._frames_at_target = 0

    @property
    def target(self) -> HeadTarget | None:
        """The head target of the next frame; None when the scan is done."""
        return self._queue[0] if self._queue else None

    @property
    def done(self) -> bool:
        return not self._queue

    def feed(self, frame: CameraFrame) -> bool:
        """Use ``frame`` if it was taken at the current target (top camera); True if used."""
        target = self.target
        if target is None or frame.camera is not CameraPosition.TOP:
            return False
        at_target = abs(frame.head_yaw_rad - target.yaw_rad) <= HEAD_SETTLED_RAD
        at_target &= abs(frame.head_pitch_rad - target.pitch_rad) <= HEAD_SETTLED_RAD
        self._frames_at_target = self._frames_at_target + 1 if at_target else 0
        if self._frames_at_target < SETTLE_FRAMES:
            return False
        self._frames_at_target = 0
        self._queue.pop(0)
        if target.purpose is ScanPurpose.CROSSBAR:
            self._resolve_sides(frame)
            return True
        result = self.pipeline.process(frame)
        self._frames.append(result)
        self._percepts.append(list(result.percepts))
        if self.look_for_crossbars:
            for index, percept in enumerate(result.percepts):
                if percept.kind is LandmarkKind.GOAL_POST and percept.post_side is PostSide.UNKNOWN:
                    self._lone_posts.append((len(self._percepts) - 1, index, target))
                    if not any(t.purpose is ScanPurpose.CROSSBAR and t.yaw_rad == target.yaw_rad for t in self._queue):
                        self._queue.insert(0, HeadTarget(target.yaw_rad, CROSSBAR_PITCH_RAD, ScanPurpose.CROSSBAR))
        return True

    def _resolve_sides(self, frame: CameraFrame) -> None:
        labels = self.pipeline.table.segment(frame.image)
        for frame_index, index, target in self._lone_posts:
            if abs(target.yaw_rad - frame.head_yaw_rad) > HEAD_SETTLED_RAD:
                continue
            percept = self._percepts[frame_index][index]
            if percept.post_side is not PostSide.UNKNOWN or percept.goal is None:
                continue
            sides = [(abs(u - percept.pixel[0]), is_left) for u, is_left in crossbar_sides(labels, percept.goal)]
            sides = [s for s in sides if s[0] <= CROSSBAR_MATCH_PX]
            if sides:
                self._percepts[frame_index][index] = dataclasses.replace(
                    percept, landmark_id=post_id(percept.goal, min(sides)[1]), post_side=PostSide.CROSSBAR
                )

    def result(self) -> ScanResult:
        """The fused percepts of the frames used so far."""
        return ScanResult(fuse_percepts([p for frame in self._percepts for p in frame]), tuple(self._frames))


def _compatible(a: LandmarkPercept, b: LandmarkPercept) -> bool:
    if a.kind is not b.kind or a.goal is not b.goal or a.camera_model != b.camera_model:
        return False
    if a.landmark_id is not None and b.landmark_id is not None and a.landmark_id is not b.landmark_id:
        return False
    if a.kind is LandmarkKind.L_CORNER and a.corner is not b.corner:
        return a.corner is None or b.corner is None
    return True


def fuse_percepts(percepts: list[LandmarkPercept]) -> tuple[LandmarkPercept, ...]:
    """Merge percepts of the same landmark from several frames (mean of their ground points).

    Two percepts are the same landmark when their kinds and identities are compatible (a
    post of unknown side matches either post of its goal) and their ground points are
    within ``max(FUSE_GATE_M, FUSE_GATE_RELATIVE * distance)``. A fused post takes the
    known side of any of its members.
    """
    groups: list[list[LandmarkPercept]] = []
    for percept in percepts:
        if not (math.isfinite(percept.distance_m) and math.isfinite(percept.bearing_rad)):
            continue
        for group in groups:
            head = group[0]
            gate = max(FUSE_GATE_M, FUSE_GATE_RELATIVE * min(head.distance_m, percept.distance_m))
            close = math.hypot(head.x_m - percept.x_m, head.y_m - percept.y_m) <= gate
            if close and all(_compatible(member, percept) for member in group):
                group.append(percept)
                break
        else:
            groups.append([percept])
    return tuple(_merge(group) for group in groups)


def _merge(group: list[LandmarkPercept]) -> LandmarkPercept:
    if len(group) == 1:
        return group[0]
    x = float(np.mean([p.x_m for p in group]))
    y = float(np.mean([p.y_m for p in group]))
    known = next((p for p in group if p.landmark_id is not None), group[0])
    side = known.post_side if known.landmark_id is not None else group[0].post_side
    corner = next((p.corner for p in group if p.corner is not None), None)
    return dataclasses.replace(
        known,
        bearing_rad=math.atan2(y, x),
        distance_m=math.hypot(x, y),
        post_side=side,
        corner=corner,
        frames=sum(p.frames for p in group),
    )


def scan_coverage_rad(yaws_rad: tuple[float, ...] = SCAN_YAWS_RAD) -> float:
    """Horizontal angle covered by a scan's frames (thesis: about 206 degrees)."""
    return max(yaws_rad) - min(yaws_rad) + NAO_CAMERA.horizontal_fov_rad

