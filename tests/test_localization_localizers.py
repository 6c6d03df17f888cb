"""The localizers behind one interface: oracle recovery, odometer rules, bad input, kidnapping."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from agents.localization import (
    LOCALIZERS,
    LocalizationConfigError,
    LocalizationInputError,
    Localizer,
    disambiguate,
    localizer,
)
from agents.localization.estimate import EstimateSource
from agents.localization.odometry import compose
from agents.localization.thesis_method import REASON_ALL_REJECTED, REASON_FEW_LANDMARKS, REASON_JUMP
from agents.vision.percepts import CornerShape, LandmarkPercept
from match.protocol import Displacement
from tests.oracle_percepts import oracle_percepts
from tests.strategies import field_pose
from world.field import FIELD, GoalColor, LandmarkId, LandmarkKind, Pose2D, normalize_angle

METHODS = sorted(LOCALIZERS)
FILTERS = ("particle", "hybrid")
PARTICLE_UPDATES = 3  # scans of a standing robot a particle filter may take to find its pose from nothing


def _error(estimate, pose: Pose2D) -> tuple[float, float]:
    return math.hypot(estimate.x_m - pose.x, estimate.y_m - pose.y), abs(normalize_angle(estimate.theta_rad - pose.theta))


def _same_pose(a: Pose2D, b: Pose2D) -> bool:
    return math.hypot(a.x - b.x, a.y - b.y) < 1e-9 and abs(normalize_angle(a.theta - b.theta)) < 1e-9


def _percept(kind, bearing, distance, landmark_id=None, goal=None) -> LandmarkPercept:
    return LandmarkPercept(kind, (0.0, 0.0), bearing, distance, "test", landmark_id=landmark_id, goal=goal)


# ---- the interface ----------------------------------------------------------------------------


def test_unknown_method_name_is_a_typed_error_naming_it_and_the_choices():
    with pytest.raises(LocalizationConfigError) as error:
        localizer("kalman")
    assert "kalman" in str(error.value)
    assert all(name in str(error.value) for name in METHODS)
    assert isinstance(error.value, ValueError)


def test_unknown_option_is_a_typed_error():
    with pytest.raises(LocalizationConfigError, match="particle_count"):
        localizer("particle", particle_count=10)
    assert localizer("particle", particles=50).config.particles == 50
    with pytest.raises(LocalizationConfigError, match="particles"):
        localizer("particle", particles=0)
    with pytest.raises(LocalizationConfigError, match="orientation"):
        localizer("thesis", orientation="median")
    for option, bad in (("inject_min_percepts", 0), ("inject_min_percepts", True), ("inject_below_likelihood", 1.5)):
        with pytest.raises(LocalizationConfigError, match=option):
            localizer("particle", **{option: bad})


@pytest.mark.parametrize("name", METHODS)
def test_every_method_is_a_localizer(name):
    loc = localizer(name, seed=0)
    assert isinstance(loc, Localizer)
    assert loc.name == name


@pytest.mark.parametrize("name", METHODS)
def test_empty_or_nan_percepts_give_no_estimate_and_keep_the_odometer(name):
    start = Pose2D(-1.2, 1.0, 0.0)
    loc = localizer(name, seed=0, initial_pose=start)
    step = Displacement(0.25, 0.0, 0.3)
    loc.move(step)
    expected = compose(start, step)
    nan = _percept(LandmarkKind.CENTER_CIRCLE, math.nan, 1.0, LandmarkId.CENTER_CIRCLE)
    for percepts in ([], (), [nan], [nan, _percept(LandmarkKind.L_CORNER, 0.2, math.inf)]):
        assert loc.localize(percepts) is None
        assert _same_pose(loc.pose, expected)


@pytest.mark.parametrize("name", METHODS)
def test_bad_input_is_a_typed_error_and_changes_nothing(name):
    start = Pose2D(0.5, -0.5, 1.0)
    loc = localizer(name, seed=0, initial_pose=start)
    bad_moves = (Displacement(math.nan, 0.0, 0.0), Displacement(0.0, 0.0, math.inf), "forward", None, (0.1, 0.0, 0.0))
    for bad in bad_moves:
        with pytest.raises(LocalizationInputError, match="displacement"):
            loc.move(bad)
    for bad in (Pose2D(math.nan, 0.0, 0.0), (0.0, 0.0, 0.0)):
        with pytest.raises(LocalizationInputError, match="pose"):
            loc.reset(bad)
    mislabelled = _percept(LandmarkKind.L_CORNER, 0.1, 2.0, LandmarkId.BLUE_GOAL_LEFT_POST)
    for bad in (None, "percepts", [1, 2], 3.0, [mislabelled], [_percept(LandmarkKind.GOAL_POST, 0.1, 2.0, "blue")]):
        with pytest.raises(LocalizationInputError, match="percept"):
            loc.localize(bad)
    assert loc.pose == start


any_float = st.floats(allow_nan=True, allow_infinity=True) | st.floats(-10.0, 10.0)


@st.composite
def any_percept(draw) -> LandmarkPercept:
    """Well-typed percepts with any measurements: a landmark id, if any, of the percept's kind."""
    kind = draw(st.sampled_from(LandmarkKind))
    ids = [lm.id for lm in FIELD.landmarks if lm.kind is kind]
    return LandmarkPercept(
        kind,
        (draw(any_float), draw(any_float)),
        draw(any_float),
        draw(any_float),
        "fuzz",
        draw(st.none() | st.sampled_from(ids)),
        draw(st.none() | st.sampled_from(GoalColor)),
        draw(st.none() | st.sampled_from(CornerShape)),
    )


