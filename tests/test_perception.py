"""``robotstadium perception``: scoring of percepts against truth, and a short real run."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from agents.vision.percepts import LandmarkPercept
from scenarios import cli
from scenarios.perception.records import CROWD_ORDER, FrameSetup, PerceptionConfig, PerceptionConfigError
from scenarios.perception.run import (
    MEASURED,
    MIN_SEPARATION_M,
    TIMING_KEYS,
    park_others,
    roster,
    run_perception,
    sample_setup,
    stage_frame,
)
from scenarios.perception.scoring import (
    MAX_GATE_M,
    STAT_KEYS,
    TrueLandmark,
    gate_m,
    kind_statistics,
    match_frame,
)
from world.field import FIELD, LandmarkId, LandmarkKind, Pose2D
from scenarios.perception.truth import to_torso, true_landmarks
from world.config import WorldConfig
from world.world import World

KIND_VALUES = {k.value for k in LandmarkKind}


# ---- scoring on synthetic percepts -----------------------------------------------------------


def _truths(pose: Pose2D, visible: set[LandmarkId] | None = None) -> tuple[TrueLandmark, ...]:
    found = []
    for lm in FIELD.landmarks:
        x, y = to_torso(pose, lm.x, lm.y)
        found.append(TrueLandmark(lm, float(x), float(y), visible is None or lm.id in visible))
    return tuple(found)


def _percept_of(truth: TrueLandmark, *, with_id: bool = True, d_scale: float = 1.0, db: float = 0.0) -> LandmarkPercept:
    lm = truth.landmark
    has_goal = lm.kind in (LandmarkKind.GOAL_POST, LandmarkKind.GOAL_CENTER)
    identified = with_id and (has_goal or lm.kind is LandmarkKind.CENTER_CIRCLE)
    return LandmarkPercept(
        lm.kind, (80.0, 60.0), truth.bearing_rad + db, truth.distance_m * d_scale, "exact",
        landmark_id=lm.id if identified else None, goal=lm.goal if has_goal else None,
    )


def _truth(truths, landmark_id: LandmarkId) -> TrueLandmark:
    return next(t for t in truths if t.landmark.id is landmark_id)


poses = st.builds(
    Pose2D,
    st.floats(-3.0, 3.0),
    st.floats(-2.0, 2.0),
    st.floats(-math.pi, math.pi),
)


@settings(max_examples=60, deadline=None)
@given(pose=poses, index=st.integers(0, len(FIELD.landmarks) - 1), with_id=st.booleans())
def test_an_exact_percept_is_a_true_positive_with_zero_error(pose: Pose2D, index: int, with_id: bool) -> None:
    truths = _truths(pose)
    truth = truths[index]
    score = match_frame([_percept_of(truth, with_id=with_id)], truths)
    (scored,) = score.percepts
    assert scored.matched
    assert scored.truth.landmark.id is truth.landmark.id  # landmarks of one kind lie >= 1.08 m apart
    assert scored.distance_error_m == pytest.approx(0.0, abs=1e-9)
    assert scored.bearing_error_rad == pytest.approx(0.0, abs=1e-9)


def test_a_percept_naming_the_wrong_post_is_a_false_positive() -> None:
    truths = _truths(Pose2D(-1.0, 0.5, math.pi))  # facing the blue goal from 2 m
    right = _truth(truths, LandmarkId.BLUE_GOAL_RIGHT_POST)
    seen = _percept_of(right)
    wrong = LandmarkPercept(seen.kind, seen.pixel, seen.bearing_rad, seen.distance_m, "exact",
                            landmark_id=LandmarkId.BLUE_GOAL_LEFT_POST, goal=seen.goal)
    assert not match_frame([wrong], truths).percepts[0].matched
    wrong_colour = LandmarkPercept(seen.kind, seen.pixel, seen.bearing_rad, seen.distance_m, "exact",
                                   goal=seen.goal.other)
    assert not match_frame([wrong_colour], truths).percepts[0].matched
    # The same position with the side unknown matches the right post.
    unknown = LandmarkPercept(seen.kind, seen.pixel, seen.bearing_rad, seen.distance_m, "exact", goal=seen.goal)
    assert match_frame([unknown], truths).percepts[0].truth.landmark.id is LandmarkId.BLUE_GOAL_RIGHT_POST


@settings(max_examples=40, deadline=None)
@given(pose=poses, far=st.floats(1.1, 3.0))
def test_a_percept_far_from_every_compatible_landmark_is_a_false_positive(pose: Pose2D, far: float) -> None:
    truths = _truths(pose)
    t = _truth(truths, LandmarkId.T_JUNCTION_LEFT)
    # Move the T junction's estimate sideways by more than the largest gate.
    x, y = t.x_m + far * MAX_GATE_M * -math.sin(t.bearing_rad), t.y_m + far * MAX_GATE_M * math.cos(t.bearing_rad)
    shifted = LandmarkPercept(LandmarkKind.T_JUNCTION, (0.0, 0.0), math.atan2(y, x), math.hypot(x, y), "exact")
    other = _truth(truths, LandmarkId.T_JUNCTION_RIGHT)
    if math.hypot(x - other.x_m, y - other.y_m) <= gate_m(other.distance_m):
        return  # landed on the other T junction: a legitimate match
    assert not match_frame([shifted], truths).percepts[0].matched


def test_one_landmark_is_matched_once_and_the_nearer_percept_wins() -> None:
    truths = _truths(Pose2D(0.0, 0.0, 0.0))
    circle = _truth(truths, LandmarkId.CENTER_CIRCLE)
    post = _truth(truths, LandmarkId.YELLOW_GOAL_LEFT_POST)
    near = _percept_of(post, d_scale=1.01)
    farther = _percept_of(post, d_scale=1.1)
    score = match_frame([farther, near], truths)
    assert [s.matched for s in score.percepts] == [False, True]
    assert circle.distance_m == 0.0


def test_recall_counts_only_visible_landmarks_and_errors_only_within_range() -> None:
    pose = Pose2D(-1.0, 0.0, math.pi)
    visible = {LandmarkId.BLUE_GOAL_LEFT_POST, LandmarkId.BLUE_GOAL_RIGHT_POST, LandmarkId.BLUE_GOAL_CENTER}
    truths = _truths(pose, visible)
    post = _truth(truths, LandmarkId.BLUE_GOAL_LEFT_POST)
    far_post = _truth(truths, LandmarkId.YELLOW_GOAL_LEFT_POST)  # 4 m behind, not visible
    percepts = [_percept_of(post, d_scale=1.1), _percept_of(far_post, d_scale=1.05)]
    stats = kind_statistics([match_frame(percepts, truths)], max_range_m=3.0)
    posts = stats["goal_post"]
    assert posts["detections"] == 2 and posts["precision"] == 1.0
    assert posts["visible"] == 2 and posts["matched"] == 1 and posts["recall"] == 0.5
    assert posts["distance_error_rel_median"] == pytest.approx(0.1)  # the far post's error is out of range
    assert stats["goal_center"]["recall"] == 0.0 and stats["goal_center"]["precision"] is None
    assert stats["l_corner"]["visible"] == 0 and stats["l_corner"]["recall"] is None


def test_statistics_are_json_without_nan() -> None:
    stats = kind_statistics([], max_range_m=4.0)
    assert set(stats) == KIND_VALUES
    for kind_stats in stats.values():
        assert set(STAT_KEYS) <= set(kind_stats)
    json.dumps(stats, allow_nan=False)


@settings(max_examples=50, deadline=None)
@given(d=st.floats(0.0, 10.0))
def test_gate_grows_with_distance_and_is_capped(d: float) -> None:
    assert 0.5 <= gate_m(d) <= MAX_GATE_M
    assert gate_m(d) <= gate_m(d + 1.0)


# ---- frame setups ------------------------------------------------------------------------------


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), crowd=st.integers(0, 7))
def test_crowd_robots_stand_on_the_field_apart(seed: int, crowd: int) -> None:
    setup = sample_setup(np.random.default_rng(seed), crowd)
    points = [(setup.pose.x, setup.pose.y)] + [(p.x, p.y) for p in setup.crowd]
    assert len(setup.crowd) == crowd
    for i, (x, y) in enumerate(points):
        assert abs(x) <= FIELD.half_length and abs(y) <= FIELD.half_width
        for a, b in points[i + 1 :]:
            assert math.hypot(x - a, y - b) >= MIN_SEPARATION_M
    assert -80.0 - 1e-9 <= math.degrees(setup.head_yaw_rad) <= 80.0 + 1e-9


@pytest.mark.render
def test_a_staged_crowd_stands_apart_and_a_close_robot_hides_a_landmark() -> None:
    with World(roster(), seed=0) as world:
        park_others(world, 7)
        setup = sample_setup(np.random.default_rng(5), 7)
        stage_frame(world, setup)
        ids = (MEASURED, *CROWD_ORDER)
        points = [world.robot_truth(r).pose for r in ids]
        assert not any(world.robot_truth(r).fallen for r in ids)
        for i, a in enumerate(points):
            for b in points[i + 1 :]:
                assert math.hypot(a.x - b.x, a.y - b.y) >= MIN_SEPARATION_M - 0.02  # settling moves them mm
        # Looking at the T junction at (0, 2) from 2 m: visible, then hidden by a robot 0.6 m in front.
        park_others(world, 0)
        stage_frame(world, FrameSetup(Pose2D(0.0, 0.0, math.pi / 2), 0.0))
        assert _t_junction_left(world).visible
        stage_frame(world, FrameSetup(Pose2D(0.0, 0.0, math.pi / 2), 0.0, (Pose2D(0.0, 1.2, 0.0),)))
        assert not _t_junction_left(world).visible


@pytest.mark.render
def test_with_a_head_rate_the_frame_is_taken_while_the_head_turns_and_the_profile_smears_it() -> None:
    """The same staged frame in a clean world and under the robotstadium profile: with the head still, they
    differ by the profile's faint noise alone; turning at 2 rad/s, edges smear by several pixels."""
    setup = FrameSetup(Pose2D(0.0, 0.0, math.pi / 2), 0.0)
    smeared = {}
    for rate in (0.0, 2.0):
        images = {}
        for profile in ("clean", "robotstadium"):
            with World(roster(), WorldConfig(camera_profile=profile), seed=0) as world:
                park_others(world, 0)
                stage_frame(world, setup, rate)
                assert world.sensors(MEASURED).head_yaw_rad == pytest.approx(0.0, abs=1e-3)
                images[profile] = world.render_camera(MEASURED).astype(int)
        difference = np.abs(images["clean"] - images["robotstadium"]).max(axis=2)
        smeared[rate] = float(np.mean(difference > 12))  # far beyond the noise's 1.5 levels
    assert smeared[0.0] == 0.0
    assert smeared[2.0] > 0.01


