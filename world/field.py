"""Field geometry of the SPL 2011 field used by RobotStadium, and its 17 landmarks.

Pure Python: no pybullet. Every other part of the project (scene, vision, localization,
referee, plots) reads the field from here.

Frame (thesis section 5.1): origin at the centre spot, +x toward the yellow goal
(x in [-3, 3] m), +y to the left when facing +x (y in [-2, 2] m), z up. Orientation
``theta = 0`` faces the yellow goal, counter-clockwise positive, normalized to (-pi, pi].

"Left" and "right" of a goal's posts, field corners and goal-area corners are as seen by a
robot inside the field facing that goal. "Left" and "right" of the two T junctions are as
seen facing +x (the yellow goal): the left T junction is at y = +2.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass
from functools import cached_property


def normalize_angle(angle_rad: float) -> float:
    """Return ``angle_rad`` wrapped into (-pi, pi]."""
    wrapped = math.fmod(angle_rad, 2.0 * math.pi)
    if wrapped <= -math.pi:
        wrapped += 2.0 * math.pi
    elif wrapped > math.pi:
        wrapped -= 2.0 * math.pi
    return wrapped


@dataclass(frozen=True)
class Pose2D:
    """A pose on the field: position in metres, heading ``theta`` in radians (field frame)."""

    x: float
    y: float
    theta: float

    def is_finite(self) -> bool:
        return all(math.isfinite(v) for v in (self.x, self.y, self.theta))


class GoalColor(enum.Enum):
    """Colour of a goal; the blue goal is at x = -3, the yellow goal at x = +3."""

    BLUE = "blue"
    YELLOW = "yellow"

    @property
    def sign(self) -> int:
        """Sign of the x coordinate of this goal's line."""
        return -1 if self is GoalColor.BLUE else 1

    @property
    def other(self) -> GoalColor:
        return GoalColor.YELLOW if self is GoalColor.BLUE else GoalColor.BLUE


@dataclass(frozen=True)
class FieldGeometry:
    """Dimensions of the field in metres. Line positions are line centres.

    Only independent dimensions are fields; everything mirrored or derived is a property.
    """

    length: float = 6.0
    width: float = 4.0
    line_width: float = 0.05
    center_circle_radius: float = 0.6
    goal_area_depth: float = 0.6
    goal_area_width: float = 2.2
    penalty_mark_distance_from_center: float = 1.2
    penalty_mark_size: float = 0.1
    carpet_margin: float = 0.7
    goal_inner_width: float = 1.4
    goal_post_diameter: float = 0.1
    goal_height: float = 0.8
    goal_depth: float = 0.5
    ball_radius: float = 0.0325
    ball_mass: float = 0.055

    @property
    def half_length(self) -> float:
        return self.length / 2.0

    @property
    def half_width(self) -> float:
        return self.width / 2.0

    @property
    def carpet_half_length(self) -> float:
        return self.half_length + self.carpet_margin

    @property
    def carpet_half_width(self) -> float:
        return self.half_width + self.carpet_margin

    @property
    def goal_post_y(self) -> float:
        """|y| of the goal post centres."""
        return (self.goal_inner_width + self.goal_post_diameter) / 2.0

    @property
    def goal_post_radius(self) -> float:
        return self.goal_post_diameter / 2.0

    @property
    def goal_area_x(self) -> float:
        """|x| of the goal-area front line."""
        return self.half_length - self.goal_area_depth

    @property
    def goal_area_half_width(self) -> float:
        return self.goal_area_width / 2.0

    @property
    def penalty_mark_x(self) -> float:
        return self.penalty_mark_distance_from_center

    def goal_line_x(self, color: GoalColor) -> float:
        return color.sign * self.half_length

    def is_on_carpet(self, x: float, y: float) -> bool:
        return abs(x) <= self.carpet_half_length and abs(y) <= self.carpet_half_width

    @cached_property
    def landmarks(self) -> tuple[Landmark, ...]:
        return _build_landmarks(self)

    @cached_property
    def line_segments(self) -> tuple[LineSegment, ...]:
        return _build_line_segments(self)

    @property
    def center_circle(self) -> Circle:
        return Circle(0.0, 0.0, self.center_circle_radius)

    @property
    def penalty_marks(self) -> tuple[tuple[float, float], ...]:
        return ((-self.penalty_mark_x, 0.0), (self.penalty_mark_x, 0.0))

    def landmark(self, landmark_id: LandmarkId) -> Landmark:
        for landmark in self.landmarks:
            if landmark.id is landmark_id:
                return landmark
        raise KeyError(landmark_id)  # unreachable: every id is built


class LandmarkKind(enum.Enum):
    GOAL_POST = "goal_post"
    GOAL_CENTER = "goal_center"
    CENTER_CIRCLE = "center_circle"
    L_CORNER = "l_corner"
    T_JUNCTION = "t_junction"


