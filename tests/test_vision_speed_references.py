"""The fast vision primitives against plain reference implementations kept here.

Each reference is the straightforward (or the previous, whole-image) way to compute the same
thing: pixel loops, 8-neighbour counts, labelling the whole image, ``numpy.linalg.lstsq``,
:meth:`world.camera_model.CameraIntrinsics.pixel_ray`. Inputs are seeded random images,
runs and pixels, so that every branch is met many times.
"""

from __future__ import annotations

import math

import cv2
import numpy as np
import pytest

from agents.vision.ball import _largest_blob, ground_point
from agents.vision.border import FieldBorder, border_line_from_left
from agents.vision.camera_models import ExactCameraModel
from agents.vision.colors import ColorClass
from agents.vision.frame import CameraFrame
from agents.vision.goals import RIM_REACH_PX, GoalRims, find_posts
from agents.vision.lines.classification import fit_polynomial
from agents.vision.lines.formation import (
    DIRECTION_DEADBAND_PX,
    LENGTH_DEVIATION_MIN_PX,
    LENGTH_DEVIATION_RATIO,
    MAX_GAP_DISTS,
    MIN_BLACK_LINES,
    add_limit,
    form_lines,
)
from agents.vision.lines.scan_lines import DIST, NEIGHBOURS_ALLOWED, NEIGHBOURS_THESIS, continuity, scan_black_lines
from agents.vision.kernels import LEVEL_SHIFT
from agents.vision.segmentation import ColorTable, clean_outliers, load_thresholds
from world.camera_model import NAO_CAMERA, NAO_HEAD, CameraPosition
from world.field import GoalColor

GREEN, WHITE, ORANGE = int(ColorClass.GREEN), int(ColorClass.WHITE), int(ColorClass.ORANGE)
NEIGHBOURS = [(dr, dc) for dr in (-1, 0, 1) for dc in (-1, 0, 1) if (dr, dc) != (0, 0)]


def random_labels(rng: np.random.Generator, shape: tuple[int, int] = (120, 160)) -> np.ndarray:
    """Green with white lines of 1-4 px, and specks and patches of every class."""
    labels = np.full(shape, GREEN, np.uint8)
    h, w = shape
    for _ in range(rng.integers(0, 8)):
        ends = [(int(rng.integers(-20, w + 20)), int(rng.integers(0, h))) for _ in range(2)]
        cv2.line(labels, ends[0], ends[1], WHITE, int(rng.integers(1, 5)))
    for _ in range(rng.integers(0, 6)):
        top, left = int(rng.integers(0, h)), int(rng.integers(0, w))
        labels[top : top + rng.integers(1, 30), left : left + rng.integers(1, 8)] = rng.integers(0, 7)
    specks = rng.random(shape) < 0.01
    labels[specks] = rng.integers(0, 7, int(specks.sum()))
    return labels


def test_fit_polynomial_agrees_with_lstsq_and_is_exact_on_exact_data():
    rng = np.random.default_rng(0)
    for _ in range(300):
        w = np.sort(rng.choice(np.arange(0, 160, 5), size=int(rng.integers(3, 32)), replace=False)).astype(float)
        h = rng.integers(0, 240, len(w)) / 2.0  # midpoints of runs: half pixels
        x = w - w.mean()
        for degree in (1, 2):
            reference = np.linalg.lstsq(np.vander(x, degree + 1), h, rcond=None)[0]
            assert np.polyval(fit_polynomial(w, h, degree), w) == pytest.approx(np.polyval(reference, x), abs=1e-8)
    # Midpoints of a rendered line whose least-squares slope is -7/100, Table 4.3's side-line threshold: the old
    # lstsq fit gave -0.07000000000000034 (a side line), the closed form gives the double nearest -0.07 (straight).
    assert fit_polynomial([30.0, 35.0, 40.0, 45.0], [35.0, 36.0, 35.5, 34.0], degree=1)[0] == -0.07
    with pytest.raises(ValueError):
        fit_polynomial([5.0, 5.0, 10.0, 10.0], [1.0, 2.0, 3.0, 4.0])


