"""Landmark disambiguation (thesis 5.2): every corner and junction placed where a robot in the field sees it."""

from __future__ import annotations

import dataclasses
import math
from collections import Counter

import numpy as np
import pytest
from hypothesis import given, settings

from agents.localization.disambiguation import (
    CORNER_POST_MAX_ANGLE_RAD,
    corner_table,
    disambiguate,
    junction_table,
    resolve,
    unique_landmark,
)
from agents.vision.percepts import CornerShape, LandmarkPercept, PostSide
from tests.oracle_percepts import oracle_percepts
from tests.strategies import field_pose
from world.field import FIELD, LandmarkId, LandmarkKind, Pose2D, normalize_angle

AMBIGUOUS = (LandmarkKind.L_CORNER, LandmarkKind.T_JUNCTION)


def _true_landmark(pose: Pose2D, percept: LandmarkPercept) -> LandmarkId:
    """The landmark of ``percept``'s kind nearest the field point it shows from ``pose``."""
    c, s = math.cos(pose.theta), math.sin(pose.theta)
    fx = pose.x + c * percept.x_m - s * percept.y_m
    fy = pose.y + s * percept.x_m + c * percept.y_m
    same = [lm for lm in FIELD.landmarks if lm.kind is percept.kind]
    return min(same, key=lambda lm: math.hypot(lm.x - fx, lm.y - fy)).id


def _posts(percepts):
    return [(p, unique_landmark(p)) for p in percepts if p.kind is LandmarkKind.GOAL_POST and p.landmark_id]


def _nearest_post(percept, posts) -> LandmarkId:
    return min(posts, key=lambda item: abs(normalize_angle(percept.bearing_rad - item[0].bearing_rad)))[1].id


def test_the_thesis_example_up_corner_nearest_the_blue_left_post_is_at_minus3_minus2():
    corner = FIELD.landmark(corner_table()[(LandmarkId.BLUE_GOAL_LEFT_POST, CornerShape.UP)][0])
    assert (corner.x, corner.y) == (-3.0, -2.0)
    assert corner.id is LandmarkId.FIELD_CORNER_BLUE_LEFT


def test_the_table_covers_every_post_and_shape_and_every_corner():
    table = corner_table()
    posts = [lm.id for lm in FIELD.landmarks if lm.kind is LandmarkKind.GOAL_POST]
    assert set(table) == {(post, shape) for post in posts for shape in CornerShape}
    corners = {lm.id for lm in FIELD.landmarks if lm.kind is LandmarkKind.L_CORNER}
    assert {ids[0] for ids in table.values()} == corners
    for (post, _), ids in table.items():
        assert all(FIELD.landmark(i).goal is FIELD.landmark(post).goal for i in ids)
    for post, junctions in junction_table().items():
        assert len(junctions) == 1
        assert math.copysign(1, FIELD.landmark(junctions[0]).y) == math.copysign(1, FIELD.landmark(post).y)


@settings(max_examples=300, deadline=None)
@given(field_pose)
def test_every_placed_corner_and_junction_is_the_one_seen(pose):
    percepts = oracle_percepts(pose, None)
    posts = _posts(percepts)
    for percept in percepts:
        if percept.kind in AMBIGUOUS:
            landmark = resolve(percept, posts)
            assert landmark is None or landmark.id is _true_landmark(pose, percept)
    placed = {o.landmark_id for o in disambiguate(percepts)}
    assert placed <= {_true_landmark(pose, p) for p in percepts}


@pytest.fixture(scope="module")
def sighting_sample():
    """(nearest post, shape, placed landmark, true landmark) of every corner and junction placed from 1500 poses."""
    rng = np.random.default_rng(7)
    found = []
    for _ in range(1500):
        pose = Pose2D(rng.uniform(-3.0, 3.0), rng.uniform(-2.0, 2.0), rng.uniform(-math.pi, math.pi))
        percepts = oracle_percepts(pose, None)
        posts = _posts(percepts)
        for percept in percepts:
            if percept.kind in AMBIGUOUS and posts:
                landmark = resolve(percept, posts)
                if landmark is not None:
                    found.append((_nearest_post(percept, posts), percept.corner, landmark.id, _true_landmark(pose, percept)))
    return found


