"""Field lines (thesis 4.5): criteria, Algorithm 3, Table 4.3, circle fit, rendered circle."""

from __future__ import annotations

import math

import cv2
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from agents.vision.border import find_border
from agents.vision.colors import ColorClass
from agents.vision.frame import CameraFrame
from agents.vision.lines import detect_line_landmarks
from agents.vision.lines.line_landmarks import circle_through
from agents.vision.lines.scan import BlackLine, apply_criteria, white_runs
from agents.vision.lines.shapes import DOWN, STRAIGHT, UP, LineType, classify, direction_labels, fit_parabola, form_lines
from agents.vision.camera_models import camera_model
from agents.vision.pipeline import VisionPipeline
from world.field import LandmarkKind, Pose2D

GREEN, WHITE = int(ColorClass.GREEN), int(ColorClass.WHITE)


def field_labels(border_row: int = 20) -> np.ndarray:
    labels = np.full((120, 160), WHITE, np.uint8)
    labels[border_row:] = GREEN
    return labels


def test_a_thin_line_below_the_border_is_kept_and_a_robot_blob_is_not():
    labels = field_labels()
    cv2.line(labels, (0, 60), (159, 70), WHITE, 2)
    labels[80:110, 100:112] = WHITE  # a robot: a long white run
    labels[95:97, 103:109] = int(ColorClass.CYAN)  # its waistband
    border = find_border(labels)
    runs = apply_criteria(labels, white_runs(labels, border))
    line_runs = [r for r in runs if r.top < 75]
    robot_runs = [r for r in runs if r.top >= 75]
    assert line_runs and all(r.rejected == 0 for r in line_runs)
    assert robot_runs and all(r.rejected for r in robot_runs)


def test_a_run_touching_the_border_fails_criterion_1():
    labels = field_labels()
    labels[20:30, 50] = WHITE  # white from the border down
    runs = apply_criteria(labels, white_runs(labels, find_border(labels)))
    assert [r.rejected for r in runs if r.u == 50] == [1]


def test_an_isolated_run_fails_criterion_4():
    labels = field_labels()
    labels[60:62, 50] = WHITE
    runs = apply_criteria(labels, white_runs(labels, find_border(labels)))
    assert [r.rejected for r in runs] == [4]


def test_getline_forms_one_line_and_keeps_distant_strokes_apart():
    runs = [BlackLine(u, 50 + u // 10, 51 + u // 10) for u in range(0, 60, 5)]
    runs += [BlackLine(u, 90, 91) for u in range(100, 130, 5)]
    lines = form_lines(runs)
    assert sorted(len(line) for line in lines) == [6, 12]


def _runs(mids):
    return [BlackLine(5 * i, int(m), int(m) + 1) for i, m in enumerate(mids)]


def test_algorithm_3_labels_segments():
    rising = _runs([60 - 2 * i for i in range(9)])
    assert direction_labels(rising)[0] == (UP,)
    arc = _runs([60, 57, 54, 52, 52, 52, 54, 57, 60])
    assert direction_labels(arc)[0] == (UP, STRAIGHT, DOWN)


@pytest.mark.parametrize(
    "a, b, expected",
    [
        (2.0, 0.1, LineType.UPPER_HALF_CIRCLE),
        (-2.0, 0.0, LineType.DOWN_HALF_CIRCLE),
        (6.0, 0.2, LineType.UP_CORNER),
        (-6.0, -0.2, LineType.DOWN_CORNER),
        (0.0, 0.3, LineType.SIDE_DOWN),
        (0.0, -0.3, LineType.SIDE_UP),
        (0.1, 0.01, LineType.STRAIGHT),
        (2.0, 0.9, LineType.SIDE_DOWN),
    ],
)
def test_table_4_3(a, b, expected):
    assert classify(a, b) == expected


@given(
    a=st.floats(-8.0, 8.0),
    b=st.floats(-1.0, 1.0),
    c=st.floats(20.0, 100.0),
)
def test_least_squares_recovers_the_parabola(a, b, c):
    w = np.arange(20.0, 140.0, 5.0)
    x = w - w.mean()
    h = a / 1000.0 * x * x + b * x + c
    fa, fb, fc = fit_parabola(w, h)
    assert fa == pytest.approx(a, abs=1e-6) and fb == pytest.approx(b, abs=1e-9) and fc == pytest.approx(c, abs=1e-6)


@given(
    cx=st.floats(-3, 3), cy=st.floats(-3, 3), r=st.floats(0.2, 2.0),
    t=st.lists(st.floats(0, 2 * math.pi), min_size=3, max_size=3, unique=True),
)
def test_circle_through_three_points(cx, cy, r, t):
    points = [np.array([cx + r * math.cos(a), cy + r * math.sin(a)]) for a in t]
    chords = [np.linalg.norm(points[i] - points[j]) for i, j in ((0, 1), (1, 2), (0, 2))]
    if min(chords) < 0.05 * r:
        return
    fitted = circle_through(*points)
    assert fitted is not None
    assert fitted == pytest.approx((cx, cy, r), abs=1e-6)


def test_collinear_points_have_no_circle():
    assert circle_through(np.array([0.0, 0.0]), np.array([1.0, 1.0]), np.array([2.0, 2.0])) is None


def test_no_border_no_line_landmarks():
    labels = np.full((120, 160), WHITE, np.uint8)
    border = find_border(labels)
    frame = CameraFrame(np.zeros((120, 160, 3), np.uint8), 0.0, 0.3)
    assert detect_line_landmarks(labels, border, frame, camera_model("exact"))[0] == ()


@pytest.mark.render
def test_the_centre_circle_is_found_from_known_poses(world):
    pipeline = VisionPipeline("exact")
    world.place_robot("b", Pose2D(0.0, -3.2, 0.0))
    found = 0
    for pose in (Pose2D(-1.3, 0.0, 0.0), Pose2D(1.4, 0.3, math.pi), Pose2D(0.0, -1.4, math.pi / 2)):
        world.place_robot("a", pose)
        world.set_head("a", 0.0, math.radians(17.0))
        world.step(15)
        s = world.sensors("a")
        frame = CameraFrame(world.render_camera("a"), s.head_yaw_rad, s.head_pitch_rad, s.camera, None)
        circles = [p for p in pipeline.process(frame).percepts if p.kind is LandmarkKind.CENTER_CIRCLE]
        truth = world.robot_pose("a")
        distance = math.hypot(truth.x, truth.y)
        bearing = math.remainder(math.atan2(-truth.y, -truth.x) - truth.theta, 2 * math.pi)
        for circle in circles:
            assert circle.distance_m == pytest.approx(distance, rel=0.15)
            assert abs(math.degrees(math.remainder(circle.bearing_rad - bearing, 2 * math.pi))) < 5.0
        found += bool(circles)
    assert found >= 2
