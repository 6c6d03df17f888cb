"""The ball in one camera image, and its position on the ground.

Pixels are classified by the calibrated colour table of :mod:`agents.vision.segmentation`
(the same table as every other percept; orange is the ball's class), then the largest
8-connected orange blob is the ball; the ray through its centre is intersected with the
plane ``z = ball radius`` of the torso frame (origin on the ground below the torso, x
forward, y left, z up), where the ball's centre lies.
"""

from __future__ import annotations

import functools
import logging
import math
from dataclasses import dataclass

import cv2
import numpy as np

from agents.vision.camera_models import torso_camera_pose
from agents.vision.colors import ColorClass
from agents.vision.segmentation import ColorTable, load_thresholds
from world.camera_model import NAO_CAMERA, NAO_HEAD, CameraPosition, world_to_camera
from world.field import FIELD

LOG = logging.getLogger(__name__)

MIN_BALL_PIXELS = 3
MIN_FIT_POINTS = 6  # outline points needed to fit a circle to a ball cut by the image border
MAX_DISTANCE_M = 9.0  # longer than the field diagonal: used when the ray misses the ground
# A ball cut off by the image border shows less than its disc; one merged with orange beyond
# it shows more. Outside these ratios of the expected disc area the blob is not the ball.
CAMERA_HEIGHT_M = 0.5  # about: the size check needs no more
MIN_SIZE_RATIO = 0.08
MAX_SIZE_RATIO = 3.0


@dataclass(frozen=True)
class BallPercept:
    """The ball seen in one image.

    ``pixel_u``, ``pixel_v``: blob centroid (pixel index coordinates, column and row);
    ``bearing_rad``: direction of the ball in the torso frame, CCW positive (left > 0);
    ``distance_m``: ground distance from the point below the torso to the ball's centre;
    ``pixels``: blob size in pixels.
    """

    pixel_u: float
    pixel_v: float
    bearing_rad: float
    distance_m: float
    pixels: int

    @property
    def forward_m(self) -> float:
        """Ball position along torso x (m)."""
        return self.distance_m * math.cos(self.bearing_rad)

    @property
    def left_m(self) -> float:
        """Ball position along torso y (m)."""
        return self.distance_m * math.sin(self.bearing_rad)


@functools.cache
def calibrated_table() -> ColorTable:
    """The colour table of the calibrated thresholds shipped with the package (built once)."""
    return ColorTable(load_thresholds())


def orange_mask(image: np.ndarray, table: ColorTable | None = None) -> np.ndarray:
    """Boolean (H, W) mask of the ball-coloured (orange) pixels of an RGB uint8 image (H, W, 3)."""
    return (table or calibrated_table()).classify(image) == int(ColorClass.ORANGE)


