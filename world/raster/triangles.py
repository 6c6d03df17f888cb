"""TinyRenderer's triangle pipeline, compiled: vertex transform, back-face culling, near-plane
clipping, coverage, depth test and Lambert shading, in TinyRenderer's arithmetic.

TinyRenderer works in float32 matrices whose products sum their terms last index first,
tests coverage at integer screen points with double-precision barycentric coordinates of
float32 screen points, keeps a float32 depth buffer (larger is nearer) that it compares with
a double fragment depth, and shades with the normals interpolated at the fragment. Each
function here does those operations in that order, so a triangle covers the same pixels with
the same colours and depths. Screen rows count from the bottom, as TinyRenderer's do; the
caller flips them.

Matrices are (4, 4) float32 arrays indexed ``[row, column]``, as TinyRenderer's.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

F32 = np.float32
FLAT_MARGIN = 1e-2  # how far from a whole number a flat face's channel must be to be shaded once (see _flat_colour)
SPAN_MARGIN_PX = 0.01  # rounding moves a span's ends by some 1e-9 px; a hundredth of a pixel is far beyond it


@njit(cache=True, inline="always")
def dot4(a0, a1, a2, a3, b0, b1, b2, b3):
    """TinyRenderer's dot product of two float32 4-vectors: ((a3 b3 + a2 b2) + a1 b1) + a0 b0 from zero."""
    ret = F32(0.0)
    ret += a3 * b3
    ret += a2 * b2
    ret += a1 * b1
    ret += a0 * b0
    return ret


@njit(cache=True)
def mat_mul(a, b, out):
    """``out[:] = a @ b`` for (4, 4) float32 matrices, each element summed as :func:`dot4`."""
    for i in range(4):
        for j in range(4):
            out[i, j] = dot4(a[i, 0], a[i, 1], a[i, 2], a[i, 3], b[0, j], b[1, j], b[2, j], b[3, j])


@njit(cache=True, inline="always")
def b3_min(a, b):
    """Bullet's ``b3Min``: ``a < b ? a : b`` (so a NaN ``b`` wins)."""
    return a if a < b else b


@njit(cache=True, inline="always")
def b3_max(a, b):
    """Bullet's ``b3Max``: ``a > b ? a : b``."""
    return a if a > b else b


@njit(cache=True, inline="always")
def _det2(m00, m01, m10, m11):
    ret = F32(0.0)
    ret += m01 * (m10 * F32(-1.0))
    ret += m00 * m11
    return ret


@njit(cache=True)
def _det3(m):
    """Determinant of a (3, 3) float32 matrix by cofactors along row 0, last column first."""
    ret = F32(0.0)
    for i in range(2, -1, -1):
        c0 = 1 if i == 0 else 0
        c1 = 1 if i == 2 else 2
        minor = _det2(m[1, c0], m[1, c1], m[2, c0], m[2, c1])
        sign = F32(-1.0) if i % 2 else F32(1.0)
        ret += m[0, i] * (minor * sign)
    return ret


@njit(cache=True)
def invert_transpose(m):
    """TinyRenderer's ``invert_transpose``: the adjugate divided by its row 0's dot product with ``m``'s row 0."""
    adjugate = np.empty((4, 4), np.float32)
    minor = np.empty((3, 3), np.float32)
    for i in range(3, -1, -1):
        for j in range(3, -1, -1):
            for r in range(3):
                for c in range(3):
                    minor[r, c] = m[r if r < i else r + 1, c if c < j else c + 1]
            sign = F32(-1.0) if (i + j) % 2 else F32(1.0)
            adjugate[i, j] = _det3(minor) * sign
    determinant = dot4(adjugate[0, 0], adjugate[0, 1], adjugate[0, 2], adjugate[0, 3], m[0, 0], m[0, 1], m[0, 2], m[0, 3])
    out = np.empty((4, 4), np.float32)
    for i in range(4):
        for j in range(4):
            out[i, j] = adjugate[i, j] / determinant
    return out


