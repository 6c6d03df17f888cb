"""The static hall drawn analytically: floor and carpet, walls with their banners, roof.

Seen from inside, the hall is a box whose faces look inward (the walls towards the field,
the roof down), and TinyRenderer draws only the faces it sees from the front. A pixel's ray
therefore shows the wall or roof through which it leaves the box: the nearest of the faces
the camera is in front of. A camera outside the box (the broadcast view, above the roof)
looks through the back faces between it and the hall, and sees the hall only where its ray
enters the box before it leaves it.

Along a ray of unit depth ``d`` (see :mod:`world.pixel_rays`) the inverse depth of the
plane ``x_k = c`` is ``d_k / (c - p_k)``, linear in the ray, so each face's inverse depth
over the whole image is one broadcast sum; the visible face is the largest. Banners are
axis-aligned rectangles on their own planes just in front of the walls: each of their
edges is the sign of another broadcast sum, evaluated only in the rows and columns where
all four can hold. Walls, banners and roof are sampled where TinyRenderer samples.

The ground (carpet and floor, z = 0) is drawn where the analytic ground has always been
drawn: at pixel centres, in float64, wherever it is nearer than the walls, so images stay
byte-identical to the ones before the walls were drawn here. Rows in which the ground is
nearer than any wall or roof could be skip the walls altogether.

Colours are TinyRenderer's (:mod:`world.shading`), in a palette of at most 256 packed RGBA
words: the few colours of the floor texture (the carpet padded with the floor out to the
walls), then one per wall, roof and banner face. A frame is a palette index per pixel.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from world.config import RenderConfig
from world.field import FieldGeometry
from world.pixel_rays import separable_rays
from world.pose_cache import PoseCache
from world.scene import (
    BANNER_RGBA,
    FLOOR_RGBA,
    SKY_RGBA,
    WALL_RGBA,
    Quad,
    banner_quads,
    hall_half_extent,
    roof_quad,
    wall_quads,
)
from world.shading import flat_shade, material_rgb
from world.textures import TEXEL_M, carpet_texture

F32 = np.float32
CACHE_SIZE = 4  # camera poses whose backdrop is kept (the broadcast view does not move)
FLOOR_NORMAL = (0.0, 0.0, 1.0)
HALL_FACES = 5  # four walls, the roof


@dataclass(frozen=True)
class Backdrop:
    """The hall as one camera sees it (rows top to bottom).

    ``rgba``: (h, w) uint32, pixels packed as TinyRenderer's RGBA bytes. ``min_depth``:
    (h, w) float32, the smallest value of TinyRenderer's depth buffer (0 at the near
    plane, 1 at the far plane) behind which the hall is in front; +inf where the hall is
    not in view. ``colour_index`` (h, w) uint8 and ``texel`` (h, w) int32: what each pixel
    shows, for :meth:`HallBackdrop.floor_texel_centres`.
    """

    rgba: np.ndarray
    min_depth: np.ndarray
    colour_index: np.ndarray
    texel: np.ndarray


@dataclass(frozen=True)
class _Plane:
    """The plane ``x[axis] = offset`` (m, world), seen from the side ``facing`` (+1: x[axis] > offset)."""

    axis: int
    offset: float
    facing: int

    @property
    def normal(self) -> tuple[float, float, float]:
        return tuple(float(self.facing) if k == self.axis else 0.0 for k in range(3))


@dataclass(frozen=True)
class _Banners:
    """The banners, one row each: banner ``b`` hangs on face ``face[b]`` (a palette ``colour[b]``) and lies
    on the plane ``x[axis[b]] = offset[b]``; its four edges are ``x[edge_axes[b, e]] >= edge_bounds[b, e]``
    for ``e`` = 0, 2 and ``<=`` for ``e`` = 1, 3 (m)."""

    face: np.ndarray
    colour: np.ndarray
    axis: np.ndarray
    offset: np.ndarray
    edge_axes: np.ndarray
    edge_bounds: np.ndarray


EDGE_SIGNS = np.array([1.0, -1.0, 1.0, -1.0])[:, None]  # >= low, <= high, >= low, <= high (per edge)


def _plane_and_edges(quad: Quad) -> tuple[_Plane, list[int], list[float]]:
    """The axis-aligned plane of a quad, and its edges as axes and bounds of ``>= low``, ``<= high``."""
    corners = np.asarray(quad, float)
    flat = [k for k in range(3) if np.ptp(corners[:, k]) == 0.0]
    if len(flat) != 1:
        raise ValueError(f"quad {quad} does not lie in an axis-aligned plane")
    axis = flat[0]
    normal = np.cross(corners[1] - corners[0], corners[2] - corners[0])
    others = [k for k in range(3) if k != axis]
    bounds = [float(bound) for k in others for bound in (corners[:, k].min(), corners[:, k].max())]
    plane = _Plane(axis, float(corners[0, axis]), 1 if normal[axis] > 0 else -1)
    return plane, [k for k in others for _ in "lh"], bounds


class _Palette:
    """The colours a backdrop can show, as packed RGBA words, at most 256 of them."""

    def __init__(self) -> None:
        self._rgb: list[np.ndarray] = []

    def add(self, rgb: np.ndarray) -> int:
        """Append a colour (3,) uint8; return its index."""
        self._rgb.append(rgb)
        if len(self._rgb) > 256:
            raise ValueError("more than 256 colours in the hall")
        return len(self._rgb) - 1

    @property
    def packed(self) -> np.ndarray:
        rgb = np.stack(self._rgb)
        return np.concatenate([rgb, np.full((len(rgb), 1), 255, np.uint8)], axis=1).view(np.uint32).ravel()


@dataclass(frozen=True)
class HallTables:
    """What draws the hall, for :mod:`world.raster.hall`: the floor texture as palette indices
    (rows * columns, flat), its shape, corner (m) and padding (texels) around the carpet; the five
    faces' axes, offsets (m), facings and palette colours; the banners; the palette (packed RGBA);
    the index of TinyRenderer's clear colour; the near and far planes (m) and TinyRenderer's depth
    of an inverse depth, ``k0 - k1 * s``."""

    floor_colours: np.ndarray
    floor_shape: tuple[int, int]
    floor_corner_m: tuple[float, float]
    carpet_half_m: tuple[float, float]
    pad_texels: tuple[int, int]
    texel_m: float
    axes: np.ndarray
    offsets_m: np.ndarray
    facings: np.ndarray
    face_colours: np.ndarray
    banners: _Banners
    palette: np.ndarray
    nothing: int
    near_m: float
    far_m: float
    depth_of_inverse: tuple[float, float]
    far_from_inside: bool


class HallBackdrop:
    """Draws the hall of a field for any pinhole camera; caches the last few camera poses."""

    def __init__(self, field: FieldGeometry, render: RenderConfig, texel_m: float = TEXEL_M):
        palette = _Palette()
        floor, self._floor_corner = _floor_texture(field, render, texel_m)
        colours, texel_colours = _unique_colours(floor.reshape(-1, 3))
        self._floor_colours = np.array([palette.add(c) for c in colours], np.uint8)[texel_colours.ravel()]
        self._texel_m, self._floor_shape = texel_m, floor.shape[:2]
        self._carpet_half = (field.carpet_half_length, field.carpet_half_width)
        self._nothing = palette.add(np.full(3, 255, np.uint8))  # TinyRenderer's clear colour; never shown
        planes, self._colours, banners = [], [], []
        for quad, rgba in [(q, WALL_RGBA) for q in wall_quads(field)] + [(roof_quad(field), SKY_RGBA)]:
            plane = _plane_and_edges(quad)[0]
            self._colours.append(palette.add(flat_shade(material_rgb(rgba), plane.normal, render)))
            mine = [edges for edges in map(_plane_and_edges, banner_quads(field)) if edges[0].normal == plane.normal]
            if mine:
                colour = palette.add(flat_shade(material_rgb(BANNER_RGBA), plane.normal, render))
                banners += [(len(planes), colour, b.axis, b.offset, axes, bounds) for b, axes, bounds in mine]
            planes.append(plane)
        face, colour, axis, offset, axes, bounds = (np.array(column) for column in zip(*banners))
        self._banners = _Banners(face, colour.astype(np.uint8), axis, offset, axes, bounds)
        self._axes = np.array([p.axis for p in planes])
        self._offsets = np.array([p.offset for p in planes])
        self._facings = np.array([p.facing for p in planes])
        self._palette = palette.packed
        self._near_m, self._far_m = render.near_m, render.far_m
        # TinyRenderer's depth buffer value at inverse eye depth s is far/(far-near) * (1 - near * s).
        near, far = self._near_m, self._far_m
        self._depth_of_inverse = (F32(far / (far - near)), F32(far * near / (far - near)))
        half_x, half_y = hall_half_extent(field)
        diagonal = float(np.linalg.norm([2 * half_x, 2 * half_y, planes[-1].offset]))  # the roof is last
        self._far_from_inside = diagonal >= far  # may a camera inside the hall see past the far plane?
        self._cache: PoseCache[Backdrop] = PoseCache(CACHE_SIZE)

    def draw(
        self, rotation: np.ndarray, position: np.ndarray, width_px: int, height_px: int, focal_px: float
    ) -> Backdrop:
        """The hall seen from a camera (rotation camera->world, position m), ``focal_px`` focal length."""
        return self._cache.get(rotation, position, (width_px, height_px, focal_px),
                               lambda: self._draw(rotation, np.asarray(position, float), width_px, height_px, focal_px))

    def tables(self) -> HallTables:
        """The tables this backdrop draws from (see :class:`HallTables`)."""
        corner_x, corner_y = self._floor_corner
        half_x, half_y = self._carpet_half
        return HallTables(
            floor_colours=self._floor_colours, floor_shape=tuple(self._floor_shape),
            floor_corner_m=(corner_x, corner_y), carpet_half_m=(half_x, half_y),
            pad_texels=(round((corner_x - half_x) / self._texel_m), round((corner_y - half_y) / self._texel_m)),
            texel_m=self._texel_m, axes=self._axes, offsets_m=self._offsets, facings=self._facings,
            face_colours=np.asarray(self._colours), banners=self._banners, palette=self._palette,
            nothing=self._nothing, near_m=self._near_m, far_m=self._far_m,
            depth_of_inverse=tuple(float(k) for k in self._depth_of_inverse), far_from_inside=self._far_from_inside,
        )

    def floor_texel_centres(self, backdrop: Backdrop) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Which pixels (flat) show the floor or carpet, and the field (x, y) m of the centres of their texels."""
        on_floor = backdrop.colour_index.reshape(-1) < self._nothing
        row, col = np.divmod(backdrop.texel.reshape(-1)[on_floor], self._floor_shape[1])
        corner_x, corner_y = self._floor_corner
        return on_floor, (col + 0.5) * self._texel_m - corner_x, corner_y - (row + 0.5) * self._texel_m

    def _draw(
        self, rotation: np.ndarray, position: np.ndarray, width_px: int, height_px: int, focal_px: float
    ) -> Backdrop:
        shape = (height_px, width_px)
        ground_depth, texel = self._ground(rotation, position, width_px, height_px, focal_px)
        colour_index = np.full(shape, self._nothing, np.uint8)
        hall_inverse = np.full(shape, -np.inf, F32)  # inverse depth of the walls and roof
        columns, rows = separable_rays(rotation, width_px, height_px, focal_px)
        gaps = self._offsets - position[self._axes]
        with np.errstate(divide="ignore"):
            column_terms = (columns[self._axes] / gaps[:, None]).astype(F32)  # inverse depth = column + row term
            row_terms = (rows[self._axes] / gaps[:, None]).astype(F32)
        in_front = gaps * self._facings < 0.0
        front = np.flatnonzero(in_front & (column_terms.max(axis=1) + row_terms.max(axis=1) > 0.0))
        if front.size:
            # Rows where the ground is nearer than any wall or roof could be need no more.
            row_bound = (row_terms[front] + column_terms[front].max(axis=1, keepdims=True)).max(axis=0)
            needed = np.flatnonzero((ground_depth * row_bound[:, None] >= 1.0).any(axis=1))
            if needed.size:
                top, bottom = needed[0], needed[-1] + 1
                rows_needed, row_terms_needed = rows[:, top:bottom], row_terms[:, top:bottom]
                colour_index[top:bottom], hall_inverse[top:bottom] = self._walls_and_roof(
                    front, column_terms, row_terms_needed, columns, rows_needed, position, in_front, gaps
                )
        k0, k1 = self._depth_of_inverse
        ground = np.isfinite(ground_depth)
        ground &= ground_depth * hall_inverse <= 1.0  # in front of the walls and roof
        colour_index = np.where(ground, self._floor_colours.take(texel), colour_index)
        with np.errstate(divide="ignore"):  # -inf hall inverse depth: out of view, +inf minimum depth
            min_depth = k0 - k1 * np.where(ground, F32(1.0) / ground_depth.astype(F32), hall_inverse)
        return Backdrop(self._palette.take(colour_index), min_depth, colour_index, texel)

    def _walls_and_roof(self, front, column_terms, row_terms, columns, rows, position, in_front, gaps):
        """Palette indices (h, w) uint8 of the walls, banners and roof at TinyRenderer's sample points of
        ``rows``, and their inverse depth (h, w) float32 (-inf where they are out of view). ``front``: the
        faces the camera is in front of and some ray leaves the hall through; ``*_terms``: each face's
        inverse depth as column plus row terms."""
        inverse = row_terms[front, :, None] + column_terms[front, None, :]
        nearest = inverse.max(axis=0)
        colour_index = np.empty(nearest.shape, np.uint8)
        on_faces = {}
        for face, face_inverse in zip(front, inverse):
            on_faces[face] = face_inverse == nearest
            np.putmask(colour_index, on_faces[face], self._colours[face])
        _draw_banners(colour_index, on_faces, self._banners, columns, rows, position)
        behind = np.flatnonzero(~in_front & (gaps != 0.0))
        if behind.size or self._far_from_inside:
            in_view = nearest > F32(1.0 / self._far_m)
            for face in behind:  # the ray must enter the box before it leaves it
                in_view &= nearest < row_terms[face, :, None] + column_terms[face]
            nearest[~in_view] = -np.inf
            colour_index[~in_view] = self._nothing
        return colour_index, nearest

    def _ground(
        self, rotation: np.ndarray, position: np.ndarray, width_px: int, height_px: int, focal_px: float
    ) -> tuple[np.ndarray, np.ndarray]:
        """Depth (h, w) m along the optical axis at which each pixel centre's ray meets the floor (+inf where
        it does not, in the near-far range), and the flat index (h, w) int32 of that texel of the floor texture."""
        if position[2] <= 0.0:  # at or below the ground: it faces away
            return np.full((height_px, width_px), np.inf), np.zeros((height_px, width_px), np.int32)
        rays = _centre_rays(width_px, height_px, focal_px)
        down = rays @ rotation[2]
        with np.errstate(divide="ignore", invalid="ignore"):
            depth = -position[2] / down
            x = position[0] + depth * (rays @ rotation[0])
            y = position[1] + depth * (rays @ rotation[1])
        corner_x, corner_y = self._floor_corner
        on_floor = (depth > self._near_m) & (depth < self._far_m)  # and so the ray points down
        on_floor &= (np.abs(x) < corner_x) & (np.abs(y) < corner_y)
        depth = np.where(on_floor, depth, np.inf)
        # Texel columns and rows counted from the carpet's corner, as the carpet texture's, then padded.
        half_x, half_y = self._carpet_half
        pad_columns = round((corner_x - half_x) / self._texel_m)
        pad_rows = round((corner_y - half_y) / self._texel_m)
        with np.errstate(invalid="ignore"):
            column = np.where(on_floor, (x + half_x) / self._texel_m + pad_columns, 0.0).astype(np.int32)
            row = np.where(on_floor, (half_y - y) / self._texel_m + pad_rows, 0.0).astype(np.int32)
        np.minimum(column, self._floor_shape[1] - 1, out=column)
        np.minimum(row, self._floor_shape[0] - 1, out=row)
        row *= self._floor_shape[1]
        row += column
        return depth.reshape(height_px, width_px), row.reshape(height_px, width_px)