def reference_continuity(scan_index: np.ndarray, top: np.ndarray, bottom: np.ndarray) -> np.ndarray:
    """Criterion 4 of thesis 4.5.1 pair by pair (scan_lines' constants: touching rows, a third, 3 px)."""
    n = len(scan_index)

    def close(i: int, j: int) -> bool:
        return scan_index[j] == scan_index[i] + 1 and max(top[i], top[j]) <= min(bottom[i], bottom[j]) + 1

    length = bottom - top + 1
    ok = np.zeros(n, bool)
    for i in range(n):
        right = [j for j in range(n) if close(i, j)]
        left = [k for k in range(n) if close(k, i)]
        starts = any(close(j, k) for j in right for k in range(n))  # i -> j -> k
        ends = any(close(m, k) for k in left for m in range(n))  # m -> k -> i
        chained = starts or ends or (left and right)
        shorter = any(length[j] / 3.0 > length[i] and length[j] - length[i] >= 3 for j in right)
        ok[i] = chained and not shorter
    return ok


def test_continuity_agrees_with_the_pairwise_reference():
    rng = np.random.default_rng(1)
    for _ in range(400):
        scan_index, top, bottom = [], [], []
        for column in range(int(rng.integers(1, 10))):
            row = int(rng.integers(0, 8))
            for _ in range(int(rng.integers(0, 4))):
                row += int(rng.integers(0, 4))
                scan_index.append(column)
                top.append(row)
                row += int(rng.integers(0, 9))
                bottom.append(row)
                row += 2
        runs = np.array(scan_index, int), np.array(top, int), np.array(bottom, int)
        assert np.array_equal(continuity(*runs), reference_continuity(*runs))


def reference_clean_outliers(labels: np.ndarray) -> np.ndarray:
    """Thesis 4.1's neighbour check by counting each pixel's 8 neighbours of its own class and orange."""
    padded = np.pad(labels, 1, constant_values=255)
    h, w = labels.shape
    same = sum((padded[1 + dr : 1 + dr + h, 1 + dc : 1 + dc + w] == labels).astype(int) for dr, dc in NEIGHBOURS)
    orange = sum((padded[1 + dr : 1 + dr + h, 1 + dc : 1 + dc + w] == ORANGE).astype(int) for dr, dc in NEIGHBOURS)
    out = labels.copy()
    out[(same == 0) & (labels != WHITE)] = WHITE
    lone_white = (same == 0) & (labels == WHITE)
    out[lone_white] = np.where(orange[lone_white] >= 4, ORANGE, GREEN)
    return out


def test_clean_outliers_agrees_with_counting_every_pixels_neighbours():
    rng = np.random.default_rng(2)
    images = [random_labels(rng) for _ in range(30)]
    images += [rng.choice([WHITE, ORANGE, GREEN], size=(7, 9), p=[0.2, 0.6, 0.2]).astype(np.uint8) for _ in range(300)]
    images += [rng.integers(0, 7, (9, 7)).astype(np.uint8) for _ in range(300)]
    for labels in images:
        assert np.array_equal(clean_outliers(labels), reference_clean_outliers(labels))


def reference_border_line(heights: np.ndarray, start: int) -> tuple[bool, np.ndarray]:
    """Algorithm 1 of thesis 4.3 on a numpy array, element by element."""
    border = heights.copy()
    left, right, counter = start, start + 1, 0
    while right < len(border) - 1:
        if border[left] == -1:
            left += 1
            continue
        if heights[right] != -1 and abs(int(heights[left]) - int(heights[right])) < 3:
            left += 1
        else:
            border[right] = -1
            counter += 1
        right += 1
        if counter > 0.75 * len(border):
            return False, border
    border[:start] = -1
    border[right:] = -1
    return True, border


def test_border_line_agrees_with_the_array_reference():
    rng = np.random.default_rng(3)
    for _ in range(2000):
        size = int(rng.integers(3, 60))
        heights = np.cumsum(rng.integers(-3, 4, size)) + 60 if rng.random() < 0.5 else rng.integers(-1, 120, size)
        start = int(rng.integers(0, size))
        found, line = border_line_from_left(heights, start)
        expected_found, expected = reference_border_line(heights, start)
        assert found == expected_found and line.dtype == expected.dtype and np.array_equal(line, expected)