@njit(cache=True, inline="always")
def transform_point(m, x, y, z, w, out, column):
    """``out[:, column] = m @ (x, y, z, w)`` summed as :func:`dot4`."""
    for i in range(4):
        out[i, column] = dot4(m[i, 0], m[i, 1], m[i, 2], m[i, 3], x, y, z, w)


@njit(cache=True, inline="always")
def transform_point3(m, x, y, z, out, column):
    """``out[:, column]`` = the first three rows of ``m @ (x, y, z, 0)`` (a direction), summed as :func:`dot4`."""
    for i in range(3):
        out[i, column] = dot4(m[i, 0], m[i, 1], m[i, 2], m[i, 3], x, y, z, F32(0.0))


@njit(cache=True)
def _barycentric(ax, ay, bx, by, cx, cy, px, py):
    """TinyRenderer's barycentric coordinates of screen point P in triangle ABC (double); (-1, 1, 1) when degenerate."""
    s0x, s0y, s0z = float(cx) - float(ax), float(bx) - float(ax), float(ax) - float(px)
    s1x, s1y, s1z = float(cy) - float(ay), float(by) - float(ay), float(ay) - float(py)
    ux = s0y * s1z - s0z * s1y
    uy = s0z * s1x - s0x * s1z
    uz = s0x * s1y - s0y * s1x
    if abs(uz) > 1e-2:
        return 1.0 - (ux + uy) / uz, uy / uz, ux / uz
    return -1.0, 1.0, 1.0


@njit(cache=True)
def _screen(viewport, clip, screen, points):
    """Screen points (3, 4) float32 of clip-space vertices (4, 3) (columns), and their projections (3, 2)."""
    for v in range(3):
        for i in range(4):
            screen[v, i] = dot4(viewport[i, 0], viewport[i, 1], viewport[i, 2], viewport[i, 3],
                                clip[0, v], clip[1, v], clip[2, v], clip[3, v])
        points[v, 0] = screen[v, 0] / screen[v, 3]
        points[v, 1] = screen[v, 1] / screen[v, 3]


@njit(cache=True)
def shade(normals, bar0, bar1, bar2, light, rgb, ambient, diffuse_coefficient, specular_coefficient, out):
    """TinyRenderer's fragment colour (uint8 per channel, into ``out``) from the vertex normals (3, 3)
    (column = vertex) at float32 barycentric ``bar``: ambient plus Lambert (plus Phong) of the material ``rgb``."""
    n0 = F32(0.0)
    n1 = F32(0.0)
    n2 = F32(0.0)
    n0 += normals[0, 2] * bar2
    n0 += normals[0, 1] * bar1
    n0 += normals[0, 0] * bar0
    n1 += normals[1, 2] * bar2
    n1 += normals[1, 1] * bar1
    n1 += normals[1, 0] * bar0
    n2 += normals[2, 2] * bar2
    n2 += normals[2, 1] * bar1
    n2 += normals[2, 0] * bar0
    scale = F32(1.0) / F32(np.sqrt(n0 * n0 + n1 * n1 + n2 * n2))
    n0, n1, n2 = n0 * scale, n1 * scale, n2 * scale
    lambert = F32(0.0)
    lambert += n2 * light[2]
    lambert += n1 * light[1]
    lambert += n0 * light[0]
    specular = F32(0.0)
    if specular_coefficient != F32(0.0):  # Phong with exponent 2, reflected about the normal
        twice = lambert * F32(2.0)
        r0, r1, r2 = n0 * twice - light[0], n1 * twice - light[1], n2 * twice - light[2]
        r_scale = F32(1.0) / F32(np.sqrt(r0 * r0 + r1 * r1 + r2 * r2))
        specular = F32(b3_max(r2 * r_scale, F32(0.0)) ** F32(2.0))
    lambert = b3_max(F32(0.0), lambert)
    for i in range(3):
        c = F32(rgb[i])
        value = ambient * c + F32(diffuse_coefficient * lambert + specular_coefficient * specular) * c
        channel = int(value) if value == value else 0
        out[i] = min(channel, 255)