def _largest_blob(mask: np.ndarray) -> tuple[float, float, int] | None:
    """Centre (u, v) and size of the largest 8-connected blob of ``mask``, or None.

    The centre is the blob's centroid, or, when the blob touches the image border (a ball
    cut off), the centre of a circle fitted to its outline away from the border.
    """
    pixels = np.flatnonzero(mask)
    if len(pixels) < MIN_BALL_PIXELS:
        return None
    rows, cols = mask.shape
    # Labelling only the box around the mask's pixels, from an even row and column: OpenCV labels
    # 2x2 blocks in raster order, so the blobs keep the labels (and ties the order) of the whole image.
    top, bottom = int(pixels[0] // cols) & ~1, int(pixels[-1] // cols)
    pixel_cols = pixels % cols
    left, right = int(pixel_cols.min()) & ~1, int(pixel_cols.max())
    crop = mask[top : bottom + 1, left : right + 1].astype(np.uint8)
    count, labels, stats, centroids = cv2.connectedComponentsWithStats(crop, connectivity=8)
    if count <= 1:
        return None
    best = int(np.argmax(stats[1:, cv2.CC_STAT_AREA])) + 1
    size = int(stats[best, cv2.CC_STAT_AREA])
    if size < MIN_BALL_PIXELS:
        return None
    u, v = float(centroids[best, 0]) + left, float(centroids[best, 1]) + top
    blob_left, blob_top = int(stats[best, cv2.CC_STAT_LEFT]) + left, int(stats[best, cv2.CC_STAT_TOP]) + top
    width, height = int(stats[best, cv2.CC_STAT_WIDTH]), int(stats[best, cv2.CC_STAT_HEIGHT])
    if blob_left == 0 or blob_top == 0 or blob_left + width == cols or blob_top + height == rows:
        blob = np.zeros(mask.shape, bool)
        blob[top : bottom + 1, left : right + 1] = labels == best
        fitted = _fit_cut_circle(blob)
        if fitted is not None:
            u, v = fitted
    return u, v, size


def _fit_cut_circle(blob: np.ndarray) -> tuple[float, float] | None:
    """Centre (u, v) of a least-squares (Kasa) circle through the blob's outline off the border."""
    contours, _ = cv2.findContours(blob.astype(np.uint8), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    points = np.concatenate([c.reshape(-1, 2) for c in contours]).astype(float)
    rows, cols = blob.shape
    inside = (points[:, 0] > 0) & (points[:, 0] < cols - 1) & (points[:, 1] > 0) & (points[:, 1] < rows - 1)
    points = points[inside]
    if len(points) < MIN_FIT_POINTS:
        return None
    x, y = points[:, 0], points[:, 1]
    design = np.stack([x, y, np.ones_like(x)], axis=1)
    (d, e, f), *_ = np.linalg.lstsq(design, -(x * x + y * y), rcond=None)
    cu, cv = -d / 2.0, -e / 2.0
    if not (np.isfinite(cu) and np.isfinite(cv)) or cu * cu + cv * cv - f <= 0.0:
        return None
    return float(cu), float(cv)


def plausible(ball: BallPercept) -> bool:
    """Whether a blob can be the ball: on the ground (its ray descends) and of about the size a
    ball has at its distance (orange on a banner or a far robot is rejected)."""
    if ball.distance_m >= MAX_DISTANCE_M:
        return False
    camera_range_m = math.hypot(ball.distance_m, CAMERA_HEIGHT_M - FIELD.ball_radius)
    expected_px = math.pi * (NAO_CAMERA.focal_px * FIELD.ball_radius / camera_range_m) ** 2
    return MIN_SIZE_RATIO * expected_px <= ball.pixels <= MAX_SIZE_RATIO * expected_px + MIN_BALL_PIXELS


def ground_point(
    u: float, v: float, head_yaw_rad: float, head_pitch_rad: float, camera: CameraPosition, height_m: float
) -> tuple[float, float]:
    """Torso-frame (bearing rad, ground distance m) of the point at ``height_m`` seen at pixel (u, v).

    When the ray does not descend to ``height_m`` the bearing of the ray is returned with
    :data:`MAX_DISTANCE_M`.
    """
    rotation, position = torso_camera_pose(NAO_HEAD, head_yaw_rad, head_pitch_rad, camera)
    ray_x, ray_y, ray_z = NAO_CAMERA.rotated_pixel_rays(float(u), float(v), rotation)
    bearing = math.atan2(ray_y, ray_x)
    px, py, pz = position.tolist()
    drop = pz - height_m
    if ray_z >= -1e-9 or drop <= 0.0:
        return bearing, MAX_DISTANCE_M
    t = drop / -ray_z
    x, y = px + t * ray_x, py + t * ray_y
    distance = math.hypot(x, y)
    if distance > MAX_DISTANCE_M:
        return bearing, MAX_DISTANCE_M
    return math.atan2(y, x), distance


def ground_pixel(
    bearing_rad: float, distance_m: float, head_yaw_rad: float, head_pitch_rad: float, camera: CameraPosition,
    height_m: float,
) -> tuple[float, float] | None:
    """The pixel (u, v) where the point ``height_m`` above the ground at (bearing rad, ground
    distance m) in the torso frame appears, or None when it lies behind the camera (the
    inverse of :func:`ground_point`; it may fall outside the image)."""
    rotation, position = torso_camera_pose(NAO_HEAD, head_yaw_rad, head_pitch_rad, camera)
    point = np.array([distance_m * math.cos(bearing_rad), distance_m * math.sin(bearing_rad), height_m])
    pixel = NAO_CAMERA.project(world_to_camera(point, rotation, position))[0]
    if not np.isfinite(pixel).all():
        return None
    return float(pixel[0]), float(pixel[1])


def find_ball(
    image: np.ndarray,
    head_yaw_rad: float,
    head_pitch_rad: float,
    camera: CameraPosition,
    table: ColorTable | None = None,
) -> BallPercept | None:
    """The ball in a 160x120 RGB image taken by ``camera`` at the given head angles, or None.

    ``table``: the colour table to classify with (default: the calibrated one).
    """
    return ball_in_mask(orange_mask(np.asarray(image), table), head_yaw_rad, head_pitch_rad, camera)


def ball_in_mask(
    mask: np.ndarray, head_yaw_rad: float, head_pitch_rad: float, camera: CameraPosition
) -> BallPercept | None:
    """The ball as the largest blob of a boolean (H, W) orange mask, or None."""
    blob = _largest_blob(mask)
    if blob is None:
        return None
    u, v, size = blob
    bearing, distance = ground_point(u, v, head_yaw_rad, head_pitch_rad, camera, FIELD.ball_radius)
    LOG.debug("ball at pixel (%.1f, %.1f), %d px: bearing %.2f rad, %.2f m", u, v, size, bearing, distance)
    return BallPercept(u, v, bearing, distance, size)