def random_frame(rng: np.random.Generator) -> CameraFrame:
    tilt = float(rng.uniform(0.0, 0.5))
    accelerometer = (9.81 * math.sin(tilt), -0.5, 9.81 * math.cos(tilt)) if rng.random() < 0.5 else None
    camera = CameraPosition.TOP if rng.random() < 0.5 else CameraPosition.BOTTOM
    yaw, pitch = float(rng.uniform(-2.0, 2.0)), float(rng.uniform(-0.6, 0.5))
    return CameraFrame(np.zeros((120, 160, 3), np.uint8), yaw, pitch, camera, accelerometer)


def test_locate_and_ground_point_agree_with_pixel_rays():
    rng = np.random.default_rng(4)
    model = ExactCameraModel()
    for _ in range(60):
        frame = random_frame(rng)
        u, v = rng.uniform(-0.5, 159.5, 50), rng.uniform(-0.5, 119.5, 50)
        rotation, position = model.camera_pose(frame)
        rays = NAO_CAMERA.pixel_ray(u, v) @ rotation.T
        assert np.column_stack(NAO_CAMERA.rotated_pixel_rays(u, v, rotation)) == pytest.approx(rays, abs=1e-15)
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.where(rays[:, 2] < -1e-9, -position[2] / rays[:, 2], np.nan)
        gx, gy = position[0] + t * rays[:, 0], position[1] + t * rays[:, 1]
        ground = model.locate(frame, u, v)
        assert np.array_equal(ground.valid, np.isfinite(t))
        assert ground.distance_m[ground.valid] == pytest.approx(np.hypot(gx, gy)[ground.valid], rel=1e-9)
        assert ground.bearing_rad[ground.valid] == pytest.approx(np.arctan2(gy, gx)[ground.valid], rel=1e-9, abs=1e-12)
        # The ball and robots: the untilted camera, rays met with a plane 0.27 m up, 9 m at most.
        rotation, position = NAO_HEAD.camera_in_torso(frame.head_yaw_rad, frame.head_pitch_rad, frame.camera)
        ray = rotation @ NAO_CAMERA.pixel_ray(u[0], v[0])
        expected = (math.atan2(ray[1], ray[0]), 9.0)
        if ray[2] < -1e-9:
            x, y = position[:2] + (position[2] - 0.27) / -ray[2] * ray[:2]
            if math.hypot(x, y) <= 9.0:
                expected = (math.atan2(y, x), math.hypot(x, y))
        point = ground_point(u[0], v[0], frame.head_yaw_rad, frame.head_pitch_rad, frame.camera, 0.27)
        assert point == pytest.approx(expected, rel=1e-9, abs=1e-12)


def test_locate_is_the_numpy_formulation_to_the_bit():
    """The compiled ground points are what the array code they replaced computed: the rays of
    ``rotated_pixel_rays``, met with the ground, their bearings and distances (NaN above the horizon)."""
    rng = np.random.default_rng(5)
    model = ExactCameraModel()
    for trial in range(200):
        frame = random_frame(rng)
        shape = (40,) if trial % 2 else (5, 8)
        u, v = rng.uniform(-0.5, 159.5, shape), rng.uniform(-0.5, 119.5, shape)
        if trial % 3 == 0:
            u, v = np.round(u), np.round(v)
        rotation, position = model.camera_pose(frame)
        ray_x, ray_y, ray_z = NAO_CAMERA.rotated_pixel_rays(u, v, rotation)
        px, py, pz = position.tolist()
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.where(ray_z < -1e-9, -pz / ray_z, np.nan)
        gx, gy = px + t * ray_x, py + t * ray_y
        ground = model.locate(frame, u, v)
        assert ground.bearing_rad.tobytes() == np.arctan2(gy, gx).tobytes()
        assert ground.distance_m.tobytes() == np.hypot(gx, gy).tobytes()
    scalar, array = model.locate(frame, 80.0, 100.0), model.locate(frame, np.array([80.0]), np.array([100.0]))
    assert scalar.distance_m.shape == () and scalar.distance_m.tobytes() == array.distance_m.tobytes()