@njit(cache=True, error_model="numpy", inline="always")
def raster_triangle(clip, original, clipped, viewport, zbuffer, colour, label, label_value, width, height, rows,
                    normals, light, rgb, ambient, diffuse_coefficient, specular_coefficient, near, far, scratch):
    """Draw one clip-space triangle (4, 3) into the float32 depth buffer ``zbuffer`` (h*w, larger is nearer),
    the packed colour buffer ``colour`` (h*w uint32, RGBA bytes) and ``label`` (h*w int32), rows from the bottom.

    ``clipped``: ``clip`` is a piece of the near-plane-clipped triangle ``original``, which then gives the
    shading coordinates, and no near/far test is made (TinyRenderer's ``triangleClipped``). ``rows``: the
    buffer rows ``(lo, hi)`` drawn (a band of the image; ``(0, height)`` for all). ``scratch``: a
    :func:`new_scratch`.

    TinyRenderer tests every point of the triangle's bounding box; here each row's points are first
    narrowed to the span the triangle's edges allow, widened by :data:`SPAN_MARGIN_PX` (a point outside
    it fails TinyRenderer's test by far more than its rounding), then tested exactly as TinyRenderer
    tests them.
    """
    screen, points, org_screen, org_points, rgba, row = scratch
    _screen(viewport, clip, screen, points)
    if clipped:
        _screen(viewport, original, org_screen, org_points)
    big = np.finfo(np.float32).max
    lo_x, lo_y, hi_x, hi_y = big, big, -big, -big
    clamp_x, clamp_y = F32(width - 1), F32(height - 1)
    for v in range(3):
        lo_x = b3_max(F32(0.0), b3_min(lo_x, points[v, 0]))
        lo_y = b3_max(F32(0.0), b3_min(lo_y, points[v, 1]))
        hi_x = b3_min(clamp_x, b3_max(hi_x, points[v, 0]))
        hi_y = b3_min(clamp_y, b3_max(hi_y, points[v, 1]))
    if not (lo_x <= hi_x and lo_y <= hi_y) or int(hi_y) < rows[0] or int(lo_y) >= rows[1]:
        return
    ax, ay = float(points[0, 0]), float(points[0, 1])
    s0x, s0y = float(points[2, 0]) - ax, float(points[1, 0]) - ax
    s1x, s1y = float(points[2, 1]) - ay, float(points[1, 1]) - ay
    area = s0x * s1y - s0y * s1x  # TinyRenderer's u.z, the same at every point: degenerate, nothing drawn
    if not abs(area) > 1e-2:
        return
    side = 1.0 if area > 0.0 else -1.0
    flat = not clipped and _flat_colour(normals, light, rgb, ambient, diffuse_coefficient, specular_coefficient, rgba)
    z0, z1, z2 = float(clip[2, 0]), float(clip[2, 1]), float(clip[2, 2])
    w0, w1, w2 = float(screen[0, 3]), float(screen[1, 3]), float(screen[2, 3])
    first_x, last_x = int(lo_x), int(hi_x)
    # u.x = a_x px + b_x, u.y = a_y px + b_y, u.z - u.x - u.y: each must have the sign of u.z. The slopes
    # are the same on every row; a span's ends, where an edge function is zero, come from their
    # reciprocals (some 1e-13 px from the quotients at most, far inside the margin)
    a_x, a_y = s1y, -s1x
    a_z = -(a_x + a_y)
    inverse_x = -1.0 / a_x if a_x != 0.0 else 0.0
    inverse_y = -1.0 / a_y if a_y != 0.0 else 0.0
    inverse_z = -1.0 / a_z if a_z != 0.0 else 0.0
    for py in range(max(int(lo_y), rows[0]), min(int(hi_y) + 1, rows[1])):
        dy = ay - py
        b_x = s0y * dy - ax * s1y
        b_y = ax * s1x - s0x * dy
        start, stop = float(first_x), float(last_x)
        for a, b, inverse in ((a_x, b_x, inverse_x), (a_y, b_y, inverse_y), (a_z, area - b_x - b_y, inverse_z)):
            a, b = a * side, b * side
            if a > 0.0:
                start = max(start, b * side * inverse - SPAN_MARGIN_PX)
            elif a < 0.0:
                stop = min(stop, b * side * inverse + SPAN_MARGIN_PX)
            elif b < -SPAN_MARGIN_PX:
                stop = -1.0
        if not start <= stop:
            continue
        x0, x1 = int(math.ceil(start)), int(math.floor(stop))
        _row_coordinates(x0, x1, py, ax, ay, s0x, s0y, s1x, s1y, area, w0, w1, w2, z0, z1, z2, row)
        for j in range(x1 - x0 + 1):
            px = x0 + j
            depth = row[6, j]
            index = px + py * width
            if row[0, j] < 0 or row[1, j] < 0 or row[2, j] < 0 or float(zbuffer[index]) > depth:
                continue
            c0, c1, c2 = row[3, j], row[4, j], row[5, j]
            if clipped:
                o0, o1, o2 = _barycentric(org_points[0, 0], org_points[0, 1], org_points[1, 0], org_points[1, 1],
                                          org_points[2, 0], org_points[2, 1], F32(px), F32(py))
                c0, c1, c2 = o0 / float(org_screen[0, 3]), o1 / float(org_screen[1, 3]), o2 / float(org_screen[2, 3])
                total = c0 + c1 + c2
                c0, c1, c2 = c0 / total, c1 / total, c2 / total
            elif depth < -float(far) or depth > float(near):
                continue
            if not flat:
                shade(normals, F32(c0), F32(c1), F32(c2), light, rgb, ambient, diffuse_coefficient,
                      specular_coefficient, rgba)
            zbuffer[index] = F32(depth)
            colour[index] = np.uint32(rgba[0]) | (np.uint32(rgba[1]) << 8) | (np.uint32(rgba[2]) << 16) | np.uint32(0xFF000000)
            label[index] = label_value


