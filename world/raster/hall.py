"""The hall (floor, carpet, walls, banners, roof) drawn per pixel in compiled code.

The same image as :class:`world.backdrop.HallBackdrop` draws with numpy, pixel for pixel:
the floor at pixel centres in float64, walls, banners and roof at TinyRenderer's sample
points with inverse depths summed from a column and a row term in float32, the same ties
(the last face of equal inverse depth colours the pixel, a banner shows where its face is
among the nearest), the same rows skipped where the ground is nearer than any wall could be,
and the same depth threshold of TinyRenderer's buffer behind which the hall shows. The
tables come from :meth:`world.backdrop.HallBackdrop.tables`.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

F32 = np.float32
NEG_INF = -math.inf


@njit(cache=True, error_model="numpy")
def _ground(rotation, position, width, height, row_lo, row_hi, focal, near, far, corner_x, corner_y, carpet_half_x,
            carpet_half_y, texel_m, pad_columns, pad_rows, floor_rows, floor_columns, depth, texel):
    """Depth (m, along the optical axis) at which each pixel centre's ray of rows ``row_lo:row_hi`` meets
    the floor (+inf where it does not, within near-far), and the flat index of the floor texel there (0
    where there is none).

    Each row is computed in two passes: the arithmetic of all its pixels (which the compiler can
    vectorise), then the tests; rows whose rays all point up are skipped."""
    depth[row_lo * width:row_hi * width] = np.inf
    texel[row_lo * width:row_hi * width] = 0
    if position[2] <= 0.0:
        return
    column_slope = np.empty(width)
    for i in range(width):
        column_slope[i] = (i + 0.5 - width / 2) / focal
    d = np.empty(width)
    x = np.empty(width)
    y = np.empty(width)
    for r in range(row_lo, row_hi):
        ry = (r + 0.5 - height / 2) / focal
        down_row, x_row, y_row = ry * rotation[2, 1], ry * rotation[0, 1], ry * rotation[1, 1]
        left = (column_slope[0] * rotation[2, 0] + down_row) + rotation[2, 2]
        right = (column_slope[width - 1] * rotation[2, 0] + down_row) + rotation[2, 2]
        if left > 1e-9 and right > 1e-9:  # every ray of the row points up
            continue
        for i in range(width):
            rx = column_slope[i]
            d[i] = -position[2] / ((rx * rotation[2, 0] + down_row) + rotation[2, 2])
            x[i] = position[0] + d[i] * ((rx * rotation[0, 0] + x_row) + rotation[0, 2])
            y[i] = position[1] + d[i] * ((rx * rotation[1, 0] + y_row) + rotation[1, 2])
        depth_row, texel_row = depth[r * width:(r + 1) * width], texel[r * width:(r + 1) * width]
        for i in range(width):  # selects, no branches: the loop vectorises
            inside = d[i] > near and d[i] < far and abs(x[i]) < corner_x and abs(y[i]) < corner_y
            # a point outside is clamped to the floor, so its texel's arithmetic stays in range (unused)
            column = min(np.int32((min(max(x[i], -corner_x), corner_x) + carpet_half_x) / texel_m + pad_columns),
                         floor_columns - 1)
            row = min(np.int32((carpet_half_y - min(max(y[i], -corner_y), corner_y)) / texel_m + pad_rows),
                      floor_rows - 1)
            depth_row[i] = d[i] if inside else np.inf
            texel_row[i] = row * floor_columns + column if inside else 0


@njit(cache=True, error_model="numpy")
def draw_hall(rotation, position, width, height, focal, tables_f64, tables_i64, floor_colours, face_colours,
              banner_i, banner_f, palette, out_rgba, out_min_depth):
    """The hall seen from a camera (rotation camera->world, position m, ``focal`` px): packed RGBA
    (h*w uint32) and the smallest TinyRenderer depth-buffer value behind which it shows (h*w float32,
    +inf where it is not in view). ``tables_f64``, ``tables_i64``, ``banner_i`` and ``banner_f`` are
    :class:`world.backdrop.HallTables` packed by :func:`pack_tables`."""
    draw_hall_rows(rotation, position, width, height, 0, height, focal, tables_f64, tables_i64, floor_colours,
                   face_colours, banner_i, banner_f, palette, out_rgba, out_min_depth)


@njit(cache=True, error_model="numpy")
def draw_hall_rows(rotation, position, width, height, row_lo, row_hi, focal, tables_f64, tables_i64, floor_colours,
                   face_colours, banner_i, banner_f, palette, out_rgba, out_min_depth):
    """:func:`draw_hall` for the image rows ``row_lo:row_hi`` (from the top) only: each row's pixels
    depend on nothing but the row, so bands drawn apart make the same image."""
    near, far, corner_x, corner_y = tables_f64[0], tables_f64[1], tables_f64[2], tables_f64[3]
    carpet_half_x, carpet_half_y, texel_m = tables_f64[4], tables_f64[5], tables_f64[6]
    k0, k1, inverse_far = F32(tables_f64[7]), F32(tables_f64[8]), F32(1.0 / far)
    pad_columns, pad_rows, floor_rows, floor_columns = tables_i64[0], tables_i64[1], tables_i64[2], tables_i64[3]
    nothing, far_from_inside, faces = tables_i64[4], tables_i64[5] != 0, tables_i64[6]
    axes, facings = tables_i64[7:7 + faces], tables_i64[7 + faces:7 + 2 * faces]
    offsets = tables_f64[9:9 + faces]
    pixels = width * height
    ground_depth = np.empty(pixels, np.float64)
    texel = np.empty(pixels, np.int32)
    _ground(rotation, position, width, height, row_lo, row_hi, focal, near, far, corner_x, corner_y, carpet_half_x,
            carpet_half_y, texel_m, pad_columns, pad_rows, floor_rows, floor_columns, ground_depth, texel)

    # Sample points of TinyRenderer: column slope (i - w/2) / f, row slope (r + 1 - h/2) / f.
    column_rays = np.empty((3, width))
    row_rays = np.empty((3, height))
    for i in range(width):
        x = (i - width / 2) / focal
        for k in range(3):
            column_rays[k, i] = rotation[k, 0] * x + rotation[k, 2]
    for r in range(height):
        y = (r + 1 - height / 2) / focal
        for k in range(3):
            row_rays[k, r] = rotation[k, 1] * y
    gaps = np.empty(faces)
    column_terms = np.empty((faces, width), np.float32)
    row_terms = np.empty((faces, height), np.float32)
    front = np.zeros(faces, np.bool_)
    behind = np.zeros(faces, np.bool_)
    column_max = np.empty(faces, np.float32)
    any_front = False
    for f in range(faces):
        gaps[f] = offsets[f] - position[axes[f]]
        best_c = F32(-np.inf)
        for i in range(width):
            column_terms[f, i] = F32(column_rays[axes[f], i] / gaps[f])
            best_c = max(best_c, column_terms[f, i])
        best_r = F32(-np.inf)
        for r in range(height):
            row_terms[f, r] = F32(row_rays[axes[f], r] / gaps[f])
            best_r = max(best_r, row_terms[f, r])
        column_max[f] = best_c
        in_front = gaps[f] * facings[f] < 0.0
        front[f] = in_front and best_c + best_r > F32(0.0)
        behind[f] = (not in_front) and gaps[f] != 0.0
        any_front = any_front or front[f]
    any_behind = False
    for f in range(faces):
        any_behind = any_behind or behind[f]

    colour = np.full(pixels, nothing, np.int32)
    hall_inverse = np.full(pixels, F32(NEG_INF), np.float32)
    top, bottom = row_hi, row_lo
    if any_front:  # rows in which the ground is nearer than any wall or roof could be need no more
        for r in range(row_lo, row_hi):
            bound = F32(-np.inf)
            for f in range(faces):
                if front[f]:
                    bound = max(bound, row_terms[f, r] + column_max[f])
            # some pixel's ground_depth * bound >= 1: at the row's farthest ground, as the product grows with it
            farthest = 0.0
            for g in ground_depth[r * width:(r + 1) * width]:
                farthest = max(farthest, g)
            if bound > F32(0.0) and farthest * bound >= 1.0:
                top = min(top, r)
                bottom = max(bottom, r + 1)
    if top < bottom:
        _walls(top, bottom, width, faces, front, behind, any_behind or far_from_inside, inverse_far, column_terms,
               row_terms, face_colours, nothing, colour, hall_inverse)
        _banners(top, bottom, width, front, banner_i, banner_f, column_rays, row_rays, position, column_terms,
                 row_terms, colour, hall_inverse)
    lo, hi = row_lo * width, row_hi * width  # views indexed from 0, selects: the loop vectorises
    _compose(ground_depth[lo:hi], texel[lo:hi], colour[lo:hi], hall_inverse[lo:hi], floor_colours, palette, k0, k1,
             out_rgba[lo:hi], out_min_depth[lo:hi])


@njit(cache=True, error_model="numpy")
def _compose(ground_depth, texel, colour, hall_inverse, floor_colours, palette, k0, k1, out_rgba, out_min_depth):
    """Each pixel's colour and depth threshold: the floor where it is nearer than the walls, else the walls."""
    for k in range(ground_depth.shape[0]):
        g = ground_depth[k]
        on_ground = g < np.inf and g * hall_inverse[k] <= 1.0
        chosen = np.int32(floor_colours[texel[k]]) if on_ground else colour[k]
        inverse = F32(1.0) / F32(g) if on_ground else hall_inverse[k]
        out_min_depth[k] = k0 - k1 * inverse
        out_rgba[k] = palette[chosen]