def test_every_table_entry_is_seen_and_placed_right(sighting_sample):
    assert all(placed is truth for _, _, placed, truth in sighting_sample)
    corner_entries = {(post, shape) for post, shape, _, _ in sighting_sample if shape is not None}
    assert corner_entries == set(corner_table())
    junction_entries = {post for post, shape, placed, _ in sighting_sample if shape is None}
    assert junction_entries == set(junction_table())
    placed = Counter(placed for _, _, placed, _ in sighting_sample)
    assert set(placed) == {lm.id for lm in FIELD.landmarks if lm.kind in AMBIGUOUS}


def test_thesis_table_alone_misplaces_goal_area_corners_seen_from_inside_the_goal_area():
    pose = Pose2D(2.7, 0.0, 2.0)  # inside the yellow goal area, facing its left goal-area corner
    percepts = oracle_percepts(pose, None)
    corner = next(p for p in percepts if p.kind is LandmarkKind.L_CORNER and _true_landmark(pose, p).name.startswith("GOAL_AREA"))
    assert corner.corner is CornerShape.UP
    posts = _posts(percepts)
    assert resolve(corner, posts, check_separation=False).id is LandmarkId.FIELD_CORNER_YELLOW_LEFT
    assert resolve(corner, posts).id is LandmarkId.GOAL_AREA_CORNER_YELLOW_LEFT


def _percept(kind, bearing, distance, **fields):
    return LandmarkPercept(kind, (0.0, 0.0), bearing, distance, "test", **fields)


def test_no_post_no_corner_and_posts_of_unknown_side_do_not_count():
    corner = _percept(LandmarkKind.L_CORNER, 0.2, 3.6, corner=CornerShape.UP)
    lone = _percept(LandmarkKind.GOAL_POST, 0.1, 3.1, goal=FIELD.landmarks[2].goal, post_side=PostSide.UNKNOWN)
    assert disambiguate([corner]) == ()
    assert disambiguate([corner, lone]) == ()


def test_a_corner_beyond_51_degrees_from_every_post_is_rejected():
    post = _percept(LandmarkKind.GOAL_POST, 0.3, 3.0, landmark_id=LandmarkId.YELLOW_GOAL_LEFT_POST, post_side=PostSide.PAIR)
    posts = [(post, FIELD.landmark(LandmarkId.YELLOW_GOAL_LEFT_POST))]
    for side in (1.0, -1.0):
        inside = _percept(LandmarkKind.L_CORNER, 0.3 + side * (CORNER_POST_MAX_ANGLE_RAD - 0.01), 3.0, corner=CornerShape.UP)
        beyond = dataclasses.replace(inside, bearing_rad=0.3 + side * (CORNER_POST_MAX_ANGLE_RAD + 0.01))
        assert resolve(inside, posts, check_separation=False).id is LandmarkId.FIELD_CORNER_YELLOW_LEFT
        assert resolve(beyond, posts, check_separation=False) is None
        assert disambiguate([post, beyond]) == disambiguate([post])


def test_unique_landmarks_are_placed_directly():
    pose = Pose2D(1.0, 0.5, 0.1)
    percepts = oracle_percepts(pose, None)
    observations = {o.landmark_id: o for o in disambiguate(percepts)}
    for percept in percepts:
        if percept.landmark_id is not None:
            observation = observations[percept.landmark_id]
            landmark = FIELD.landmark(percept.landmark_id)
            assert (observation.x_m, observation.y_m) == (landmark.x, landmark.y)
            assert (observation.distance_m, observation.bearing_rad) == (percept.distance_m, percept.bearing_rad)
