"""The compiled renderer of a world: every camera frame of a step in one call to compiled code.

It draws what TinyRenderer and the analytic hall draw (:mod:`world.rendering`), from the
world's pybullet client: each call reads the bodies' poses once, builds each camera's view
matrix with pybullet's own function, and hands everything to :mod:`world.raster.frames`.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence

import numpy as np

from world import rendering
from world.backdrop import HallBackdrop
from world.config import RenderConfig
from world.pose_cache import PoseCache
from world.raster import frames as kernels
from world.raster.geometry import RasterGeometry, model_matrices
from world.raster.hall import draw_hall, pack_tables
from world.raster.threads import parallel_cameras
from world.shading import material_rgb
from world.teams import TeamColor

F32 = np.float32
HALL_CACHE_SIZE = 4  # fixed camera poses whose hall is kept
# A lone camera's frame is drawn in bands of rows on numba's threads from this size on (the
# broadcast view); a smaller one is drawn sooner on one thread than the sleeping threads wake.
LONE_FRAME_BANDS_MIN_PIXELS = 320 * 240


@functools.lru_cache(maxsize=16)
def projection_matrix(vertical_fov_rad: float, aspect: float, near_m: float, far_m: float) -> np.ndarray:
    """pybullet's projection matrix (4, 4) float32, indexed [row, column], as TinyRenderer gets it; read-only."""
    matrix = np.asarray(rendering.projection_matrix(vertical_fov_rad, aspect, near_m, far_m), np.float32)
    matrix = matrix.reshape(4, 4).T.copy()
    matrix.flags.writeable = False
    return matrix


def view_matrix(rotation: np.ndarray, position: np.ndarray) -> np.ndarray:
    """pybullet's view matrix (4, 4) float32 [row, column] of a camera (rotation camera->world, position m)."""
    return np.asarray(rendering.view_matrix(rotation, position), np.float32).reshape(4, 4).T


class CompiledRenderer:
    """Draws the cameras of one pybullet world (``client``) whose bodies ``geometry`` lists.

    ``parallel``: whether the cameras of one call, or a large lone frame's bands of rows, are drawn on
    numba's threads (:func:`world.raster.threads.parallel_cameras` by default; the images are the same).
    """

    def __init__(self, client: int, geometry: RasterGeometry, hall: HallBackdrop, render: RenderConfig):
        self._client, self._geometry, self._render = client, geometry, render
        self._hall = pack_tables(hall.tables())
        light = np.asarray(render.light_direction, F32).astype(float)
        self._light = (light / np.linalg.norm(light)).astype(F32)
        self._coefficients = (F32(render.ambient), F32(render.diffuse), F32(render.specular))
        self._rgb_of_teams: dict[tuple, np.ndarray] = {}
        self._hall_cache: PoseCache[tuple[np.ndarray, np.ndarray]] = PoseCache(HALL_CACHE_SIZE)
        self.parallel = parallel_cameras()
        self._models: tuple[object, np.ndarray] | None = None  # (poses key, model matrices) of the last call

    def frames(
        self,
        cameras: Sequence[tuple[np.ndarray, np.ndarray]],
        width_px: int,
        height_px: int,
        vertical_fov_rad: float,
        teams: dict[int, TeamColor],
        *,
        fixed_camera: bool = False,
        poses_key: object = None,
    ) -> tuple[np.ndarray, np.ndarray]:
        """RGB images (n, h, w, 3) uint8 of cameras (rotation camera->world, position m), square pixels, and
        each pixel's body label (n, h, w) int32 as pybullet's segmentation mask gives it (object id plus
        (link + 1) << 24), -1 where the hall shows. ``teams`` maps each robot's body id to its team.
        ``fixed_camera``: the cameras seldom move (the broadcast view), so each one's hall is kept for
        the next call from the same pose. ``poses_key``: a value that changes whenever a body moves (None:
        read the poses anew); the next call with the same key reuses the bodies' poses read by this one."""
        n = len(cameras)
        out = np.empty((n, height_px, width_px, 3), np.uint8)
        labels = np.empty((n, height_px, width_px), np.int32)
        if n == 0:
            return out, labels
        rotations = np.ascontiguousarray([np.asarray(r, np.float64) for r, _ in cameras])
        positions = np.ascontiguousarray([np.asarray(p, np.float64) for _, p in cameras])
        views = np.ascontiguousarray([view_matrix(r, p) for r, p in zip(rotations, positions)])
        projection = projection_matrix(vertical_fov_rad, width_px / height_px, self._render.near_m, self._render.far_m)
        focal = (height_px / 2.0) / math.tan(vertical_fov_rad / 2.0)
        if fixed_camera:
            halls = [self._cached_hall(r, p, width_px, height_px, focal) for r, p in zip(rotations, positions)]
            halls_rgba, halls_depth = np.stack([h[0] for h in halls]), np.stack([h[1] for h in halls])
        else:
            halls_rgba = np.empty((n, width_px * height_px), np.uint32)
            halls_depth = np.empty((n, width_px * height_px), np.float32)
        g = self._geometry
        parallel = self.parallel and (n > 1 or width_px * height_px >= LONE_FRAME_BANDS_MIN_PIXELS)
        draw = kernels.draw_frames_parallel if parallel else kernels.draw_frames
        draw(out, labels, halls_rgba, halls_depth, fixed_camera, rotations, positions, views, projection, width_px,
             height_px, focal, *self._hall, self._model_matrices(poses_key), g.vertices, g.normals, g.triangles,
             g.instance, g.first, g.count, self._shape_rgb(teams), g.label, g.centre, g.radius, self._light,
             *self._coefficients)
        return out, labels

    def _model_matrices(self, poses_key: object) -> np.ndarray:
        if poses_key is None or self._models is None or self._models[0] != poses_key:
            self._models = (poses_key, model_matrices(self._client, self._geometry))
        return self._models[1]

    def _cached_hall(self, rotation: np.ndarray, position: np.ndarray, width_px: int, height_px: int,
                     focal: float) -> tuple[np.ndarray, np.ndarray]:
        def draw() -> tuple[np.ndarray, np.ndarray]:
            hall = (np.empty(width_px * height_px, np.uint32), np.empty(width_px * height_px, np.float32))
            draw_hall(rotation, position, width_px, height_px, focal, *self._hall, *hall)
            return hall

        return self._hall_cache.get(rotation, position, (width_px, height_px, focal), draw)

    def _shape_rgb(self, teams: dict[int, TeamColor]) -> np.ndarray:
        """The shapes' colours with each waistband in its robot's team colour."""
        key = tuple(sorted((body, team.value) for body, team in teams.items()))
        rgb = self._rgb_of_teams.get(key)
        if rgb is None:
            rgb = self._geometry.rgb.copy()
            for body, shape in self._geometry.team_shapes.items():
                rgb[shape] = material_rgb(teams[body].rgba)
            self._rgb_of_teams[key] = rgb
        return rgb
