"""Pure geometry of localization: circle intersections (thesis 5.3), Algorithm 4 (5.4), odometry (5.5)."""

from __future__ import annotations

import math

import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from agents.localization.circles import CircleCase, intersect_circles
from agents.localization.constraint import FIELD_MARGIN_M, in_field, solve
from agents.localization.estimate import LandmarkObservation
from agents.localization.odometry import Odometer, compose
from match.protocol import Displacement
from world.field import FIELD, Pose2D, normalize_angle

coord = st.floats(-5.0, 5.0, allow_nan=False)
radius = st.floats(0.05, 5.0, allow_nan=False)
angle = st.floats(-math.pi, math.pi, allow_nan=False)


def _dist(a: tuple[float, float], b: tuple[float, float]) -> float:
    return math.hypot(a[0] - b[0], a[1] - b[1])


# ---- circle intersections: the five cases of thesis 5.3 --------------------------------------


@given(coord, coord, coord, coord, coord, coord)
def test_intersecting_circles_give_both_points_through_a_known_point(x0, y0, x1, y1, px, py):
    c0, c1, p = (x0, y0), (x1, y1), (px, py)
    d, r0, r1 = _dist(c0, c1), _dist(p, c0), _dist(p, c1)
    assume(d > 0.05 and r0 > 0.05 and r1 > 0.05)
    # keep clear of tangency: p at least 1 cm off the line through the centres
    cross = ((x1 - x0) * (py - y0) - (y1 - y0) * (px - x0)) / d
    assume(abs(cross) > 0.01)
    result = intersect_circles(c0, r0, c1, r1)
    assert result.case is CircleCase.INTERSECTING
    assert len(result.points) == 2
    assert min(_dist(q, p) for q in result.points) < 1e-6
    for q in result.points:
        assert _dist(q, c0) == pytest.approx(r0, abs=1e-6)
        assert _dist(q, c1) == pytest.approx(r1, abs=1e-6)
    mirror = max(result.points, key=lambda q: _dist(q, p))
    assert _dist(mirror, p) == pytest.approx(2 * abs(cross), abs=1e-6)


@given(coord, coord, angle, st.floats(0.1, 5.0), radius, st.floats(0.001, 3.0))
def test_separated_circles_give_nothing(x0, y0, direction, d, r0, gap):
    assume(d > r0)
    r1 = d - r0 - gap
    assume(r1 > 0.0)
    c1 = (x0 + d * math.cos(direction), y0 + d * math.sin(direction))
    result = intersect_circles((x0, y0), r0, c1, r1)
    assert result.case is CircleCase.SEPARATED and result.points == ()


@given(coord, coord, radius)
def test_coincident_circles_give_nothing(x, y, r):
    result = intersect_circles((x, y), r, (x, y), r)
    assert result.case is CircleCase.COINCIDENT and result.points == ()


@given(coord, coord, angle, st.floats(0.1, 5.0), st.floats(0.01, 0.99))
def test_externally_tangent_circles_give_the_tangent_point(x0, y0, direction, d, share):
    r0, r1 = share * d, (1.0 - share) * d
    c0 = (x0, y0)
    c1 = (x0 + d * math.cos(direction), y0 + d * math.sin(direction))
    result = intersect_circles(c0, r0, c1, r1)
    assert result.case is CircleCase.TANGENT and len(result.points) == 1
    truth = (x0 + r0 * math.cos(direction), y0 + r0 * math.sin(direction))
    assert _dist(result.points[0], truth) < 1e-6


@given(coord, coord, angle, st.floats(0.1, 3.0), st.floats(0.05, 3.0))
def test_internally_tangent_circles_give_the_tangent_point(x0, y0, direction, d, r_small):
    r_big = d + r_small
    big = (x0, y0)
    small = (x0 + d * math.cos(direction), y0 + d * math.sin(direction))
    truth = (x0 + r_big * math.cos(direction), y0 + r_big * math.sin(direction))
    for args in ((big, r_big, small, r_small), (small, r_small, big, r_big)):
        result = intersect_circles(*args)
        assert result.case is CircleCase.TANGENT and len(result.points) == 1
        assert _dist(result.points[0], truth) < 1e-6