def reference_largest_blob(mask: np.ndarray) -> tuple[float, float, int] | None:
    """The ball's largest 8-connected blob, labelling the whole image (its centroid, without the cut-circle fit)."""
    count, _, stats, centroids = cv2.connectedComponentsWithStats(mask.astype(np.uint8), connectivity=8)
    if count <= 1 or np.count_nonzero(mask) < 3:
        return None
    best = int(np.argmax(stats[1:, cv2.CC_STAT_AREA])) + 1
    size = int(stats[best, cv2.CC_STAT_AREA])
    return (float(centroids[best, 0]), float(centroids[best, 1]), size) if size >= 3 else None


def test_the_ball_blob_is_the_one_of_the_whole_image_even_among_equal_blobs():
    rng = np.random.default_rng(5)
    for _ in range(300):
        mask = np.zeros((120, 160), bool)
        side = int(rng.integers(1, 5))
        for _ in range(int(rng.integers(1, 9))):  # equal squares: ties broken by the labels' order
            top, left = int(rng.integers(1, 118 - side)), int(rng.integers(1, 158 - side))
            mask[top : top + side, left : left + side] = True
        mask |= rng.random(mask.shape) < 0.002 * rng.integers(0, 2)
        mask[[0, -1]] = mask[:, [0, -1]] = False  # nothing touches the image border: no cut-circle fit
        blob, expected = _largest_blob(mask), reference_largest_blob(mask)
        assert (blob is None) == (expected is None)
        if blob is not None:
            assert blob[2] == expected[2] and blob[:2] == pytest.approx(expected[:2], abs=1e-12)


