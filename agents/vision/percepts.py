"""What one camera frame showed: the landmark percepts of the vision pipeline."""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

from world.field import GoalColor, LandmarkId, LandmarkKind


class CornerShape(enum.Enum):
    """How an L corner appears in the image (thesis 4.5.4, FindCorner)."""

    UP = "up"
    DOWN = "down"
    LEFT = "left"
    RIGHT = "right"


class PostSide(enum.Enum):
    """How a goal post's side (left or right, seen from the field) was decided (thesis 4.4)."""

    PAIR = "pair"  # both posts of the goal in the frame
    CROSSBAR = "crossbar"  # a lone post; the crossbar seen leaving its top to one side
    UNKNOWN = "unknown"  # a lone post whose crossbar was not in the frame


@dataclass(frozen=True)
class LandmarkPercept:
    """One landmark seen in one frame (or fused over a head scan).

    ``landmark_id`` is set when the image alone tells which landmark it is (goal posts
    whose side is known, goal centres, the centre circle); L corners and T junctions are
    resolved later by localization. ``pixel`` is the (u, v) image point used (continuous
    pixel-index coordinates). ``bearing_rad`` is counter-clockwise positive in the torso
    frame and ``distance_m`` is on the ground from the point below the torso, both from
    the camera model named by ``camera_model``.
    """

    kind: LandmarkKind
    pixel: tuple[float, float]
    bearing_rad: float
    distance_m: float
    camera_model: str
    landmark_id: LandmarkId | None = None
    goal: GoalColor | None = None
    corner: CornerShape | None = None
    post_side: PostSide | None = None
    frames: int = 1  # how many frames of a head scan were fused into this percept

    @property
    def x_m(self) -> float:
        """Position along the torso x axis (forward), metres."""
        return self.distance_m * math.cos(self.bearing_rad)

    @property
    def y_m(self) -> float:
        """Position along the torso y axis (left), metres."""
        return self.distance_m * math.sin(self.bearing_rad)
