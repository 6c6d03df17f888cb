"""Other robots in one camera image, found by their team markers, and where they stand.

Robots wear a waistband in their team's colour (cyan: blue team, magenta: red team; the SPL
2011 markers, :class:`match.protocol.TeamColor`). In the segmented image of
:mod:`agents.vision.segmentation` the 8-connected blobs of each marker class are found, the
fragments of one band (an arm hides the middle of a band seen from the side) are joined,
tiny blobs (noise) are dropped, and the ray through each band's centre is met with the
horizontal plane at the band's height, :data:`WAISTBAND_HEIGHT_M`, in the torso frame
(origin on the ground below the torso, x forward, y left, z up), with the geometry the
ball uses (:func:`agents.vision.ball.ground_point`). The band seen is the robot's near
side; the robot's centre lies :data:`BODY_RADIUS_M` further along the ray. A band cut by
the image's side edge gives the direction of its visible part.

Percepts are robot-relative: bearing CCW positive (rad) and ground distance (m) from the
point below the observer's torso to the point below the other robot's torso. The distance
assumes both robots upright; a fallen robot's band lies lower and reads farther.
"""

from __future__ import annotations

import enum
import logging
import math
from dataclasses import dataclass

import cv2
import numpy as np

from agents.vision.ball import MAX_DISTANCE_M, ground_point
from agents.vision.colors import ColorClass
from agents.vision.errors import VisionInputError
from match.protocol import TeamColor
from world.camera_model import CameraPosition

LOG = logging.getLogger(__name__)

# The waistband of the world's robot model (world.robot_model, which agents may not import;
# tests/test_robot_perception.py checks that these agree with it): a box 0.096 m deep,
# 0.146 m wide and 0.03 m tall whose centre is 0.27 m above the ground when the robot
# stands (torso centre 0.34 m, waist link 0.07 m below it).
WAISTBAND_HEIGHT_M = 0.27
WAISTBAND_TALL_M = 0.03
WAISTBAND_WIDTH_M = 0.146
WAISTBAND_DEPTH_M = 0.096
BODY_RADIUS_M = 0.05  # ours: the band's near face lies about half its depth before the torso centre

MIN_BLOB_PIXELS = 4  # ours: smaller marker blobs are noise (a band 3 m away covers 8-25 px)
# ours: blobs of one colour in the same rows are fragments of one band (an arm hides the
# middle of a band seen from the side, a goal post or another robot may cut it) when together
# they are no wider than a band seen corner-on, sqrt(0.146^2 + 0.096^2) = 0.175 m, which is
# this many times its height (0.03 m) at any distance, with some pixels to spare
JOIN_WIDTH_BANDS = math.hypot(WAISTBAND_WIDTH_M, WAISTBAND_DEPTH_M) / WAISTBAND_TALL_M
JOIN_SLACK_PX = 2
MIN_DISTANCE_M = 0.15  # ours: a marker nearer than this is the observer's own waistband, which the
# bottom camera sees at about 0.08 m with the head bent down

MARKERS: dict[TeamColor, ColorClass] = {TeamColor.BLUE: ColorClass.CYAN, TeamColor.RED: ColorClass.MAGENTA}
"""The waistband colour class of each team."""


class RobotKind(enum.Enum):
    """Whose robot a percept is, as the observer's own team colour tells it."""

    TEAMMATE = "teammate"
    OPPONENT = "opponent"


@dataclass(frozen=True)
class RobotPercept:
    """One robot seen in one image.

    ``bearing_rad``: direction of its torso centre in the observer's torso frame, CCW
    positive (left > 0); ``distance_m``: ground distance from the point below the
    observer's torso to the point below the robot's torso; ``team``: the colour of its
    waistband; ``kind``: teammate or opponent of the observer; ``box``: the band's pixel
    box (left column, top row, width, height); ``pixel``: the image point used
    (continuous pixel-index coordinates, column and row); ``pixels``: band size in pixels.
    """

    bearing_rad: float
    distance_m: float
    team: TeamColor
    kind: RobotKind
    box: tuple[int, int, int, int]
    pixel: tuple[float, float]
    pixels: int

    @property
    def x_m(self) -> float:
        """Position along torso x (forward), metres."""
        return self.distance_m * math.cos(self.bearing_rad)

    @property
    def y_m(self) -> float:
        """Position along torso y (left), metres."""
        return self.distance_m * math.sin(self.bearing_rad)


@dataclass(frozen=True)
class MarkerBlob:
    """The pixels of one waistband in the image: its colour class, box (left, top, width,
    height), size in pixels and pixel centroid (column, row)."""

    color: ColorClass
    box: tuple[int, int, int, int]
    pixels: int
    centroid: tuple[float, float]

    @property
    def center(self) -> tuple[float, float]:
        """The band's centre: the middle column of its box, its centroid row (pixel-index coordinates)."""
        left, _, width, _ = self.box
        return left + (width - 1) / 2.0, self.centroid[1]


def team_of(marker: ColorClass) -> TeamColor:
    """The team whose waistband has colour class ``marker`` (cyan or magenta)."""
    for team, color in MARKERS.items():
        if color is marker:
            return team
    expected = [c.name.lower() for c in MARKERS.values()]
    raise VisionInputError(f"colour class {marker!r} is not a team marker; expected one of {expected}")


def kind_of(team: TeamColor, own_team: TeamColor) -> RobotKind:
    """Teammate when ``team`` is the observer's own team colour, opponent otherwise."""
    return RobotKind.TEAMMATE if team is own_team else RobotKind.OPPONENT