def _t_junction_left(world: World) -> TrueLandmark:
    return next(t for t in true_landmarks(world, MEASURED, 4.0) if t.landmark.id is LandmarkId.T_JUNCTION_LEFT)


@pytest.mark.parametrize("kwargs", [{"frames": 0}, {"frames": 1, "crowd": 8}, {"frames": 1, "models": ("fisheye",)},
                                    {"frames": 1, "max_range_m": 0.0}, {"frames": 1, "head_rate_radps": -1.0},
                                    {"frames": 1, "head_rate_radps": 6.0}, {"frames": 1, "head_rate_radps": math.nan}])
def test_config_rejects_bad_values(kwargs: dict) -> None:
    with pytest.raises(PerceptionConfigError, match="got"):
        PerceptionConfig(**kwargs)


def test_cli_rejects_zero_frames_with_exit_2(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    with pytest.raises(SystemExit) as exit_info:
        cli.main(["perception", "--frames", "0", "--out", str(tmp_path)])
    assert exit_info.value.code == 2
    assert "argument --frames: expected an integer in [1, " in capsys.readouterr().err
    with pytest.raises(SystemExit) as exit_info:
        cli.main(["perception", "--frames", "2", "--crowd", "8", "--out", str(tmp_path)])
    assert exit_info.value.code == 2
    with pytest.raises(SystemExit) as exit_info:
        cli.main(["perception", "--frames", "1", "--examples", "-1", "--out", str(tmp_path), "--no-progress"])
    assert exit_info.value.code == 2
    with pytest.raises(SystemExit) as exit_info:
        cli.main(["perception", "--frames", "1", "--head-rate", "9", "--out", str(tmp_path), "--no-progress"])
    assert exit_info.value.code == 2
    assert "argument --head-rate: expected a number in [0, 5]" in capsys.readouterr().err


# ---- real runs -----------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def crowd_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("perception")
    args = ["perception", "--frames", "6", "--seed", "3", "--crowd", "4", "--out", str(out), "--no-progress"]
    assert cli.main(args) == 0
    return out


@pytest.mark.render
def test_a_short_run_writes_every_output_with_the_schema(crowd_run: Path) -> None:
    summary = json.loads((crowd_run / "summary.json").read_text())  # json.loads would accept NaN ...
    json.dumps(summary, allow_nan=False)  # ... this would not
    assert summary["frames"] == 6 and summary["crowd"] == 4
    assert summary["ms_per_frame_median"] > 0
    assert set(summary["models"]) == {"exact", "thesis"}
    for stats in summary["models"].values():
        assert set(stats) == KIND_VALUES
        for kind_stats in stats.values():
            assert set(STAT_KEYS) <= set(kind_stats)
            for key in ("precision", "recall"):
                assert kind_stats[key] is None or 0.0 <= kind_stats[key] <= 1.0
    table = (crowd_run / "table.md").read_text()
    assert "robotstadium perception --frames 6 --seed 3" in table
    assert table.count("| goal_post |") == 2
    with (crowd_run / "detections.csv").open() as handle:
        rows = list(csv.DictReader(handle))
    detections = sum(s["detections"] for stats in summary["models"].values() for s in stats.values())
    assert len(rows) == detections
    assert (crowd_run / "errors_vs_distance.png").stat().st_size > 10_000
    assert (crowd_run / "visible.csv").exists()


@pytest.mark.render
def test_the_same_seed_gives_the_same_summary(crowd_run: Path, tmp_path: Path) -> None:
    config = PerceptionConfig(frames=6, seed=3, crowd=4, progress=False, examples=0,
                              command="robotstadium perception --frames 6 --seed 3 --out X --crowd 4")
    again = run_perception(tmp_path, config)
    first = json.loads((crowd_run / "summary.json").read_text())
    again = json.loads(json.dumps(again))
    for summary in (first, again):
        for key in (*TIMING_KEYS, "command"):
            summary.pop(key)
    assert again == first
