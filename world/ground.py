"""The static scene (ground and hall) drawn analytically and merged with TinyRenderer's bodies.

TinyRenderer's cost grows with the screen area its triangles cover, and the ground, walls
and roof cover most of every image, so it draws only the bodies (robots, ball, goals) and
the scene's own visuals are hidden (see :attr:`world.scene.SceneBodies.ground_visuals`).
:mod:`world.backdrop` draws the hall per camera, with TinyRenderer's lighting; the two
images are merged by depth.
"""

from __future__ import annotations

import cv2
import numpy as np

from world.backdrop import Backdrop, HallBackdrop
from world.config import RenderConfig
from world.field import FieldGeometry
from world.textures import TEXEL_M, carpet_texture


class GroundRenderer:
    """The ground plane z = 0 (carpet and floor) and the hall around it, seen from a pinhole camera."""

    def __init__(self, field: FieldGeometry, render: RenderConfig, floor_half_extent: tuple[float, float]):
        self._texel = TEXEL_M
        self._carpet_shape = carpet_texture(field, TEXEL_M).shape[:2]
        self._carpet_half = (field.carpet_half_length, field.carpet_half_width)
        self._floor_half = floor_half_extent
        self._hall = HallBackdrop(field, render, TEXEL_M)

    @property
    def hall(self) -> HallBackdrop:
        """The hall's drawing (:mod:`world.backdrop`)."""
        return self._hall

    def composite(
        self, rgba: np.ndarray, depth_buffer: np.ndarray, rotation: np.ndarray, position: np.ndarray, focal_px: float
    ) -> np.ndarray:
        """RGB image (h, w, 3) uint8 of TinyRenderer's bodies (``rgba`` (h, w, 4) uint8 and its
        ``depth_buffer`` (h, w)) with the hall drawn wherever it is nearer (camera: rotation
        camera->world, position m, ``focal_px`` focal length)."""
        height_px, width_px = depth_buffer.shape
        hall = self._hall.draw(rotation, position, width_px, height_px, focal_px)
        return merge_by_depth(rgba, depth_buffer, hall.min_depth, hall.rgba)

    def backdrop(
        self, rotation: np.ndarray, position: np.ndarray, width_px: int, height_px: int, focal_px: float
    ) -> Backdrop:
        """The hall as a camera (rotation camera->world, position m, ``focal_px`` focal length) sees it (cached)."""
        return self._hall.draw(rotation, position, width_px, height_px, focal_px)

    def hits(
        self, depth_buffer: np.ndarray, rotation: np.ndarray, position: np.ndarray, focal_px: float
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Where the ground is the nearest thing in view: flat pixel indices, and the field (x, y) m of
        the centre of the ground texel :meth:`composite` draws there.

        ``depth_buffer`` is TinyRenderer's (h, w) buffer of the bodies for the camera
        (rotation camera->world, position in m), whose pixels have ``focal_px`` focal length.
        """
        height_px, width_px = depth_buffer.shape
        hall = self._hall.draw(rotation, position, width_px, height_px, focal_px)
        return self.floor_hits(depth_buffer >= hall.min_depth, rotation, position, focal_px)

    def floor_hits(
        self, shown: np.ndarray, rotation: np.ndarray, position: np.ndarray, focal_px: float
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """As :meth:`hits`, for the pixels where the hall shows (``shown`` (h, w) bool: no body in front)."""
        height_px, width_px = shown.shape
        hall = self._hall.draw(rotation, position, width_px, height_px, focal_px)
        shown = shown.reshape(-1)
        on_floor, x, y = self._hall.floor_texel_centres(hall)
        visible = shown[on_floor]
        return np.flatnonzero(on_floor)[visible], x[visible], y[visible]

    def carpet_texels(self, x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Which field points (m) lie on the carpet, and the (row, col) texel of each of those."""
        half_x, half_y = self._carpet_half
        on_carpet = (np.abs(x) < half_x) & (np.abs(y) < half_y)
        cols = ((x[on_carpet] + half_x) / self._texel).astype(np.intp)
        rows = ((half_y - y[on_carpet]) / self._texel).astype(np.intp)
        rows_max, cols_max = self._carpet_shape[0] - 1, self._carpet_shape[1] - 1
        return on_carpet, np.minimum(rows, rows_max), np.minimum(cols, cols_max)

    def on_floor(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """Which field points (m) lie on the hall's floor (inside the walls)."""
        floor_x, floor_y = self._floor_half
        return (np.abs(x) < floor_x) & (np.abs(y) < floor_y)


def merge_by_depth(rgba: np.ndarray, depth_buffer: np.ndarray, threshold: np.ndarray, behind: np.ndarray) -> np.ndarray:
    """RGB image (h, w, 3) uint8: TinyRenderer's bodies (``rgba`` (h, w, 4) uint8, ``depth_buffer`` (h, w))
    where they are nearer than ``threshold`` (h, w), else ``behind`` ((h, w) uint32, packed RGBA bytes)."""
    height_px, width_px = depth_buffer.shape
    bodies = np.ascontiguousarray(rgba).view(np.uint32).reshape(height_px, width_px)
    merged = np.where(depth_buffer >= threshold, behind, bodies)
    return cv2.cvtColor(merged.view(np.uint8).reshape(height_px, width_px, 4), cv2.COLOR_RGBA2RGB)