@njit(cache=True, error_model="numpy")
def _flat_colour(normals, light, rgb, ambient, diffuse_coefficient, specular_coefficient, out):
    """Whether every fragment of a face whose three vertex normals are equal gets one colour, which is then
    in ``out``.

    :func:`shade` normalises the same direction at every fragment, so its Lambert term varies only in
    its last bits (about 1e-6), and a channel's value by some 1e-4: where every channel lies farther
    than :data:`FLAT_MARGIN` from a whole number, truncation gives every fragment the colour computed
    here once, in float64. Elsewhere (or with a specular term) each fragment is shaded."""
    if specular_coefficient != F32(0.0):
        return False
    for i in range(3):
        if normals[i, 0] != normals[i, 1] or normals[i, 0] != normals[i, 2]:
            return False
    n0, n1, n2 = float(normals[0, 0]), float(normals[1, 0]), float(normals[2, 0])
    length = math.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
    lambert = max(0.0, (n0 * float(light[0]) + n1 * float(light[1]) + n2 * float(light[2])) / length)
    for i in range(3):
        c = float(rgb[i])
        value = float(ambient) * c + float(diffuse_coefficient) * lambert * c
        whole = math.floor(value)
        if not (value - whole > FLAT_MARGIN and whole + 1.0 - value > FLAT_MARGIN):
            return False
        out[i] = min(int(whole), 255)
    return True