class LandmarkId(enum.Enum):
    BLUE_GOAL_LEFT_POST = "blue_goal_left_post"
    BLUE_GOAL_RIGHT_POST = "blue_goal_right_post"
    YELLOW_GOAL_LEFT_POST = "yellow_goal_left_post"
    YELLOW_GOAL_RIGHT_POST = "yellow_goal_right_post"
    BLUE_GOAL_CENTER = "blue_goal_center"
    YELLOW_GOAL_CENTER = "yellow_goal_center"
    CENTER_CIRCLE = "center_circle"
    FIELD_CORNER_BLUE_LEFT = "field_corner_blue_left"
    FIELD_CORNER_BLUE_RIGHT = "field_corner_blue_right"
    FIELD_CORNER_YELLOW_LEFT = "field_corner_yellow_left"
    FIELD_CORNER_YELLOW_RIGHT = "field_corner_yellow_right"
    GOAL_AREA_CORNER_BLUE_LEFT = "goal_area_corner_blue_left"
    GOAL_AREA_CORNER_BLUE_RIGHT = "goal_area_corner_blue_right"
    GOAL_AREA_CORNER_YELLOW_LEFT = "goal_area_corner_yellow_left"
    GOAL_AREA_CORNER_YELLOW_RIGHT = "goal_area_corner_yellow_right"
    T_JUNCTION_LEFT = "t_junction_left"
    T_JUNCTION_RIGHT = "t_junction_right"


@dataclass(frozen=True)
class Landmark:
    """A fixed, recognizable point of the field (thesis chapter 4), position in metres."""

    id: LandmarkId
    kind: LandmarkKind
    x: float
    y: float
    goal: GoalColor | None = None


@dataclass(frozen=True)
class LineSegment:
    """Centre line of a painted line, from (x0, y0) to (x1, y1), metres."""

    x0: float
    y0: float
    x1: float
    y1: float

    @property
    def length(self) -> float:
        return math.hypot(self.x1 - self.x0, self.y1 - self.y0)


@dataclass(frozen=True)
class Circle:
    """Centre line of a painted circle, metres."""

    cx: float
    cy: float
    radius: float


def _left_y(color: GoalColor) -> float:
    """Sign of y for "left" as seen by a robot facing the goal of ``color``."""
    return 1.0 if color is GoalColor.YELLOW else -1.0


def _build_landmarks(g: FieldGeometry) -> tuple[Landmark, ...]:
    kind = LandmarkKind
    found: list[Landmark] = []
    for color in (GoalColor.BLUE, GoalColor.YELLOW):
        x_goal = g.goal_line_x(color)
        left = _left_y(color)
        name = color.name
        found += [
            Landmark(LandmarkId[f"{name}_GOAL_LEFT_POST"], kind.GOAL_POST, x_goal, left * g.goal_post_y, color),
            Landmark(LandmarkId[f"{name}_GOAL_RIGHT_POST"], kind.GOAL_POST, x_goal, -left * g.goal_post_y, color),
            Landmark(LandmarkId[f"{name}_GOAL_CENTER"], kind.GOAL_CENTER, x_goal, 0.0, color),
            Landmark(LandmarkId[f"FIELD_CORNER_{name}_LEFT"], kind.L_CORNER, x_goal, left * g.half_width, color),
            Landmark(LandmarkId[f"FIELD_CORNER_{name}_RIGHT"], kind.L_CORNER, x_goal, -left * g.half_width, color),
            Landmark(
                LandmarkId[f"GOAL_AREA_CORNER_{name}_LEFT"],
                kind.L_CORNER,
                color.sign * g.goal_area_x,
                left * g.goal_area_half_width,
                color,
            ),
            Landmark(
                LandmarkId[f"GOAL_AREA_CORNER_{name}_RIGHT"],
                kind.L_CORNER,
                color.sign * g.goal_area_x,
                -left * g.goal_area_half_width,
                color,
            ),
        ]
    found += [
        Landmark(LandmarkId.CENTER_CIRCLE, kind.CENTER_CIRCLE, 0.0, 0.0),
        Landmark(LandmarkId.T_JUNCTION_LEFT, kind.T_JUNCTION, 0.0, g.half_width),
        Landmark(LandmarkId.T_JUNCTION_RIGHT, kind.T_JUNCTION, 0.0, -g.half_width),
    ]
    order = {landmark_id: i for i, landmark_id in enumerate(LandmarkId)}
    return tuple(sorted(found, key=lambda lm: order[lm.id]))


def _build_line_segments(g: FieldGeometry) -> tuple[LineSegment, ...]:
    hl, hw = g.half_length, g.half_width
    segments = [
        LineSegment(-hl, hw, hl, hw),  # left side line
        LineSegment(-hl, -hw, hl, -hw),  # right side line
        LineSegment(-hl, -hw, -hl, hw),  # blue end line
        LineSegment(hl, -hw, hl, hw),  # yellow end line
        LineSegment(0.0, -hw, 0.0, hw),  # middle line
    ]
    for sign in (-1.0, 1.0):
        x_front, ya = sign * g.goal_area_x, g.goal_area_half_width
        segments += [
            LineSegment(x_front, -ya, x_front, ya),
            LineSegment(sign * hl, ya, x_front, ya),
            LineSegment(sign * hl, -ya, x_front, -ya),
        ]
        px, half = sign * g.penalty_mark_x, g.penalty_mark_size / 2.0
        segments += [LineSegment(px - half, 0.0, px + half, 0.0), LineSegment(px, -half, px, half)]
    return tuple(segments)


FIELD = FieldGeometry()
"""The field every part of the project uses unless told otherwise."""
