"""Whole camera frames in one compiled call: the hall per pixel, the bodies' triangles, merged by depth.

For each camera: the hall (:func:`world.raster.hall.draw_hall`) gives a colour and the depth
of TinyRenderer's buffer behind which it shows; the bodies are drawn as TinyRenderer draws
them (:mod:`world.raster.triangles`: shapes in creation order, triangles in mesh order) into
a depth, colour and label buffer; a body pixel shows where its depth, converted as pybullet
converts TinyRenderer's buffer, is nearer than the hall's. Rows are flipped to top-to-bottom.

Shapes are culled by their bounding sphere against the view frustum first (a culled shape
could not have covered a pixel). The vertices and normals of the shapes some camera may see are
placed in the world once per call (:func:`shape_in_world`); each camera then projects them.
Cameras are independent, and so are bands of rows of one camera (each row of the hall depends
only on the row, and a triangle drawn into a band covers there what it covers in the whole
frame): :func:`draw_frames_parallel` shares the cameras, or a lone camera's bands, among numba's
threads, :func:`draw_frames` draws on one.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from world.raster.hall import draw_hall_rows
from world.raster.triangles import (
    draw_triangle,
    invert_transpose,
    mat_mul,
    new_scratch,
    transform_point,
    transform_point3,
)

F32 = np.float32
CLEAR = np.uint32(0xFFFFFFFF)  # TinyRenderer's clear colour, white
LONE_CAMERA_BANDS = 2  # bands of rows of a lone camera's frame drawn apart on numba's threads


@njit(cache=True, error_model="numpy")
def _viewport(width, height):
    m = np.zeros((4, 4), np.float32)
    m[0, 0] = F32(width / 2.0)
    m[1, 1] = F32(height / 2.0)
    m[2, 2] = F32(0.5)
    m[0, 3] = F32(width / 2.0)
    m[1, 3] = F32(height / 2.0)
    m[2, 3] = F32(0.5)
    m[3, 3] = F32(1.0)
    return m


@njit(cache=True, inline="always")
def _frustum(projection, width, height):
    """The near and far planes (m, float32) of pybullet's projection matrix, and the tangents of the
    half angles of view across and up the image."""
    near = projection[2, 3] / (projection[2, 2] - F32(1.0))
    far = projection[2, 3] / (projection[2, 2] + F32(1.0))
    return near, far, (width / 2.0) / (height / 2.0) / float(projection[1, 1]), 1.0 / float(projection[1, 1])


@njit(cache=True, error_model="numpy")
def _outside_frustum(model_view, centre, radius, tan_x, tan_y, near, far):
    """Whether a sphere (centre in the shape's frame, radius m) lies wholly outside the view frustum."""
    c = np.empty(3)
    for i in range(3):
        c[i] = (float(model_view[i, 0]) * centre[0] + float(model_view[i, 1]) * centre[1]
                + float(model_view[i, 2]) * centre[2] + float(model_view[i, 3]))
    margin = radius * 1.01 + 1e-4
    ahead = -c[2]
    if ahead + margin < near or ahead - margin > far:
        return True
    scale_x = 1.0 / np.sqrt(1.0 + tan_x * tan_x)
    scale_y = 1.0 / np.sqrt(1.0 + tan_y * tan_y)
    if (c[0] - ahead * tan_x) * scale_x > margin or (-c[0] - ahead * tan_x) * scale_x > margin:
        return True
    return (c[1] - ahead * tan_y) * scale_y > margin or (-c[1] - ahead * tan_y) * scale_y > margin


@njit(cache=True, error_model="numpy")
def draw_bodies(view, projection, width, height, rows, models, world_vertices, world_normals, vertices, triangles,
                shape_instance, shape_first, shape_count, shape_rgb, shape_label, shape_centre, shape_radius,
                light, ambient, diffuse, specular, zbuffer, colour, label):
    """Every shape's triangles into the buffers (h*w, rows from the bottom), as TinyRenderer draws them;
    only the buffer rows ``rows`` = ``(lo, hi)`` are cleared and drawn. ``world_vertices`` and
    ``world_normals``: the vertices in the world (:func:`shape_in_world`)."""
    near, far, tan_x, tan_y = _frustum(projection, width, height)
    lo, hi = rows[0] * width, rows[1] * width
    zbuffer[lo:hi] = -far
    colour[lo:hi] = CLEAR
    label[lo:hi] = -1
    viewport = _viewport(width, height)
    eye = invert_transpose(view)  # its row 3 is the camera position (TinyRenderer's inverted view matrix)
    px, py, pz = float(eye[3, 0]), float(eye[3, 1]), float(eye[3, 2])
    gl = np.empty((4, 3), np.float32)
    vertex_normals = np.empty((3, 3), np.float32)
    model_view = np.empty((4, 4), np.float32)
    pmv = np.empty((4, 4), np.float32)
    scratch = new_scratch(width)
    for s in range(shape_instance.shape[0]):
        mat_mul(view, models[shape_instance[s]], model_view)
        if _outside_frustum(model_view, shape_centre[s], shape_radius[s], tan_x, tan_y, float(near), float(far)):
            continue
        mat_mul(projection, model_view, pmv)
        for t in range(shape_first[s], shape_first[s] + shape_count[s]):
            a, b, c = triangles[t, 0], triangles[t, 1], triangles[t, 2]
            w = world_vertices
            ax, ay, az = float(w[0, a]), float(w[1, a]), float(w[2, a])
            ux, uy, uz = float(w[0, b]) - ax, float(w[1, b]) - ay, float(w[2, b]) - az
            vx, vy, vz = float(w[0, c]) - ax, float(w[1, c]) - ay, float(w[2, c]) - az
            nx, ny, nz = uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx
            if (ax - px) * nx + (ay - py) * ny + (az - pz) * nz >= 0.0:  # back face
                continue
            for j in range(3):
                v = triangles[t, j]
                transform_point(pmv, vertices[v, 0], vertices[v, 1], vertices[v, 2], F32(1.0), gl, j)
                for i in range(3):
                    vertex_normals[i, j] = world_normals[i, v]
            draw_triangle(gl, viewport, zbuffer, colour, label, shape_label[s], width, height, rows, vertex_normals,
                          light, shape_rgb[s], ambient, diffuse, specular, near, far, scratch)


@njit(cache=True, error_model="numpy")
def shapes_in_view(views, projection, width, height, models, shape_instance, shape_centre, shape_radius):
    """Whether each shape may show in some camera of ``views`` (n, 4, 4): its bounding sphere is not wholly
    outside the camera's view frustum (the test :func:`draw_bodies` makes before drawing a shape)."""
    near, far, tan_x, tan_y = _frustum(projection, width, height)
    model_view = np.empty((4, 4), np.float32)
    seen = np.zeros(shape_instance.shape[0], np.bool_)
    for c in range(views.shape[0]):
        for s in range(shape_instance.shape[0]):
            if not seen[s]:
                mat_mul(views[c], models[shape_instance[s]], model_view)
                seen[s] = not _outside_frustum(model_view, shape_centre[s], shape_radius[s], tan_x, tan_y,
                                               float(near), float(far))
    return seen


@njit(cache=True, error_model="numpy")
def shape_in_world(s, models, inverse_models, vertices, normals, triangles, shape_instance, shape_first, shape_count,
                   world_vertices, world_normals):
    """Shape ``s``'s vertices in the world, the same for every camera: into ``world_vertices`` (4, v) float32
    [homogeneous coordinate, vertex] the model matrix times the vertex, into ``world_normals`` (3, v) the
    normal matrix (:func:`inverse_transposes`) times its normal. A shape's vertices are its own (the meshes
    are concatenated), so shapes may be done on several threads at once."""
    first, last = vertices.shape[0], -1
    for t in range(shape_first[s], shape_first[s] + shape_count[s]):
        for j in range(3):
            first, last = min(first, triangles[t, j]), max(last, triangles[t, j])
    model, inverse = models[shape_instance[s]], inverse_models[shape_instance[s]]
    for v in range(first, last + 1):
        transform_point(model, vertices[v, 0], vertices[v, 1], vertices[v, 2], F32(1.0), world_vertices, v)
        transform_point3(inverse, normals[v, 0], normals[v, 1], normals[v, 2], world_normals, v)


@njit(cache=True, error_model="numpy")
def _merge(width, height, rows, projection, zbuffer, colour, label, hall_rgba, hall_min_depth, out, out_label):
    """The bodies where nearer than the hall, else the hall, in the buffer rows ``rows`` = ``(lo, hi)``;
    rows flipped to top-to-bottom.

    A pixel no body covers has the clear depth, which converts to ``clear_depth``: it shows the hall, or
    the clear colour where the hall is not in view. Each row is first written as if no body covered it
    (a loop without branches), then rewritten from the first to the last pixel a body covers, each depth
    converted."""
    near, far, _, _ = _frustum(projection, width, height)
    clear = -far
    clear_depth = _depth_of(clear, near, far)
    packed = np.empty(width, np.uint32)
    for y in range(rows[0], rows[1]):
        # views of the row, indexed from 0 by the loops: the compiler sees no negative index and vectorises
        source, target = y * width, (height - 1 - y) * width
        z_row, colour_row = zbuffer[source:source + width], colour[source:source + width]
        label_row = label[source:source + width]
        hall_row, threshold_row = hall_rgba[target:target + width], hall_min_depth[target:target + width]
        rgb_row, out_label_row = out[height - 1 - y].reshape(-1), out_label[target:target + width]
        first, last = width, -1
        for x in range(width):
            covered = z_row[x] != clear
            first = min(first, x if covered else width)
            last = max(last, x if covered else -1)
        for x in range(width):
            packed[x] = CLEAR if clear_depth < threshold_row[x] else hall_row[x]
            out_label_row[x] = -1
        for x in range(first, last + 1):
            body = _depth_of(z_row[x], near, far) < threshold_row[x]
            packed[x] = colour_row[x] if body else packed[x]
            out_label_row[x] = label_row[x] if body else -1
        for x in range(width):  # apart: byte stores would keep the loops above from vectorising
            _put(rgb_row, x, packed[x])


@njit(cache=True, inline="always")
def _depth_of(z, near, far):
    """pybullet's depth-buffer value (float32) of TinyRenderer's buffer value ``z``."""
    z_c = -z
    return F32((far * (near + z_c)) / (2.0 * float(far) * float(near) + float(far * z_c) - float(near * z_c)))


@njit(cache=True, inline="always")
def _put(flat, k, packed):
    """Pixel ``k`` of the flat RGB image ``flat``: the first three bytes of the packed RGBA ``packed``."""
    flat[3 * k] = np.uint8(packed & 0xFF)
    flat[3 * k + 1] = np.uint8((packed >> 8) & 0xFF)
    flat[3 * k + 2] = np.uint8((packed >> 16) & 0xFF)


@njit(cache=True, error_model="numpy")
def _draw_band(c, band, bands, out, out_labels, halls_rgba, halls_min_depth, halls_given, rotations, positions, views,
               projection, width, height, focal, hall_f64, hall_i64, floor_colours, face_colours, banner_i, banner_f,
               palette, models, world_vertices, world_normals, vertices, triangles, shape_instance, shape_first,
               shape_count, shape_rgb, shape_label, shape_centre, shape_radius, light, ambient, diffuse, specular):
    """Band ``band`` of ``bands`` equal bands of rows of camera ``c``'s frame."""
    top, bottom = band * height // bands, (band + 1) * height // bands  # image rows, from the top
    if not halls_given:
        draw_hall_rows(rotations[c], positions[c], width, height, top, bottom, focal, hall_f64, hall_i64,
                       floor_colours, face_colours, banner_i, banner_f, palette, halls_rgba[c], halls_min_depth[c])
    rows = (height - bottom, height - top)  # the same rows in the buffers, which count from the bottom
    pixels = width * height
    zbuffer = np.empty(pixels, np.float32)
    colour = np.empty(pixels, np.uint32)
    label = np.empty(pixels, np.int32)
    draw_bodies(views[c], projection, width, height, rows, models, world_vertices, world_normals, vertices, triangles,
                shape_instance, shape_first, shape_count, shape_rgb, shape_label, shape_centre, shape_radius,
                light, ambient, diffuse, specular, zbuffer, colour, label)
    _merge(width, height, rows, projection, zbuffer, colour, label, halls_rgba[c], halls_min_depth[c], out[c],
           out_labels[c].reshape(-1))


@njit(cache=True, error_model="numpy")
def inverse_transposes(models):
    """TinyRenderer's normal matrices (``invert_transpose``) of the model matrices (n, 4, 4)."""
    out = np.empty_like(models)
    for i in range(models.shape[0]):
        out[i] = invert_transpose(models[i])
    return out


@njit(cache=True, error_model="numpy")
def _world_buffers(views, projection, width, height, models, vertices, shape_instance, shape_centre, shape_radius):
    """What a call places in the world before its cameras draw: the normal matrices, the buffers of the
    vertices and normals in the world (for :func:`shape_in_world`) and the shapes some camera may see."""
    shown = np.nonzero(shapes_in_view(views, projection, width, height, models, shape_instance, shape_centre,
                                      shape_radius))[0]
    return (inverse_transposes(models), np.empty((4, vertices.shape[0]), np.float32),
            np.empty((3, vertices.shape[0]), np.float32), shown)


@njit(cache=True, error_model="numpy")
def draw_frames(out, out_labels, halls_rgba, halls_min_depth, halls_given, rotations, positions, views, projection,
                width, height, focal, hall_f64, hall_i64, floor_colours, face_colours, banner_i, banner_f, palette,
                models, vertices, normals, triangles, shape_instance, shape_first, shape_count, shape_rgb,
                shape_label, shape_centre, shape_radius, light, ambient, diffuse, specular):
    """Every camera's frame (``out`` (n, h, w, 3) uint8) and pybullet-style labels (``out_labels`` (n, h, w)
    int32, -1 where the hall shows), one camera after another. ``halls_*`` (n, h*w): each camera's hall,
    drawn here unless ``halls_given``."""
    inverse_models, world_vertices, world_normals, shown = _world_buffers(
        views, projection, width, height, models, vertices, shape_instance, shape_centre, shape_radius)
    for k in range(shown.shape[0]):
        shape_in_world(shown[k], models, inverse_models, vertices, normals, triangles, shape_instance, shape_first,
                       shape_count, world_vertices, world_normals)
    for c in range(out.shape[0]):
        _draw_band(c, 0, 1, out, out_labels, halls_rgba, halls_min_depth, halls_given, rotations, positions,
                   views, projection, width, height, focal, hall_f64, hall_i64, floor_colours, face_colours, banner_i,
                   banner_f, palette, models, world_vertices, world_normals, vertices, triangles, shape_instance,
                   shape_first, shape_count, shape_rgb, shape_label, shape_centre, shape_radius, light, ambient,
                   diffuse, specular)


@njit(cache=True, error_model="numpy", parallel=True)
def draw_frames_parallel(out, out_labels, halls_rgba, halls_min_depth, halls_given, rotations, positions, views,
                         projection, width, height, focal, hall_f64, hall_i64, floor_colours, face_colours, banner_i,
                         banner_f, palette, models, vertices, normals, triangles, shape_instance, shape_first,
                         shape_count, shape_rgb, shape_label, shape_centre, shape_radius, light, ambient, diffuse,
                         specular):
    """As :func:`draw_frames`, the cameras shared among numba's threads; a lone camera's frame is shared
    as :data:`LONE_CAMERA_BANDS` bands of rows."""
    inverse_models, world_vertices, world_normals, shown = _world_buffers(
        views, projection, width, height, models, vertices, shape_instance, shape_centre, shape_radius)
    for k in prange(shown.shape[0]):
        shape_in_world(shown[k], models, inverse_models, vertices, normals, triangles, shape_instance, shape_first,
                       shape_count, world_vertices, world_normals)
    bands = LONE_CAMERA_BANDS if out.shape[0] == 1 else 1
    for job in prange(out.shape[0] * bands):
        _draw_band(job // bands, job % bands, bands, out, out_labels, halls_rgba, halls_min_depth, halls_given,
                   rotations, positions, views, projection, width, height, focal, hall_f64, hall_i64, floor_colours,
                   face_colours, banner_i, banner_f, palette, models, world_vertices, world_normals, vertices,
                   triangles, shape_instance, shape_first, shape_count, shape_rgb, shape_label, shape_centre,
                   shape_radius, light, ambient, diffuse, specular)