@pytest.mark.parametrize("name", METHODS)
@settings(max_examples=40, deadline=None)
@given(percepts=st.lists(any_percept(), max_size=8))
def test_any_well_typed_percepts_give_a_finite_estimate_or_none(name, percepts):
    loc = localizer(name, seed=0, initial_pose=Pose2D(0.0, 0.0, 0.0))
    estimate = loc.localize(percepts)
    if estimate is not None:
        assert all(math.isfinite(v) for v in (estimate.x_m, estimate.y_m, estimate.theta_rad))
    assert loc.pose.is_finite()


# ---- recovery from oracle percepts without noise ----------------------------------------------

@settings(max_examples=60, deadline=None)
@given(field_pose)
def test_thesis_method_recovers_the_pose_from_nothing(pose):
    percepts = oracle_percepts(pose, None)
    assume(len(disambiguate(percepts)) >= 2)
    estimate = localizer("thesis").localize(percepts)
    position, heading = _error(estimate, pose)
    assert position < 0.01 and heading < math.radians(0.5)


@pytest.mark.parametrize("name", FILTERS)
@settings(max_examples=25, deadline=None)
@given(pose=field_pose, seed=st.integers(0, 2**16))
def test_particle_filters_recover_the_pose_from_nothing_within_a_few_scans(name, pose, seed):
    """From particles spread over the field, at most PARTICLE_UPDATES scans of a standing robot."""
    percepts = oracle_percepts(pose, None)
    assume(len(disambiguate(percepts)) >= 2)  # the landmarks fix the pose (no mirror image)
    loc = localizer(name, seed=seed)
    errors = []
    for _ in range(PARTICLE_UPDATES):
        errors.append(_error(loc.localize(percepts), pose))
    position, heading = errors[-1]
    assert position < 0.01 and heading < math.radians(0.5), errors


SIDE_LINE_FACING_OUT = Pose2D(-0.5, -2.0, -1.0)  # sees one far post and two L corners, 3-3.7 m away