def _unique_colours(rgb: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The distinct rows of ``rgb`` (n, 3) uint8 in lexicographic order, and each row's index among them:
    ``np.unique(rgb, axis=0, return_inverse=True)``, twenty times faster on packed 24-bit words."""
    wide = rgb.astype(np.uint32)
    words, inverse = np.unique((wide[:, 0] << 16) | (wide[:, 1] << 8) | wide[:, 2], return_inverse=True)
    colours = np.stack([words >> 16, (words >> 8) & 255, words & 255], axis=1).astype(np.uint8)
    return colours, inverse.ravel()


@functools.lru_cache(maxsize=8)
def _centre_rays(width_px: int, height_px: int, focal_px: float) -> np.ndarray:
    """Unit-depth rays (h*w, 3) through pixel centres, camera frame (x right, y down, z ahead); read-only.

    The ground has always been sampled at pixel centres, in float64, in this order of operations.
    """
    u, v = np.meshgrid(np.arange(width_px) + 0.5, np.arange(height_px) + 0.5)
    rays = np.stack([(u - width_px / 2) / focal_px, (v - height_px / 2) / focal_px, np.ones_like(u)], axis=-1)
    rays = rays.reshape(-1, 3)
    rays.flags.writeable = False
    return rays


def _floor_texture(
    field: FieldGeometry, render: RenderConfig, texel_m: float
) -> tuple[np.ndarray, tuple[float, float]]:
    """The shaded carpet padded with the shaded floor out to the walls (rows, columns, 3) uint8, and
    the corner (x, y) m such that texel (row, col) of field point (x, y) is
    ``((corner_y - y) / texel_m, (x + corner_x) / texel_m)``."""
    carpet = carpet_texture(field, texel_m)
    half_x, half_y = hall_half_extent(field)
    pad_x = round((half_x - field.carpet_half_length) / texel_m)
    pad_y = round((half_y - field.carpet_half_width) / texel_m)
    corner = (field.carpet_half_length + pad_x * texel_m, field.carpet_half_width + pad_y * texel_m)
    if not np.allclose(corner, (half_x, half_y)):
        raise ValueError(f"the floor around the carpet is not a whole number of {texel_m} m texels wide")
    floor = np.empty((carpet.shape[0] + 2 * pad_y, carpet.shape[1] + 2 * pad_x, 3), np.uint8)
    floor[:] = flat_shade(material_rgb(FLOOR_RGBA), FLOOR_NORMAL, render)
    floor[pad_y:-pad_y, pad_x:-pad_x] = flat_shade(material_rgb((1.0, 1.0, 1.0, 1.0), carpet), FLOOR_NORMAL, render)
    return floor, corner


def _draw_banners(colour_index, on_faces: dict[int, np.ndarray], banners: _Banners, columns, rows, position) -> None:
    """Paint the banners into ``colour_index`` where they cover their face (``on_faces``: face -> pixels).

    On a banner's plane ``x_k = c`` a ray meets ``x_j = p_j + d_j (c - p_k) / d_k``; for rays
    that reach the plane, ``x_j >= b`` is ``d_j - (b - p_j) / (c - p_k) * d_k >= 0``: a column
    term plus a row term, whose extremes bound the rows and columns a banner can cover.
    """
    shown = np.zeros(HALL_FACES, bool)
    shown[list(on_faces)] = True
    chosen = np.flatnonzero(shown[banners.face])
    axis, axes = banners.axis[chosen], banners.edge_axes[chosen]
    slopes = (banners.edge_bounds[chosen] - position[axes]) / (banners.offset[chosen] - position[axis])[:, None]
    column_terms = EDGE_SIGNS * (columns[axes] - slopes[:, :, None] * columns[axis][:, None])  # (banners, 4, w)
    row_terms = EDGE_SIGNS * (rows[axes] - slopes[:, :, None] * rows[axis][:, None])  # (banners, 4, h)
    rows_in = (row_terms + column_terms.max(axis=2, keepdims=True) >= 0.0).all(axis=1)
    columns_in = (column_terms + row_terms.max(axis=2, keepdims=True) >= 0.0).all(axis=1)
    first_row, last_row = rows_in.argmax(axis=1), rows_in.shape[1] - 1 - rows_in[:, ::-1].argmax(axis=1)
    first_column, last_column = columns_in.argmax(axis=1), columns_in.shape[1] - 1 - columns_in[:, ::-1].argmax(axis=1)
    for i in np.flatnonzero(rows_in.any(axis=1) & columns_in.any(axis=1)).tolist():
        r0, r1, c0, c1 = first_row[i], last_row[i], first_column[i], last_column[i]
        row_term, column_term = row_terms[i, :, r0 : r1 + 1], column_terms[i, :, c0 : c1 + 1]
        inside = (column_term[:, None, :] >= -row_term[:, :, None]).all(axis=0)
        inside &= on_faces[banners.face[chosen[i]]][r0 : r1 + 1, c0 : c1 + 1]
        colour_index[r0 : r1 + 1, c0 : c1 + 1][inside] = banners.colour[chosen[i]]
