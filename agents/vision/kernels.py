"""The vision's loops over pixels and runs in compiled code (numba): the segmentation of a frame, the
white runs of its scan columns and the chains of criterion 4, line formation, the goal colours'
masks and their post candidates, and where pixels' rays meet the ground.

They compute exactly what the array formulations and Python loops they replace computed (tests
compare them with those, kept as references); ``python -m agents.compile`` (run by ``make install``) puts
their machine code in numba's cache, so no controller process compiles them.
"""

from __future__ import annotations

import numba
import numpy as np

from agents.vision.colors import ColorClass

WHITE, GREEN, ORANGE = int(ColorClass.WHITE), int(ColorClass.GREEN), int(ColorClass.ORANGE)
LEVEL_SHIFT = 2  # 256 levels -> 64 per channel in the colour table


@numba.njit(cache=True, nogil=True)
def classify_pixels(image: np.ndarray, table: np.ndarray) -> np.ndarray:
    """Raw class labels (H, W) uint8 of an RGB uint8 image (H, W, 3) through the lookup table over
    quantized RGB (``(r >> 2) << 12 | (g >> 2) << 6 | (b >> 2)``)."""
    h, w = image.shape[0], image.shape[1]
    labels = np.empty((h, w), np.uint8)
    for r in range(h):
        for c in range(w):
            index = ((image[r, c, 0] >> LEVEL_SHIFT) << 12) | ((image[r, c, 1] >> LEVEL_SHIFT) << 6) | (
                image[r, c, 2] >> LEVEL_SHIFT)
            labels[r, c] = table[index]
    return labels


@numba.njit(cache=True, nogil=True)
def clean_isolated(labels: np.ndarray) -> np.ndarray:
    """The thesis' neighbour check (section 4.1) on a copy of ``labels`` (H, W) uint8: a non-white pixel
    with no 8-neighbour of its own class becomes white; a white one with no white 8-neighbour becomes
    orange when at least 4 of its neighbours are orange, green otherwise. Outside the image counts as
    no class."""
    h, w = labels.shape
    out = labels.copy()
    for r in range(h):
        for c in range(w):
            own = labels[r, c]
            if c > 0 and labels[r, c - 1] == own:
                continue
            if c < w - 1 and labels[r, c + 1] == own:
                continue
            isolated = True
            orange = 0
            for dr in range(-1, 2):
                rr = r + dr
                if rr < 0 or rr >= h:
                    continue
                for dc in range(-1, 2):
                    cc = c + dc
                    if (dr == 0 and dc == 0) or cc < 0 or cc >= w:
                        continue
                    neighbour = labels[rr, cc]
                    if neighbour == own:
                        isolated = False
                    elif neighbour == ORANGE:
                        orange += 1
            if not isolated:
                continue
            if own != WHITE:
                out[r, c] = WHITE
            elif orange >= 4:
                out[r, c] = ORANGE
            else:
                out[r, c] = GREEN
    return out