@njit(cache=True, error_model="numpy")
def _walls(top, bottom, width, faces, front, behind, check_view, inverse_far, column_terms, row_terms,
           face_colours, nothing, colour, hall_inverse):
    """The nearest wall or roof face of each pixel of rows ``top:bottom``, its colour and inverse depth.

    Faces in order, the last of equal inverse depth kept; each row is done face by face over all its
    pixels, with selects (the loops vectorise)."""
    nearest = np.empty(width, np.float32)
    chosen = np.empty(width, np.int32)
    in_view = np.empty(width, np.bool_)
    for r in range(top, bottom):
        nearest[:] = F32(NEG_INF)
        chosen[:] = -1
        for f in range(faces):
            if not front[f]:
                continue
            term, columns = row_terms[f, r], column_terms[f]
            for i in range(width):
                inverse = term + columns[i]
                take = inverse >= nearest[i]
                nearest[i] = inverse if take else nearest[i]
                chosen[i] = f if take else chosen[i]
        for i in range(width):
            in_view[i] = chosen[i] >= 0
        if check_view:  # the ray must reach the far plane's side of the hall, and enter before it leaves
            for i in range(width):
                in_view[i] = in_view[i] and nearest[i] > inverse_far
            for f in range(faces):
                if not behind[f]:
                    continue
                term, columns = row_terms[f, r], column_terms[f]
                for i in range(width):
                    in_view[i] = in_view[i] and nearest[i] < term + columns[i]
        colour_row, inverse_row = colour[r * width:(r + 1) * width], hall_inverse[r * width:(r + 1) * width]
        for i in range(width):
            seen = chosen[i] >= 0
            inverse_row[i] = nearest[i] if in_view[i] else (F32(NEG_INF) if seen else inverse_row[i])
            colour_row[i] = face_colours[max(chosen[i], 0)] if in_view[i] else (nothing if seen else colour_row[i])


