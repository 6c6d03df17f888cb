"""A fixed camera's static scene drawn once: the hall and the goals, merged with the moving bodies by depth.

The broadcast view (:func:`world.rendering.render_overview`) never moves, and of what it shows
only the robots and the ball do. The hall is drawn analytically and cached per camera pose
(:mod:`world.backdrop`), but TinyRenderer still drew the two goals every frame, about a third
of the frame. Here the goals are drawn once per camera pose by TinyRenderer in a client of
their own (the same static scene, :func:`world.scene.build_scene`, with nothing else in it)
and merged with the hall into one layer: a colour and a depth threshold per pixel. A frame
then draws the bodies alone (the world's goals hidden for that call) and takes the layer's
colour wherever the bodies' depth is at or beyond the threshold.

The image is the one TinyRenderer and the hall gave before, pixel for pixel: a body pixel
shows when it is nearer than the hall (as before) and nearer than or as near as the goal
there (TinyRenderer drew the bodies first, and a later fragment wins only when strictly
nearer); the goal's colour and depth at a pixel do not depend on the bodies
(``tests/test_analytic_scene.py`` compares every pixel).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pybullet as pb

from world.config import RenderConfig
from world.field import FieldGeometry
from world.ground import GroundRenderer, merge_by_depth
from world.pose_cache import PoseCache
from world.rendering import focal_length_px, tiny_renderer_buffers
from world.scene import GOAL_RGBA, SceneBodies, build_scene

CACHE_SIZE = 4  # camera poses whose static layer is kept
HIDDEN = (0.0, 0.0, 0.0, 0.0)  # TinyRenderer skips a shape of alpha 0


@dataclass(frozen=True)
class StaticLayer:
    """The static scene as one camera sees it (rows top to bottom).

    ``rgba``: (h, w) uint32, TinyRenderer's packed RGBA bytes of the goals or the hall;
    ``threshold``: (h, w) float32, the smallest value of TinyRenderer's depth buffer (0 at the
    near plane, 1 at the far one) of a body pixel behind which the static scene shows.
    """

    rgba: np.ndarray
    threshold: np.ndarray


class StaticScene:
    """Draws a fixed camera's frames with the hall and the goals cached per camera pose.

    ``client`` is the world's pybullet client and ``scene`` its static bodies; ``ground`` the
    world's analytic hall. The goals' own client is made on the first frame; :meth:`close`
    frees it.
    """

    def __init__(self, client: int, field: FieldGeometry, render: RenderConfig, scene: SceneBodies,
                 ground: GroundRenderer):
        self._client, self._field, self._render = client, field, render
        self._goals = scene.goals
        self._ground = ground
        self._goal_client: int | None = None
        self._cache: PoseCache[StaticLayer] = PoseCache(CACHE_SIZE)

    def close(self) -> None:
        if self._goal_client is not None:
            pb.disconnect(physicsClientId=self._goal_client)
            self._goal_client = None

    def render(
        self, rotation: np.ndarray, position: np.ndarray, width_px: int, height_px: int, vertical_fov_rad: float
    ) -> np.ndarray:
        """RGB image (h, w, 3) uint8 from a camera pose (rotation camera->world, position m), square pixels."""
        layer = self._layer(rotation, position, width_px, height_px, vertical_fov_rad)
        for color, goal in self._goals.items():
            pb.changeVisualShape(goal, -1, rgbaColor=HIDDEN, physicsClientId=self._client)
        try:
            rgba, depth, _ = tiny_renderer_buffers(
                self._client, rotation, position, width_px, height_px, vertical_fov_rad, self._render
            )
        finally:
            for color, goal in self._goals.items():
                pb.changeVisualShape(goal, -1, rgbaColor=GOAL_RGBA[color], physicsClientId=self._client)
        return merge_by_depth(rgba, depth, layer.threshold, layer.rgba)

    def _layer(
        self, rotation: np.ndarray, position: np.ndarray, width_px: int, height_px: int, vertical_fov_rad: float
    ) -> StaticLayer:
        return self._cache.get(rotation, position, (width_px, height_px, vertical_fov_rad), lambda: self._draw(
            rotation, np.asarray(position, float), width_px, height_px, vertical_fov_rad))

    def _draw(
        self, rotation: np.ndarray, position: np.ndarray, width_px: int, height_px: int, vertical_fov_rad: float
    ) -> StaticLayer:
        if self._goal_client is None:
            self._goal_client = _goals_alone(self._field)
        goals_rgba, goals_depth, _ = tiny_renderer_buffers(
            self._goal_client, rotation, position, width_px, height_px, vertical_fov_rad, self._render
        )
        hall = self._ground.backdrop(rotation, position, width_px, height_px, focal_length_px(height_px, vertical_fov_rad))
        goals = np.ascontiguousarray(goals_rgba).view(np.uint32).reshape(height_px, width_px)
        goals_depth = np.asarray(goals_depth, np.float32)
        hall_in_front = goals_depth >= hall.min_depth
        rgba = np.where(hall_in_front, hall.rgba, goals)
        threshold = np.where(hall_in_front, hall.min_depth, np.nextafter(goals_depth, np.float32(np.inf)))
        return StaticLayer(rgba, threshold.astype(np.float32))


def _goals_alone(field: FieldGeometry) -> int:
    """A pybullet client (DIRECT) of the static scene with only the goals visible."""
    client = pb.connect(pb.DIRECT)
    if client < 0:
        raise RuntimeError("could not connect to a pybullet physics server")
    scene = build_scene(client, field)
    for body in scene.ground_visuals:
        pb.changeVisualShape(body, -1, rgbaColor=HIDDEN, physicsClientId=client)
    return client
