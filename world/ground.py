"""The ground (carpet with its lines, and the floor around it) rendered analytically.

TinyRenderer shades every covered pixel at a fixed cost, and the ground covers most of a
robot's image, so drawing it as triangles is the most expensive part of a frame. The
ground is a plane: each pixel's ray meets it at one point, whose colour is read from the
carpet texture. TinyRenderer then draws only the bodies standing on it, and the two images
are merged by depth. The result is the image TinyRenderer would draw of the textured quad
(same pixel centres, nearest-texel lookup, same flat lighting), at a fraction of the cost.
"""

from __future__ import annotations

import numpy as np

from world.config import RenderConfig
from world.field import FieldGeometry
from world.scene import FLOOR_RGBA
from world.textures import TEXEL_M, carpet_texture

BACKGROUND_DEPTH = 0.9999  # TinyRenderer's depth buffer holds ~1.0 where nothing was drawn


class GroundRenderer:
    """Colours and depths of the ground plane z = 0 seen from a pinhole camera."""

    def __init__(self, field: FieldGeometry, render: RenderConfig, floor_half_extent: tuple[float, float]):
        self._texel = TEXEL_M
        light = np.asarray(render.light_direction, float)
        shade = render.ambient + render.diffuse * max(0.0, light[2] / np.linalg.norm(light))
        self._carpet = np.clip(carpet_texture(field, TEXEL_M).astype(float) * shade, 0, 255).astype(np.uint8)
        self._floor = np.clip(np.asarray(FLOOR_RGBA[:3]) * 255.0 * shade, 0, 255).astype(np.uint8)
        self._carpet_half = (field.carpet_half_length, field.carpet_half_width)
        self._floor_half = floor_half_extent
        self._near, self._far = render.near_m, render.far_m
        self._rays: dict[tuple[int, int, float], np.ndarray] = {}

    def _camera_rays(self, width_px: int, height_px: int, focal_px: float) -> np.ndarray:
        """Unit-depth rays (h*w, 3) through pixel centres, camera frame (x right, y down, z ahead)."""
        key = (width_px, height_px, focal_px)
        rays = self._rays.get(key)
        if rays is None:
            u, v = np.meshgrid(np.arange(width_px) + 0.5, np.arange(height_px) + 0.5)
            rays = np.stack(
                [(u - width_px / 2) / focal_px, (v - height_px / 2) / focal_px, np.ones_like(u)], axis=-1
            ).reshape(-1, 3)
            self._rays[key] = rays
        return rays

    def hits(
        self, depth_buffer: np.ndarray, rotation: np.ndarray, position: np.ndarray, focal_px: float
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Where the ground is the nearest thing in view: flat pixel indices and the field (x, y) m there.

        ``depth_buffer`` is TinyRenderer's (h, w) buffer for the camera (rotation
        camera->world, position in m), whose pixels have ``focal_px`` focal length.
        """
        height_px, width_px = depth_buffer.shape
        rays = self._camera_rays(width_px, height_px, focal_px)
        # Only rays pointing down can meet the ground; work on those pixels alone.
        index = np.flatnonzero(rays @ rotation[2] < 0.0)
        if index.size == 0:
            return index, np.empty(0), np.empty(0)
        down_rays = rays[index]
        t = -position[2] / (down_rays @ rotation[2])  # camera-z depth of the ground along each ray
        near, far = self._near, self._far
        depth = depth_buffer.reshape(-1)[index].astype(float)
        with np.errstate(divide="ignore"):
            eye_depth = np.where(depth >= BACKGROUND_DEPTH, np.inf, far * near / (far - (far - near) * depth))
        visible = (t > near) & (t < far) & (t <= eye_depth)
        t, down_rays = t[visible], down_rays[visible]
        return index[visible], position[0] + t * (down_rays @ rotation[0]), position[1] + t * (down_rays @ rotation[1])

    def carpet_texels(self, x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Which field points (m) lie on the carpet, and the (row, col) texel of each of those."""
        half_x, half_y = self._carpet_half
        on_carpet = (np.abs(x) < half_x) & (np.abs(y) < half_y)
        cols = ((x[on_carpet] + half_x) / self._texel).astype(np.intp)
        rows = ((half_y - y[on_carpet]) / self._texel).astype(np.intp)
        rows_max, cols_max = self._carpet.shape[0] - 1, self._carpet.shape[1] - 1
        return on_carpet, np.minimum(rows, rows_max), np.minimum(cols, cols_max)

    def on_floor(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """Which field points (m) lie on the hall's floor (inside the walls)."""
        floor_x, floor_y = self._floor_half
        return (np.abs(x) < floor_x) & (np.abs(y) < floor_y)

    def composite(
        self,
        image: np.ndarray,
        depth_buffer: np.ndarray,
        rotation: np.ndarray,
        position: np.ndarray,
        focal_px: float,
    ) -> np.ndarray:
        """Draw the ground into ``image`` (h, w, 3) wherever it is nearer than what is there (see :meth:`hits`)."""
        index, world_x, world_y = self.hits(depth_buffer, rotation, position, focal_px)
        if index.size == 0:
            return image
        out = image.reshape(-1, 3)
        on_carpet, rows, cols = self.carpet_texels(world_x, world_y)
        out[index[on_carpet]] = self._carpet[rows, cols]
        out[index[~on_carpet & self.on_floor(world_x, world_y)]] = self._floor
        return image
