"""Negative evidence for the ball model: a believed ball in clear view that the camera does not find.

A ball the robot believes near and in the middle of its image, with no robot in front of it,
would be found if it were there. When :data:`MISSES_TO_FORGET` camera frames within
:data:`MISS_WINDOW_S` miss it, the belief is wrong (the ball was kicked away unseen, or the
referee moved it) and the robot forgets it rather than trusting it for the ball model's
whole lost time.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

from agents.modelling.ball_model import BallEstimate
from agents.modelling.obstacle_model import Obstacle
from agents.vision.ball import ground_pixel
from world.camera_model import NAO_CAMERA, CameraPosition
from world.field import FIELD

MISSES_TO_FORGET = 4  # ours: camera frames (80 ms apart) that miss a ball in clear view ...
MISS_WINDOW_S = 1.0  # ... within this long (s)
VIEW_MARGIN_PX = 12.0  # the ball's believed centre lies this far inside the image's borders ...
MIN_VIEW_M = 0.1  # ... at a ground distance within these (m): nearer, it lies under the robot ...
MAX_VIEW_M = 2.5  # ... farther, a few pixels may not survive segmentation
MAX_SIGMA_M = 0.25  # ... and the belief is this sure of where it is (m)
NEAR_M = 0.3  # nearer than this, the legs may hide a ball beside the robot: only one ahead counts ...
NEAR_BEARING_RAD = math.radians(25.0)  # ... within this of straight ahead
ROBOT_HALF_WIDTH_M = 0.15  # a robot nearer than the ball hides it within this of its centre line


def in_clear_view(
    ball: BallEstimate, head_yaw_rad: float, head_pitch_rad: float, camera: CameraPosition,
    obstacles: Iterable[Obstacle],
) -> bool:
    """Whether a frame at these head angles would show ``ball`` (torso frame) and the belief is sure
    enough (:data:`MAX_SIGMA_M`) that a frame without it is a miss (the module docstring)."""
    return ball.sigma_m <= MAX_SIGMA_M and in_view(ball, head_yaw_rad, head_pitch_rad, camera, obstacles)


def in_view(
    ball: BallEstimate, head_yaw_rad: float, head_pitch_rad: float, camera: CameraPosition,
    obstacles: Iterable[Obstacle],
) -> bool:
    """Whether a frame at these head angles would show a ball where ``ball`` (torso frame) believes it,
    however unsure the belief: at a distance a frame resolves, not beside the legs, inside the image by
    :data:`VIEW_MARGIN_PX`, and no robot of ``obstacles`` in front of it."""
    if not MIN_VIEW_M <= ball.distance_m <= MAX_VIEW_M:
        return False
    if ball.distance_m < NEAR_M and abs(ball.bearing_rad) > NEAR_BEARING_RAD:
        return False
    pixel = ground_pixel(ball.bearing_rad, ball.distance_m, head_yaw_rad, head_pitch_rad, camera, FIELD.ball_radius)
    if pixel is None:
        return False
    u, v = pixel
    if not (VIEW_MARGIN_PX <= u <= NAO_CAMERA.width_px - 1 - VIEW_MARGIN_PX
            and VIEW_MARGIN_PX <= v <= NAO_CAMERA.height_px - 1 - VIEW_MARGIN_PX):
        return False
    return not any(o.distance_m < ball.distance_m
                   and abs(math.remainder(o.bearing_rad - ball.bearing_rad, math.tau))
                   < math.atan2(ROBOT_HALF_WIDTH_M, o.distance_m)
                   for o in obstacles)


class BallAbsence:
    """Counts the frames that missed a ball in clear view since it was last seen (frames that could
    not show it, the other camera's among them, neither count nor clear the count), within
    :data:`MISS_WINDOW_S`; ``frame`` says when to forget the belief."""

    def __init__(self) -> None:
        self.misses = 0
        self.first_miss_s = -math.inf
        self.forgotten = 0  # beliefs forgotten (statistics)

    def frame(self, now_s: float, seen: bool, expected: bool) -> bool:
        """One camera frame at ``now_s`` (s): whether it found the ball, whether it should have
        (:func:`in_clear_view`). True when the belief is to be forgotten now."""
        if seen:
            self.misses = 0
            return False
        if not expected:
            return False
        if now_s - self.first_miss_s > MISS_WINDOW_S:
            self.misses, self.first_miss_s = 0, now_s
        self.misses += 1
        if self.misses < MISSES_TO_FORGET:
            return False
        self.misses = 0
        self.first_miss_s = -math.inf
        self.forgotten += 1
        return True