@pytest.mark.parametrize(
    "name",
    [
        "hybrid",
        pytest.param("particle", marks=pytest.mark.xfail(strict=True, reason="known limit of the particle filter alone")),
    ],
)
def test_a_robot_on_the_side_line_facing_out_is_found_from_nothing(name):
    """At far landmarks the scan's likelihood is a 1 m ridge; the cloud's cluster lies 0.6 m
    inward and its polish would move farther than the trust radius. Of seeds 0-299 and 1648,
    the particle filter alone stays off with 7; the hybrid's candidates find the pose with all."""
    percepts = oracle_percepts(SIDE_LINE_FACING_OUT, None)
    loc = localizer(name, seed=1648)  # one of the seven
    for _ in range(PARTICLE_UPDATES):
        estimate = loc.localize(percepts)
    position, heading = _error(estimate, SIDE_LINE_FACING_OUT)
    assert position < 0.01 and heading < math.radians(0.5)


@pytest.mark.parametrize("name", METHODS)
def test_every_method_keeps_the_true_pose_along_a_walk(name):
    """Tracking from a known start, nominal motions exact: every scan with two placed landmarks is exact."""
    rng = np.random.default_rng(3)
    pose = Pose2D(-1.2, 1.0, 0.0)
    loc = localizer(name, seed=1, initial_pose=pose)
    steps = (Displacement(0.25, 0.0, 0.0), Displacement(0.0, 0.0, math.radians(40)), Displacement(0.0, -0.08, 0.0))
    checked = 0
    for _ in range(40):
        step = steps[int(rng.integers(len(steps)))]
        if abs(compose(pose, step).x) > 2.7 or abs(compose(pose, step).y) > 1.7:
            step = Displacement(0.0, 0.0, math.radians(60))
        pose = compose(pose, step)
        loc.move(step)
        percepts = oracle_percepts(pose, None)
        estimate = loc.localize(percepts)
        if len(disambiguate(percepts)) >= 2 or name == "odometry":
            position, heading = _error(estimate, pose)
            assert position < 0.01 and heading < math.radians(0.5)
            checked += 1
    assert checked >= 20


@pytest.mark.parametrize("name", FILTERS)
def test_particle_filters_use_posts_of_unknown_side_and_unplaced_corners(name):
    """With a rough prior, percepts the thesis method cannot place still fix the pose exactly."""
    rng = np.random.default_rng(4)
    checked = 0
    while checked < 10:
        pose = Pose2D(rng.uniform(-2.5, 2.5), rng.uniform(-1.5, 1.5), rng.uniform(-math.pi, math.pi))
        percepts = oracle_percepts(pose, None, lone_post_sides=False)
        if len(percepts) < 3:
            continue
        start = Pose2D(pose.x + 0.15, pose.y - 0.1, pose.theta + 0.1)
        estimate = localizer(name, seed=checked, initial_pose=start).localize(percepts)
        position, heading = _error(estimate, pose)
        assert position < 0.01 and heading < math.radians(0.5)
        checked += 1


# ---- the odometer rules of the thesis method (5.5) --------------------------------------------


def test_fewer_than_two_landmarks_give_the_odometer():
    start = Pose2D(0.0, 0.0, 0.0)
    loc = localizer("thesis", initial_pose=start)
    estimate = loc.localize([_percept(LandmarkKind.CENTER_CIRCLE, 0.0, 1.0, LandmarkId.CENTER_CIRCLE)])
    assert estimate.source is EstimateSource.ODOMETER and estimate.reason == REASON_FEW_LANDMARKS
    assert estimate.pose == start
    assert localizer("thesis").localize([_percept(LandmarkKind.CENTER_CIRCLE, 0.0, 1.0, LandmarkId.CENTER_CIRCLE)]) is None


def test_all_candidates_rejected_give_the_odometer():
    start = Pose2D(1.0, 0.0, 0.0)
    loc = localizer("thesis", initial_pose=start)
    # both intersections of these circles lie 2.6 m off the middle of the field: outside it
    percepts = [
        _percept(LandmarkKind.CENTER_CIRCLE, 0.0, 3.0, LandmarkId.CENTER_CIRCLE),
        _percept(LandmarkKind.GOAL_CENTER, 0.5, 3.0, LandmarkId.YELLOW_GOAL_CENTER),
    ]
    estimate = loc.localize(percepts)
    assert estimate.source is EstimateSource.ODOMETER and estimate.reason == REASON_ALL_REJECTED
    assert estimate.pose == start