@njit(cache=True, error_model="numpy")
def _banners(top, bottom, width, front, banner_i, banner_f, column_rays, row_rays, position, column_terms, row_terms,
             colour, hall_inverse):
    """Paint each banner of a face in front where its four edges hold and its face is among the nearest.

    ``banner_i`` (b, 7): face, colour, plane axis, four edge axes; ``banner_f`` (b, 5): plane offset m,
    four edge bounds m (``>=`` for edges 0 and 2, ``<=`` for 1 and 3)."""
    height = bottom - top
    edge_c = np.empty((4, width))
    edge_r = np.empty((4, height))
    for b in range(banner_i.shape[0]):
        face = banner_i[b, 0]
        if not front[face]:
            continue
        axis = banner_i[b, 2]
        distance = banner_f[b, 0] - position[axis]
        rows_lo, rows_hi, cols_lo, cols_hi = height, -1, width, -1
        for e in range(4):
            edge_axis = banner_i[b, 3 + e]
            slope = (banner_f[b, 1 + e] - position[edge_axis]) / distance
            sign = 1.0 if e % 2 == 0 else -1.0
            for i in range(width):
                edge_c[e, i] = sign * (column_rays[edge_axis, i] - slope * column_rays[axis, i])
            for r in range(height):
                edge_r[e, r] = sign * (row_rays[edge_axis, top + r] - slope * row_rays[axis, top + r])
        max_c = np.empty(4)
        max_r = np.empty(4)
        for e in range(4):
            max_c[e] = edge_c[e].max()
            max_r[e] = edge_r[e].max()
        for r in range(height):
            if all_edges_hold(edge_r[:, r], max_c):
                rows_lo, rows_hi = min(rows_lo, r), max(rows_hi, r)
        for i in range(width):
            if all_edges_hold(edge_c[:, i], max_r):
                cols_lo, cols_hi = min(cols_lo, i), max(cols_hi, i)
        for r in range(rows_lo, rows_hi + 1):
            for i in range(cols_lo, cols_hi + 1):
                inside = True
                for e in range(4):
                    inside = inside and edge_c[e, i] >= -edge_r[e, r]
                k = (top + r) * width + i
                if inside and row_terms[face, top + r] + column_terms[face, i] == hall_inverse[k]:
                    colour[k] = banner_i[b, 1]


@njit(cache=True, inline="always")
def all_edges_hold(terms, other_max):
    for e in range(4):
        if not terms[e] + other_max[e] >= 0.0:
            return False
    return True


def pack_tables(tables) -> tuple[np.ndarray, ...]:
    """:class:`world.backdrop.HallTables` as the arrays :func:`draw_hall` takes: (floats, integers,
    floor colours, face colours, banner integers, banner floats, palette)."""
    faces = len(tables.axes)
    floats = np.array([tables.near_m, tables.far_m, *tables.floor_corner_m, *tables.carpet_half_m, tables.texel_m,
                       *tables.depth_of_inverse, *tables.offsets_m], np.float64)
    integers = np.array([*tables.pad_texels, *tables.floor_shape, tables.nothing, int(tables.far_from_inside), faces,
                         *tables.axes, *tables.facings], np.int64)
    banners = tables.banners
    banner_i = np.column_stack([banners.face, banners.colour, banners.axis, banners.edge_axes]).astype(np.int64)
    banner_f = np.column_stack([banners.offset, banners.edge_bounds]).astype(np.float64)
    return (floats, integers, np.ascontiguousarray(tables.floor_colours, np.uint8), tables.face_colours.astype(np.int32),
            np.ascontiguousarray(banner_i), np.ascontiguousarray(banner_f), tables.palette)