def longest_vertical_runs(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Length and bottom row of the longest vertical run of True in each column of ``mask``."""
    ones = mask.astype(np.int32)
    total = np.cumsum(ones, axis=0)
    at_gaps = np.maximum.accumulate(np.where(ones == 0, total, 0), axis=0)
    run = total - at_gaps  # length of the run ending at each pixel
    return run.max(axis=0), run.argmax(axis=0)


def reference_posts(labels: np.ndarray, goal: GoalColor, mask: np.ndarray | None = None) -> list[tuple]:
    """Post candidates from the runs of the whole image (goals' constants: run 5 px and 30 %, gap 2, 3 base rows,
    3 pixels of the goal class) of ``mask`` (default: the goal class's pixels)."""
    seeds = labels == (int(ColorClass.BLUE) if goal is GoalColor.BLUE else int(ColorClass.YELLOW))
    mask = seeds if mask is None else mask
    if not mask.any():
        return []
    length, bottom = longest_vertical_runs(mask)
    columns = np.flatnonzero(length >= max(5, 0.3 * length.max()))
    posts = []
    for group in np.split(columns, np.flatnonzero(np.diff(columns) >= 2) + 1) if columns.size else []:
        lowest = int(bottom[group].max())
        base = np.nonzero(mask[max(0, lowest - 2) : lowest + 1, group[0] : group[-1] + 1])[1] + group[0]
        core = int(np.count_nonzero(length[group] >= 0.5 * length[group].max()))
        top = int((bottom[group] - length[group] + 1).min())
        if np.count_nonzero(seeds[top : lowest + 1, group[0] : group[-1] + 1]) < 3:
            continue
        base_columns = (float(base.mean()), core, int(base.min()), int(base.max()))
        posts.append((int(group[0]), int(group[-1]), top, lowest, *base_columns))
    return posts


def test_posts_found_in_the_box_of_the_goal_pixels_are_those_of_the_whole_image():
    rng = np.random.default_rng(6)
    for _ in range(100):
        labels = random_labels(rng)
        for goal in GoalColor:
            found = [
                (p.first_column, p.last_column, p.top_row, p.bottom_row, p.base_u, p.core_width_px, p.base_first_column,
                 p.base_last_column)
                for p in find_posts(labels, goal)
            ]
            assert found == reference_posts(labels, goal)


def reference_goal_pixels(labels: np.ndarray, image: np.ndarray, goal_class: int, low: np.ndarray, high: np.ndarray,
                          reach: int) -> np.ndarray:
    """The rims' mask with numpy: the goal class's pixels and, within ``reach`` columns of their extent, the
    white pixels whose colour lies in [low, high]."""
    mask = labels == goal_class
    if not mask.any():
        return mask
    rows, columns = np.flatnonzero(mask.any(axis=1)), np.flatnonzero(mask.any(axis=0))
    top, bottom = int(rows[0]), int(rows[-1]) + 1
    left, right = max(0, int(columns[0]) - reach), int(columns[-1]) + 1 + reach
    window = image[top:bottom, left:right]
    inside = ((window >= low) & (window <= high)).all(axis=-1)
    mask[top:bottom, left:right] |= inside & (labels[top:bottom, left:right] == WHITE)
    return mask


def test_the_goal_pixels_with_their_rims_are_the_numpy_ones():
    rng = np.random.default_rng(8)
    rims = GoalRims.from_thresholds(load_thresholds())
    for _ in range(200):
        labels = random_labels(rng)
        image = rng.integers(0, 256, (*labels.shape, 3), dtype=np.uint8)
        for goal, goal_class in ((GoalColor.BLUE, int(ColorClass.BLUE)), (GoalColor.YELLOW, int(ColorClass.YELLOW))):
            low, high = rims.ranges[goal]
            expected = reference_goal_pixels(labels, image, goal_class, low, high, RIM_REACH_PX)
            assert np.array_equal(rims.goal_pixels(labels, image, goal), expected)
            found = [(p.first_column, p.last_column, p.top_row, p.bottom_row, p.base_u, p.core_width_px,
                      p.base_first_column, p.base_last_column) for p in find_posts(labels, goal, expected)]
            assert found == reference_posts(labels, goal, expected)


def reference_black_lines(labels: np.ndarray, border: FieldBorder, dist: int, allowed: set[int]) -> list[tuple]:
    """Thesis 4.5.1's runs and criteria pixel by pixel: (column, top, bottom, rejected by 0-4)."""
    h, w = labels.shape
    runs = []
    for column in range(0, w, dist):
        start = min(max(math.ceil(float(border.row_at(np.array([column]))[0]) - 1e-9), 0), h)
        row = start
        while row < h:
            if labels[row, column] != WHITE:
                row += 1
                continue
            top = row
            while row + 1 < h and labels[row + 1, column] == WHITE:
                row += 1
            green_above = top > start and labels[top - 1, column] == GREEN
            green_ends = green_above and row < h - 1 and labels[row + 1, column] == GREEN
            beside = [labels[r, c] for r in range(top + 1, row) for c in (column - 1, column + 1) if 0 <= c < w]
            runs.append([column, top, row, 0 if green_ends else 1, all(b in allowed for b in beside)])
            row += 1
    lengths = [bottom - top + 1 for _, top, bottom, _, _ in runs if bottom - top + 1 > 3]
    for run in runs:
        if run[3] == 0 and not run[4]:
            run[3] = 2
        elif run[3] == 0 and lengths and run[2] - run[1] + 1 > 2.0 * sum(lengths) / len(lengths):
            run[3] = 3
    alive = [run for run in runs if run[3] == 0]
    if alive:
        scan_index, top, bottom = (np.array(values) for values in zip(*[(c // dist, t, b) for c, t, b, *_ in alive]))
        for run, chained in zip(alive, reference_continuity(scan_index, top, bottom)):
            run[3] = 0 if chained else 4
    return [tuple(run[:4]) for run in runs]


@pytest.mark.parametrize("dist, allowed", [(5, NEIGHBOURS_ALLOWED), (3, NEIGHBOURS_THESIS)])
def test_scan_lines_agree_with_a_pixel_by_pixel_scan(dist: int, allowed: tuple):
    rng = np.random.default_rng(7)
    for _ in range(25):
        labels = random_labels(rng)
        columns = np.arange(0, 160, 3)
        rows = np.clip(rng.integers(0, 40) + np.cumsum(rng.integers(-1, 2, len(columns))), 0, 119)
        rows[rng.random(len(columns)) < 0.2] = -1  # dots Algorithm 1 ignored
        border = FieldBorder(True, columns, rows, rows)
        black = scan_black_lines(labels, border, dist, allowed)
        found = list(zip(black.column.tolist(), black.top.tolist(), black.bottom.tolist(), black.rejected_by.tolist()))
        assert found == reference_black_lines(labels, border, dist, {int(c) for c in allowed})


def test_the_compiled_classification_is_the_colour_tables_lookup():
    table = ColorTable(load_thresholds())
    rng = np.random.default_rng(11)
    for image in [rng.integers(0, 256, (120, 160, 3), dtype=np.uint8) for _ in range(5)]:
        q = image.astype(np.intp) >> LEVEL_SHIFT
        expected = table.table[(q[..., 0] << 12) | (q[..., 1] << 6) | q[..., 2]]
        assert np.array_equal(table.classify(image), expected)
        assert np.array_equal(table.classify(image[::2, ::-1]), expected[::2, ::-1])  # views of any layout


def test_the_segmentation_refuses_what_is_not_an_rgb_image_or_labels():
    table = ColorTable(load_thresholds())
    with pytest.raises(ValueError, match="RGB uint8"):
        table.classify(np.zeros((120, 160, 3), np.int64))
    with pytest.raises(ValueError, match="RGB uint8"):
        table.classify(np.zeros((120, 160), np.uint8))
    with pytest.raises(ValueError, match="uint8"):
        clean_outliers(np.zeros((4, 4), np.int32))


# ---- line formation (thesis 4.5.2) as plain Python loops ------------------------------------------------

def _large_deviation(len1: float, len2: float) -> bool:
    """True when two black-line lengths deviate too much for AddLimit to apply."""
    short, long_ = (len1, len2) if len1 <= len2 else (len2, len1)
    return long_ > LENGTH_DEVIATION_RATIO * short and long_ - short >= LENGTH_DEVIATION_MIN_PX


def _sign(d: float) -> int:
    return 0 if abs(d) <= DIRECTION_DEADBAND_PX else (1 if d > 0 else -1)


def _get_start(flag: list[int], begin: int = 0) -> int:
    """GetStart: index of the first black line from ``begin`` not used by a line, or -1."""
    for i in range(begin, len(flag)):
        if flag[i] == 0:
            return i
    return -1


def _get_line(w: list, h: list, n: list, flag: list[int], start: int, dist: int = DIST) -> list[int]:
    """GetLine (thesis Algorithm 2): the black lines of the line starting at ``start``; flags them."""
    line = [start]
    flag[start] = 1
    current = start
    direction = 0  # the sign of the last step (0 until the line has two black lines)
    limit_w = MAX_GAP_DISTS * dist
    for nxt in range(start + 1, len(w)):
        if w[nxt] - w[current] >= limit_w:  # criterion 3
            break
        if flag[nxt] or w[nxt] == w[current]:  # criteria 1 and 2
            continue
        d2 = h[nxt] - h[current]
        if abs(d2) > add_limit(n[current], n[nxt], w[current], w[nxt], dist) or _large_deviation(n[current], n[nxt]):
            continue  # criterion 4
        step = _sign(d2)
        if direction * step < 0:
            continue  # criterion 5: the direction changes sign
        line.append(nxt)
        flag[nxt] = 1
        current = nxt
        direction = step
    return line


def reference_form_lines(column: np.ndarray, middle: np.ndarray, length: np.ndarray) -> list[list[int]]:
    w, h, n = column.tolist(), middle.tolist(), length.tolist()
    flag = [0] * len(w)
    lines, start = [], 0
    while True:
        start = _get_start(flag, start)
        if start < 0:
            return lines
        line = _get_line(w, h, n, flag, start)
        if len(line) >= MIN_BLACK_LINES:
            lines.append(line)


def test_lines_formed_are_those_of_the_python_loops():
    rng = np.random.default_rng(9)
    formed = 0
    for _ in range(300):
        labels = random_labels(rng)
        columns = np.arange(0, labels.shape[1], 3)
        top_rows = np.zeros(len(columns), np.int64)  # the border at the image's top: every run is scanned
        black = scan_black_lines(labels, FieldBorder(True, columns, top_rows, top_rows))
        kept = black.kept
        args = black.column[kept], black.middle[kept], black.length[kept]
        lines = form_lines(*args)
        assert lines == reference_form_lines(*args)
        formed += len(lines)
    assert formed > 100