@numba.njit(cache=True, nogil=True)
def white_runs(labels: np.ndarray, columns: np.ndarray, start: np.ndarray, forbidden_beside: np.ndarray,
               white: int, green: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The runs of ``white`` pixels of each scan column ``columns[k]`` (K,) from row ``start[k]`` down, as
    (scan column index, top row, bottom row, criterion) arrays in column then row order, with the first
    two criteria of thesis 4.5.1 applied (criterion 0: passed, 1: an end not against ``green`` inside
    the scan, 2: a forbidden class (``forbidden_beside`` over labels 0-255) beside an interior pixel in
    a neighbouring column inside the image)."""
    height, width = labels.shape
    capacity = len(columns) * (height // 2 + 1)
    scan_index = np.empty(capacity, np.int64)
    tops = np.empty(capacity, np.int64)
    bottoms = np.empty(capacity, np.int64)
    criteria = np.zeros(capacity, np.int64)
    n = 0
    for k in range(len(columns)):
        column = columns[k]
        row = start[k]
        while row < height:
            if labels[row, column] != white:
                row += 1
                continue
            top = row
            while row + 1 < height and labels[row + 1, column] == white:
                row += 1
            bottom = row
            row += 1
            scan_index[n], tops[n], bottoms[n] = k, top, bottom
            above_ok = top > start[k] and labels[top - 1, column] == green
            below_ok = bottom < height - 1 and labels[bottom + 1, column] == green
            if not (above_ok and below_ok):
                criteria[n] = 1
            else:
                for interior in range(top + 1, bottom):
                    if ((column > 0 and forbidden_beside[labels[interior, column - 1]])
                            or (column < width - 1 and forbidden_beside[labels[interior, column + 1]])):
                        criteria[n] = 2
                        break
            n += 1
    return scan_index[:n], tops[:n], bottoms[:n], criteria[:n]


@numba.njit(cache=True, nogil=True)
def goal_mask(labels: np.ndarray, image: np.ndarray, goal: int, white: int, low: np.ndarray, high: np.ndarray,
              reach: int, rims: bool) -> np.ndarray:
    """The post search's mask (H, W) bool of one goal colour: the pixels labelled ``goal`` and, with
    ``rims``, within ``reach`` columns of their extent (and within its rows), the pixels labelled
    ``white`` whose RGB (``image`` (H, W, 3) uint8) lies in [``low``, ``high``] on every channel
    (:meth:`agents.vision.goals.GoalRims.goal_pixels`)."""
    height, width = labels.shape
    mask = np.zeros((height, width), np.bool_)
    top, bottom, left, right = height, -1, width, -1
    for r in range(height):
        for c in range(width):
            if labels[r, c] == goal:
                mask[r, c] = True
                top, bottom = min(top, r), max(bottom, r)
                left, right = min(left, c), max(right, c)
    if bottom < 0 or not rims:
        return mask
    for r in range(top, bottom + 1):
        for c in range(max(0, left - reach), min(width - 1, right + reach) + 1):
            if labels[r, c] == white:
                inside = True
                for k in range(3):
                    inside = inside and low[k] <= image[r, c, k] <= high[k]
                mask[r, c] = mask[r, c] or inside
    return mask


@numba.njit(cache=True, nogil=True)
def post_candidates(labels: np.ndarray, mask: np.ndarray, goal: int, min_run: int, run_fraction: float, gap: int,
                    min_seeds: int, base_rows: int, core_fraction: float) -> np.ndarray:
    """The post candidates of a goal's ``mask`` (H, W) bool, left to right, as rows (k, 9) int64: first and
    last column, top and bottom row, the sum and count of the base pixels' columns, the core width, the
    base's first and last column (see :func:`agents.vision.goals.find_posts`).

    A column is a post's when its longest vertical run of mask pixels is at least ``min_run`` and
    ``run_fraction`` of the longest of all; post columns ``gap`` or more apart are separate posts; a post
    holds at least ``min_seeds`` pixels labelled ``goal``; its base is its mask pixels in its lowest
    ``base_rows`` rows; its core, the columns whose run is at least ``core_fraction`` of its longest."""
    height, width = mask.shape
    top, box_bottom, left, right = height, -1, width, -1
    for r in range(height):
        for c in range(width):
            if mask[r, c]:
                top, box_bottom = min(top, r), max(box_bottom, r)
                left, right = min(left, c), max(right, c)
    posts = np.empty((0, 9), np.int64)
    if box_bottom < 0:
        return posts
    columns = right - left + 1
    length = np.zeros(columns, np.int64)
    bottom = np.zeros(columns, np.int64)  # the row where each column's longest run ends (its first, on ties)
    longest = 0
    for j in range(columns):
        run, best, best_row = 0, 0, 0
        for i in range(box_bottom - top + 1):
            run = run + 1 if mask[top + i, left + j] else 0
            if run > best:
                best, best_row = run, i
        length[j], bottom[j] = best, best_row + top
        longest = max(longest, best)
    threshold = max(float(min_run), run_fraction * longest)
    post_columns = np.flatnonzero(length >= threshold)
    rows = []
    start = 0
    for k in range(1, post_columns.shape[0] + 1):
        if k < post_columns.shape[0] and post_columns[k] - post_columns[k - 1] < gap:
            continue
        group = post_columns[start:k]
        start = k
        first, last = group[0] + left, group[-1] + left
        post_top, lowest, group_longest = height, -1, 0
        for j in group:
            post_top = min(post_top, bottom[j] - length[j] + 1)
            lowest = max(lowest, bottom[j])
            group_longest = max(group_longest, length[j])
        seeds = 0
        for r in range(post_top, lowest + 1):
            for c in range(first, last + 1):
                seeds += labels[r, c] == goal
        if seeds < min_seeds:
            continue  # edge-coloured pixels only: no post of this colour
        base_sum, base_count, base_first, base_last = 0, 0, width, -1
        for r in range(max(0, lowest - base_rows + 1), lowest + 1):
            for c in range(first, last + 1):
                if mask[r, c]:
                    base_sum, base_count = base_sum + c, base_count + 1
                    base_first, base_last = min(base_first, c), max(base_last, c)
        core = 0
        for j in group:
            core += length[j] >= core_fraction * group_longest
        rows.append((first, last, post_top, lowest, base_sum, base_count, core, base_first, base_last))
    if rows:
        posts = np.empty((len(rows), 9), np.int64)
        for k in range(len(rows)):
            for m in range(9):
                posts[k, m] = rows[k][m]
    return posts


@numba.njit(cache=True, nogil=True)
def formed_lines(column: np.ndarray, middle: np.ndarray, length: np.ndarray, dist: int, max_gap_dists: int,
                 min_black_lines: int, deviation_ratio: float, deviation_min_px: int, deadband_px: float
                 ) -> tuple[np.ndarray, np.ndarray]:
    """GetStart and GetLine (thesis 4.5.2) over the kept black lines (``column`` int, ``middle`` float,
    ``length`` int, sorted by column then row): the lines as the indices of their black lines, all in one
    array, and where each line starts in it (see :mod:`agents.vision.lines.formation`)."""
    count = column.shape[0]
    flag = np.zeros(count, np.bool_)
    members = np.empty(count, np.int64)
    starts = np.empty(count + 1, np.int64)
    lines, used, begin = 0, 0, 0
    limit_w = max_gap_dists * dist
    while True:
        start = -1
        for i in range(begin, count):  # GetStart
            if not flag[i]:
                start = i
                break
        if start < 0:
            break
        begin = start
        first = used
        members[used] = start
        used += 1
        flag[start] = True
        current, direction = start, 0
        for following in range(start + 1, count):  # GetLine
            if column[following] - column[current] >= limit_w:  # criterion 3
                break
            if flag[following] or column[following] == column[current]:  # criteria 1 and 2
                continue
            d2 = middle[following] - middle[current]
            len1, len2 = length[current], length[following]
            limit = (len1 + len2) / 2.0 + (column[following] - column[current]) / dist - 1.0  # AddLimit
            short, long_ = (len1, len2) if len1 <= len2 else (len2, len1)
            if abs(d2) > limit or (long_ > deviation_ratio * short and long_ - short >= deviation_min_px):
                continue  # criterion 4
            step = 0 if abs(d2) <= deadband_px else (1 if d2 > 0 else -1)
            if direction * step < 0:
                continue  # criterion 5: the direction changes sign
            members[used] = following
            used += 1
            flag[following] = True
            current, direction = following, step
        if used - first >= min_black_lines:
            starts[lines] = first
            lines += 1
        else:
            used = first  # too short: dropped, its black lines stay used
    starts[lines] = used
    return members[:used], starts[:lines + 1]


@numba.njit(cache=True, nogil=True)
def chained_runs(scan_index: np.ndarray, top: np.ndarray, bottom: np.ndarray, close_gap: int, smaller_ratio: float,
                 smaller_min_diff: int) -> np.ndarray:
    """Criterion 4 of thesis 4.5.1 on black lines (scan column index, top and bottom row; sorted by scan
    column): which are part of a chain of three close black lines in consecutive scan columns, and not
    much shorter than a close one in the next column (see :func:`agents.vision.lines.scan_lines.continuity`).
    Two black lines are close when the second is in the next scan column and their rows overlap or lie
    within ``close_gap`` + 1 rows."""
    count = scan_index.shape[0]
    has_left = np.zeros(count, np.bool_)
    has_right = np.zeros(count, np.bool_)
    following = np.empty(count, np.int64)  # the first black line of the next scan column (count: none)
    j = 0
    for i in range(count):
        while j < count and scan_index[j] <= scan_index[i]:
            j += 1
        following[i] = j
    for i in range(count):
        j = following[i]
        while j < count and scan_index[j] == scan_index[i] + 1:
            if max(top[i], top[j]) <= min(bottom[i], bottom[j]) + 1 + close_gap:
                has_right[i] = True
                has_left[j] = True
            j += 1
    ok = np.zeros(count, np.bool_)
    ends_chain = np.zeros(count, np.bool_)
    shorter = np.zeros(count, np.bool_)
    for i in range(count):
        j = following[i]
        length_i = bottom[i] - top[i] + 1
        while j < count and scan_index[j] == scan_index[i] + 1:
            if max(top[i], top[j]) <= min(bottom[i], bottom[j]) + 1 + close_gap:
                ok[i] = ok[i] or has_right[j]  # i -> j -> k
                ends_chain[j] = ends_chain[j] or has_left[i]  # k -> i -> j
                length_j = bottom[j] - top[j] + 1
                much_longer = length_j * smaller_ratio > length_i and length_j - length_i >= smaller_min_diff
                shorter[i] = shorter[i] or much_longer
            j += 1
    for i in range(count):
        ok[i] = (ok[i] or (has_left[i] and has_right[i]) or ends_chain[i]) and not shorter[i]
    return ok


@numba.njit(cache=True, nogil=True)
def ground_points(u: np.ndarray, v: np.ndarray, rotation: np.ndarray, position: np.ndarray, cx: float, cy: float,
                  focal_px: float) -> tuple[np.ndarray, np.ndarray]:
    """Bearings (rad) and distances (m) in a frame on the ground of where the rays through pixels (``u``,
    ``v``) (1-D) meet the ground: the camera at ``position`` (m) turned by ``rotation`` (3x3, camera ->
    that frame), principal point (``cx``, ``cy``) px, focal length ``focal_px``; NaN for a ray that does
    not point down. The operations of :meth:`world.camera_model.CameraIntrinsics.rotated_pixel_rays` and
    :meth:`agents.vision.camera_models.ExactCameraModel.locate`, element by element."""
    n = u.shape[0]
    bearing, distance = np.empty(n), np.empty(n)
    r00, r01, r02 = rotation[0, 0], rotation[0, 1], rotation[0, 2]
    r10, r11, r12 = rotation[1, 0], rotation[1, 1], rotation[1, 2]
    r20, r21, r22 = rotation[2, 0], rotation[2, 1], rotation[2, 2]
    px, py, pz = position[0], position[1], position[2]
    for i in range(n):
        x = (u[i] + 0.5 - cx) / focal_px
        y = (v[i] + 0.5 - cy) / focal_px
        norm = np.sqrt(x * x + y * y + 1.0)
        ray_x = (r00 * x + r01 * y + r02) / norm
        ray_y = (r10 * x + r11 * y + r12) / norm
        ray_z = (r20 * x + r21 * y + r22) / norm
        t = -pz / ray_z if ray_z < -1e-9 else np.nan
        gx = px + t * ray_x
        gy = py + t * ray_y
        bearing[i] = np.arctan2(gy, gx)
        distance[i] = np.hypot(gx, gy)
    return bearing, distance