@njit(cache=True, error_model="numpy", inline="always")
def _row_coordinates(x0, x1, py, ax, ay, s0x, s0y, s1x, s1y, area, w0, w1, w2, z0, z1, z2, row):
    """TinyRenderer's coordinates of the points ``x0..x1`` of screen row ``py``, as :func:`_barycentric` and
    its caller compute them, into ``row`` (7, w): screen barycentrics (3), perspective-correct ones (3) and
    the fragment depth. No branches: the compiler can vectorise it."""
    dy = ay - float(F32(py))
    for j in range(x1 - x0 + 1):
        dx = ax - float(F32(x0 + j))
        ux = s0y * dy - dx * s1y
        uy = dx * s1x - s0x * dy
        b0, b1, b2 = 1.0 - (ux + uy) / area, uy / area, ux / area
        c0, c1, c2 = b0 / w0, b1 / w1, b2 / w2
        total = c0 + c1 + c2
        c0, c1, c2 = c0 / total, c1 / total, c2 / total
        depth = 0.0
        depth += z2 * c2
        depth += z1 * c1
        depth += z0 * c0
        row[0, j], row[1, j], row[2, j] = b0, b1, b2
        row[3, j], row[4, j], row[5, j] = c0, c1, c2
        row[6, j] = -1.0 * depth


@njit(cache=True)
def new_scratch(width):
    """Work arrays of :func:`raster_triangle` for images ``width`` pixels wide: screen points and projections
    of a triangle and of the triangle it was clipped from, a fragment's colour, a row's coordinates."""
    return (np.empty((3, 4), np.float32), np.empty((3, 2), np.float32), np.empty((3, 4), np.float32),
            np.empty((3, 2), np.float32), np.empty(3, np.uint8), np.empty((7, width), np.float64))


@njit(cache=True)
def _clip_edge(tri, a, b, out, count):
    """TinyRenderer's ``clipEdge``: append edge a->b of ``tri`` (4, 3), cut at the near plane, to ``out``."""
    a_inside = tri[3, a] > F32(0.0) and tri[2, a] > -tri[3, a]
    b_inside = tri[3, b] > F32(0.0) and tri[2, b] > -tri[3, b]
    va = tri[:, a].copy()
    vb = tri[:, b].copy()
    if a_inside and b_inside:
        pass
    elif a_inside or b_inside:
        d0 = va[2] + va[3]
        d1 = vb[2] + vb[3]
        factor = F32(1.0 / (d1 - d0))
        new = (va * d1 - vb * d0) * factor
        if a_inside:
            vb = new
        else:
            va = new
    else:
        return count
    out[:, count] = va
    out[:, count + 1] = vb
    return count + 2


@njit(cache=True, inline="always")
def draw_triangle(tri, viewport, zbuffer, colour, label, label_value, width, height, rows, normals, light, rgb,
                  ambient, diffuse_coefficient, specular_coefficient, near, far, scratch):
    """Clip a triangle (4, 3) against the near plane as TinyRenderer does, then draw what is left."""
    if tri[3, 0] < 0 and tri[3, 1] < 0 and tri[3, 2] < 0:
        return
    if tri[3, 0] >= 0 and tri[3, 1] >= 0 and tri[3, 2] >= 0:
        raster_triangle(tri, tri, False, viewport, zbuffer, colour, label, label_value, width, height, rows, normals,
                        light, rgb, ambient, diffuse_coefficient, specular_coefficient, near, far, scratch)
        return
    polygon = np.empty((4, 6), np.float32)
    count = _clip_edge(tri, 0, 1, polygon, 0)
    count = _clip_edge(tri, 1, 2, polygon, count)
    count = _clip_edge(tri, 2, 0, polygon, count)
    if count < 3:
        return
    piece = np.empty((4, 3), np.float32)
    for i in range(1, count - 1):
        piece[:, 0] = polygon[:, 0]
        piece[:, 1] = polygon[:, i]
        piece[:, 2] = polygon[:, i + 1]
        raster_triangle(piece, tri, True, viewport, zbuffer, colour, label, label_value, width, height, rows, normals,
                        light, rgb, ambient, diffuse_coefficient, specular_coefficient, near, far, scratch)