def test_a_jump_is_accepted_the_second_consecutive_time():
    start, truth = Pose2D(-1.0, 0.0, 0.0), Pose2D(0.5, 0.8, 0.4)
    loc = localizer("thesis", initial_pose=start)
    percepts = oracle_percepts(truth, None)
    assert len(disambiguate(percepts)) >= 2
    first = loc.localize(percepts)
    assert first.source is EstimateSource.ODOMETER and first.reason == REASON_JUMP and first.pose == start
    assert first.candidates  # the rejected landmark pose's candidates are reported
    second = loc.localize(percepts)
    assert second.source == "landmarks"
    assert _error(second, truth)[0] < 0.01
    assert _same_pose(loc.pose, second.pose)


def test_an_accepted_localization_resets_the_jump_count_and_the_odometer():
    near, far = Pose2D(0.5, 0.8, 0.4), Pose2D(-1.5, -1.0, 2.5)
    loc = localizer("thesis", initial_pose=Pose2D(0.6, 0.7, 0.3))
    assert loc.localize(oracle_percepts(far, None)).reason == REASON_JUMP
    accepted = loc.localize(oracle_percepts(near, None))
    assert accepted.source == "landmarks" and _error(accepted, near)[0] < 0.01
    assert loc.localize(oracle_percepts(far, None)).reason == REASON_JUMP


# ---- particle filter: kidnapping and determinism ----------------------------------------------

KIDNAP_SCANS = 4  # a kidnapped filter is back within this many scans (200 trials: 183 in one, all in four)


@pytest.mark.parametrize("name", FILTERS)
def test_particle_filter_recovers_from_kidnapping(name):
    rng = np.random.default_rng(11)
    noise = (0.05, math.radians(2.0))
    for trial in range(8):
        home = Pose2D(rng.uniform(-2.5, 2.5), rng.uniform(-1.5, 1.5), rng.uniform(-math.pi, math.pi))
        away = Pose2D(rng.uniform(-2.5, 2.5), rng.uniform(-1.5, 1.5), rng.uniform(-math.pi, math.pi))
        loc = localizer(name, seed=trial, initial_pose=home)
        for _ in range(3):
            loc.localize(oracle_percepts(home, rng, *noise))
        assert _error(loc.localize(oracle_percepts(home, rng, *noise)), home)[0] < 0.3
        turn = Displacement(0.0, 0.0, math.radians(40))
        for scan in range(1, KIDNAP_SCANS + 1):  # teleported to ``away``; it turns in place between scans
            away = compose(away, turn)
            loc.move(turn)
            estimate = loc.localize(oracle_percepts(away, rng, *noise))
            position, heading = _error(estimate, away)
            if position < 0.25 and heading < math.radians(10):
                break
        else:
            pytest.fail(f"trial {trial}: not recovered after {KIDNAP_SCANS} scans: {position:.2f} m, {heading:.2f} rad")


@pytest.mark.parametrize("name", FILTERS)
def test_particle_filter_is_deterministic_for_a_seed(name):
    rng = np.random.default_rng(2)
    scans = [oracle_percepts(Pose2D(0.3, -0.4, 0.2 * k), rng, 0.05, 0.03) for k in range(4)]

    def run(seed):
        loc = localizer(name, seed=seed, initial_pose=Pose2D(0.3, -0.4, 0.0))
        found = []
        for percepts in scans:
            loc.move(Displacement(0.0, 0.0, 0.2))
            found.append(loc.localize(percepts))
        return found

    assert run(5) == run(5)


def test_odometry_alone_ignores_the_percepts():
    start = Pose2D(2.0, -1.0, -2.0)
    loc = localizer("odometry", initial_pose=start)
    loc.move(Displacement(0.25, 0.0, 0.0))
    estimate = loc.localize(oracle_percepts(Pose2D(0.0, 0.0, 0.0), None))
    assert estimate.pose == compose(start, Displacement(0.25, 0.0, 0.0))
    assert estimate.source is EstimateSource.ODOMETER