@given(coord, coord, angle, st.floats(0.05, 3.0), st.floats(0.05, 3.0), st.floats(0.01, 3.0))
def test_contained_circles_shrink_the_larger_radius_to_internal_tangency(x0, y0, direction, d, r_small, excess):
    r_big = d + r_small + excess  # the larger distance overestimated by ``excess`` (thesis: e = r0 - (d + r1))
    big = (x0, y0)
    small = (x0 + d * math.cos(direction), y0 + d * math.sin(direction))
    truth = (x0 + (d + r_small) * math.cos(direction), y0 + (d + r_small) * math.sin(direction))
    result = intersect_circles(big, r_big, small, r_small)
    assert result.case is CircleCase.CONTAINED and len(result.points) == 1
    assert _dist(result.points[0], truth) < 1e-6
    assert _dist(result.points[0], small) == pytest.approx(r_small, abs=1e-6)


def test_concentric_circles_of_different_radii_give_nothing():
    result = intersect_circles((1.0, 1.0), 2.0, (1.0, 1.0), 1.0)
    assert result.case is CircleCase.CONTAINED and result.points == ()


# ---- Algorithm 4 on synthetic landmark sets ---------------------------------------------------

field_x = st.floats(-FIELD.half_length, FIELD.half_length)
field_y = st.floats(-FIELD.half_width, FIELD.half_width)


def _observations(pose: Pose2D, chosen: list[int], noise: list[tuple[float, float]] | None = None):
    found = []
    for k, index in enumerate(chosen):
        lm = FIELD.landmarks[index]
        d = math.hypot(lm.x - pose.x, lm.y - pose.y)
        if d < 0.3:
            continue  # the bearing to a landmark under the robot's feet means nothing
        b = normalize_angle(math.atan2(lm.y - pose.y, lm.x - pose.x) - pose.theta)
        if noise is not None:
            rel, db = noise[k]
            d, b = d * (1.0 + rel), normalize_angle(b + db)
        found.append(LandmarkObservation(lm.id, lm.x, lm.y, d, b))
    return found


@given(field_x, field_y, angle, st.lists(st.integers(0, len(FIELD.landmarks) - 1), min_size=2, max_size=8, unique=True))
def test_algorithm4_recovers_the_true_pose_without_noise(x, y, theta, chosen):
    pose = Pose2D(x, y, theta)
    observations = _observations(pose, chosen)
    assume(len(observations) >= 2)
    best = solve(observations).best
    assert best is not None
    assert math.hypot(best.x_m - x, best.y_m - y) < 0.01
    assert abs(normalize_angle(best.theta_rad - theta)) < math.radians(0.5)
    assert best.max_diff_rad < 1e-3


@settings(max_examples=150, deadline=None)
@given(
    field_x,
    field_y,
    angle,
    st.lists(st.integers(0, len(FIELD.landmarks) - 1), min_size=4, max_size=10, unique=True),
    st.lists(st.tuples(st.floats(-0.01, 0.01), st.floats(-math.radians(0.5), math.radians(0.5))), min_size=10, max_size=10),
)
def test_algorithm4_error_is_bounded_under_bounded_noise(x, y, theta, chosen, noise):
    """Distances within 1 % and bearings within 0.5 degree, four or more landmarks 0.3-4 m away."""
    pose = Pose2D(x, y, theta)
    observations = [o for o in _observations(pose, chosen, noise) if o.distance_m <= 4.0]
    assume(len(observations) >= 4)
    solution = solve(observations, orientation="mean")
    assert solution.best is not None
    assert math.hypot(solution.best.x_m - x, solution.best.y_m - y) < 0.5
    assert abs(normalize_angle(solution.best.theta_rad - theta)) < math.radians(10.0)


def test_candidates_outside_the_field_are_rejected():
    # two posts of the blue goal: the mirror image of a point in front of the goal is behind it
    pose = Pose2D(-2.0, 0.3, math.pi)
    observations = _observations(pose, [0, 1])
    solution = solve(observations)
    assert len(solution.candidates) == 1 and len(solution.rejected) == 1
    assert not in_field(*solution.rejected[0], margin_m=FIELD_MARGIN_M)