def marker_blobs(segmented: np.ndarray, min_pixels: int = MIN_BLOB_PIXELS) -> tuple[MarkerBlob, ...]:
    """The waistbands of a segmented label image (H, W) uint8: 8-connected blobs of each marker
    class, fragments of one band joined, bands under ``min_pixels`` dropped; left to right."""
    labels = np.asarray(segmented)
    if labels.ndim != 2:
        raise VisionInputError(f"segmented image must be a 2-D label array; got shape {labels.shape}")
    blobs: list[MarkerBlob] = []
    width = labels.shape[1]
    for color in MARKERS.values():
        mask = labels == int(color)
        pixels = np.flatnonzero(mask)
        if pixels.size == 0:
            continue
        columns = pixels % width
        top, bottom = int(pixels[0] // width), int(pixels[-1] // width)
        left, right = int(columns.min()), int(columns.max())
        # Labelling only the box around the marker pixels: a few percent of the image, 50 times faster.
        crop = mask[top : bottom + 1, left : right + 1].astype(np.uint8)
        _, _, stats, centroids = cv2.connectedComponentsWithStats(crop, connectivity=8)
        boxes = stats[1:].tolist()  # columns: cv2.CC_STAT_LEFT, _TOP, _WIDTH, _HEIGHT, _AREA
        parts = [
            MarkerBlob(color, (box_left + left, box_top + top, box_width, box_height), area, (u + left, v + top))
            for (box_left, box_top, box_width, box_height, area), (u, v) in zip(boxes, centroids[1:].tolist())
        ]
        blobs.extend(b for b in _join_fragments(parts) if b.pixels >= min_pixels)
    return tuple(sorted(blobs, key=lambda b: b.box[0]))


def _join_fragments(parts: list[MarkerBlob]) -> list[MarkerBlob]:
    """Join blobs of one colour, left to right, that overlap in rows and together are no wider
    than one band (:data:`JOIN_WIDTH_BANDS` of their height)."""
    parts = sorted(parts, key=lambda b: b.box[0])
    joined: list[MarkerBlob] = []
    for part in parts:
        if joined and _near(joined[-1], part):
            joined[-1] = _union(joined[-1], part)
        else:
            joined.append(part)
    return joined


def _near(a: MarkerBlob, b: MarkerBlob) -> bool:
    """Whether ``b`` (starting at or right of ``a``'s left edge) is part of the band of ``a``."""
    a_left, a_top, a_width, a_height = a.box
    b_left, b_top, b_width, b_height = b.box
    rows_overlap = b_top <= a_top + a_height - 1 and a_top <= b_top + b_height - 1
    width = max(a_left + a_width, b_left + b_width) - a_left
    return rows_overlap and width <= JOIN_WIDTH_BANDS * max(a_height, b_height) + JOIN_SLACK_PX


def _union(a: MarkerBlob, b: MarkerBlob) -> MarkerBlob:
    left, top = min(a.box[0], b.box[0]), min(a.box[1], b.box[1])
    right = max(a.box[0] + a.box[2], b.box[0] + b.box[2])
    bottom = max(a.box[1] + a.box[3], b.box[1] + b.box[3])
    pixels = a.pixels + b.pixels
    u = (a.centroid[0] * a.pixels + b.centroid[0] * b.pixels) / pixels
    v = (a.centroid[1] * a.pixels + b.centroid[1] * b.pixels) / pixels
    return MarkerBlob(a.color, (left, top, right - left, bottom - top), pixels, (u, v))


def locate_blob(
    blob: MarkerBlob, head_yaw_rad: float, head_pitch_rad: float, camera: CameraPosition
) -> tuple[float, float] | None:
    """Torso-frame (bearing rad, ground distance m) of the robot wearing ``blob``, or None when
    the band's ray does not meet the band's plane in range or meets it at the observer itself."""
    u, v = blob.center
    bearing, distance = ground_point(u, v, head_yaw_rad, head_pitch_rad, camera, WAISTBAND_HEIGHT_M)
    if distance >= MAX_DISTANCE_M or distance < MIN_DISTANCE_M:
        return None
    return bearing, distance + BODY_RADIUS_M


def find_robots(
    segmented: np.ndarray,
    head_yaw_rad: float,
    head_pitch_rad: float,
    camera: CameraPosition,
    own_team: TeamColor,
) -> tuple[RobotPercept, ...]:
    """The robots in a segmented image taken by ``camera`` at the given head angles (rad),
    told teammate or opponent by the observer's team colour ``own_team`` (the game-control
    view's ``team_color``); left to right in the image."""
    if not isinstance(own_team, TeamColor):
        raise VisionInputError(f"own_team must be one of {[t.value for t in TeamColor]}; got {own_team!r}")
    percepts = []
    for blob in marker_blobs(segmented):
        located = locate_blob(blob, head_yaw_rad, head_pitch_rad, camera)
        if located is None:
            LOG.debug("%s band at %s dropped: no ground point in range", blob.color.name.lower(), blob.box)
            continue
        bearing, distance = located
        team = team_of(blob.color)
        percepts.append(RobotPercept(bearing, distance, team, kind_of(team, own_team), blob.box, blob.center, blob.pixels))
        LOG.debug("%s robot at bearing %.2f rad, %.2f m (%d px)", team.value, bearing, distance, blob.pixels)
    return tuple(percepts)
