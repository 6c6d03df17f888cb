"""The landmark recognition of one camera frame (thesis chapter 4), stage by stage.

segmentation (4.1) -> field border (4.3; no border: stop) -> goals (4.4) and field lines
(4.5) -> percepts, with bearings and distances from the chosen camera model (4.2).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field

import numpy as np

from agents.vision.border import FieldBorder, find_border
from agents.vision.camera_models import DEFAULT_CAMERA_MODEL, CameraModel, camera_model
from agents.vision.frame import CameraFrame
from agents.vision.goals import GoalRims, GoalTrace, detect_goals
from agents.vision.lines import LineTrace, detect_line_landmarks
from agents.vision.percepts import LandmarkPercept
from agents.vision.segmentation import ColorTable, ColorThresholds, load_thresholds

LOG = logging.getLogger(__name__)


@dataclass(frozen=True, eq=False)
class FrameResult:
    """The percepts of one frame and what each stage saw on the way (for debugging)."""

    percepts: tuple[LandmarkPercept, ...]
    segmented: np.ndarray
    border: FieldBorder
    goals: GoalTrace = field(default_factory=GoalTrace)
    lines: LineTrace | None = None


class VisionPipeline:
    """Landmark recognition with one colour table and one camera model (``exact`` or ``thesis``)."""

    def __init__(self, camera_model_name: str = DEFAULT_CAMERA_MODEL, thresholds: ColorThresholds | None = None):
        self.model: CameraModel = camera_model(camera_model_name)
        self.table = ColorTable(thresholds or load_thresholds())
        self.rims = GoalRims.from_thresholds(self.table.thresholds)
        _ = self.table.table  # compile the lookup table now, not on the first frame

    def process(self, frame: CameraFrame) -> FrameResult:
        """Recognize the landmarks of ``frame`` (a :class:`CameraFrame`, validated on creation)."""
        if not isinstance(frame, CameraFrame):
            raise TypeError(f"process() takes a CameraFrame; got {type(frame).__name__}")
        segmented = self.table.segment(frame.image)
        border = find_border(segmented)
        if not border.found:
            LOG.debug("no field border: recognition stops early")
            return FrameResult((), segmented, border)
        goal_percepts, goals = detect_goals(segmented, frame, self.model, self.rims)
        line_percepts, lines = detect_line_landmarks(segmented, border, frame, self.model)
        return FrameResult(goal_percepts + line_percepts, segmented, border, goals, lines)