def test_algorithm4_takes_the_first_observations_orientation():
    pose = Pose2D(0.5, -0.4, 0.3)
    observations = _observations(pose, [0, 1, 2, 6])
    skewed = [observations[0]] + [
        LandmarkObservation(o.landmark_id, o.x_m, o.y_m, o.distance_m, o.bearing_rad + 0.01) for o in observations[1:]
    ]
    best = solve(skewed).best
    assert best is not None
    implied = math.atan2(skewed[0].y_m - best.y_m, skewed[0].x_m - best.x_m) - skewed[0].bearing_rad
    assert best.theta_rad == pytest.approx(normalize_angle(implied), abs=1e-9)


# ---- odometry ---------------------------------------------------------------------------------

distance = st.floats(-0.5, 0.5)
turn = st.floats(-math.pi, math.pi)


@given(field_x, field_y, angle, st.integers(1, 12), distance)
def test_forward_steps_move_along_the_heading(x, y, theta, n, d):
    odometer = Odometer(Pose2D(x, y, theta))
    for _ in range(n):
        odometer.move(Displacement(forward_m=d))
    assert odometer.pose.x == pytest.approx(x + n * d * math.cos(theta), abs=1e-9)
    assert odometer.pose.y == pytest.approx(y + n * d * math.sin(theta), abs=1e-9)


@given(field_x, field_y, angle, st.integers(1, 12), distance)
def test_side_steps_move_across_the_heading(x, y, theta, n, d):
    odometer = Odometer(Pose2D(x, y, theta))
    for _ in range(n):
        odometer.move(Displacement(left_m=d))
    assert odometer.pose.x == pytest.approx(x - n * d * math.sin(theta), abs=1e-9)
    assert odometer.pose.y == pytest.approx(y + n * d * math.cos(theta), abs=1e-9)


@given(angle, st.lists(turn, min_size=1, max_size=20))
def test_turns_add_up_and_stay_normalized(theta, turns):
    odometer = Odometer(Pose2D(0.0, 0.0, theta))
    for t in turns:
        odometer.move(Displacement(turn_rad=t))
        assert -math.pi < odometer.pose.theta <= math.pi
    assert math.cos(odometer.pose.theta - (theta + sum(turns))) == pytest.approx(1.0, abs=1e-9)
    assert (odometer.pose.x, odometer.pose.y) == (0.0, 0.0)


@given(field_x, field_y, angle, st.integers(3, 12), st.floats(0.05, 0.5), st.booleans())
def test_a_closed_polygon_returns_to_the_start(x, y, theta, sides, length, left):
    exterior = (2.0 * math.pi / sides) * (1 if left else -1)
    odometer = Odometer(Pose2D(x, y, theta))
    for _ in range(sides):
        odometer.move(Displacement(forward_m=length))
        odometer.move(Displacement(turn_rad=exterior))
    assert odometer.pose.x == pytest.approx(x, abs=1e-9)
    assert odometer.pose.y == pytest.approx(y, abs=1e-9)
    assert abs(normalize_angle(odometer.pose.theta - theta)) < 1e-9


@given(
    field_x,
    field_y,
    angle,
    st.lists(st.tuples(distance, distance, turn), min_size=1, max_size=10),
)
def test_step_by_step_equals_the_composed_displacement(x, y, theta, steps):
    pose = Pose2D(x, y, theta)
    total = Displacement()
    for forward, left, t in steps:
        d = Displacement(forward, left, t)
        pose = compose(pose, d)
        total = total.plus(d)
    direct = compose(Pose2D(x, y, theta), total)
    assert pose.x == pytest.approx(direct.x, abs=1e-9)
    assert pose.y == pytest.approx(direct.y, abs=1e-9)
    assert abs(normalize_angle(pose.theta - direct.theta)) < 1e-9
    assert -math.pi < pose.theta <= math.pi


def test_unset_odometer_stays_unset_until_reset():
    odometer = Odometer()
    assert odometer.move(Displacement(0.1, 0.0, 0.0)) is None
    odometer.reset(Pose2D(1.0, 2.0, 4.0))
    assert odometer.pose == Pose2D(1.0, 2.0, normalize_angle(4.0))
