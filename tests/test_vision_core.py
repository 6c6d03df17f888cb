"""Vision pipeline: input checks, camera models, field border (Algorithm 1), goals, head scan."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pybullet as pb
import pytest

from agents.vision.border import border_line_from_left, find_border
from agents.vision.camera_models import ExactCameraModel, ThesisCameraModel, camera_model, level_rotation
from agents.vision.colors import ColorClass
from agents.vision.errors import VisionConfigError, VisionInputError
from agents.vision.frame import CameraFrame
from agents.vision.goals import detect_goals
from agents.vision.head_scan import SCAN_PITCH_RAD as PITCH_17
from agents.vision.head_scan import HeadScan, fuse_percepts, scan_coverage_rad
from agents.vision.percepts import LandmarkPercept, PostSide
from agents.vision.pipeline import VisionPipeline
from match.protocol import observation_space
from world.camera_model import NAO_CAMERA, CameraPosition, world_to_camera
from world.field import FIELD, GoalColor, LandmarkId, LandmarkKind, Pose2D


@pytest.fixture(scope="module")
def pipeline():
    return VisionPipeline("exact")


def blank(rgb=(0, 0, 0)) -> np.ndarray:
    image = np.empty((120, 160, 3), np.uint8)
    image[:] = rgb
    return image


def frame_of(world, robot="a") -> CameraFrame:
    s = world.sensors(robot)
    return CameraFrame(world.render_camera(robot), s.head_yaw_rad, s.head_pitch_rad, s.camera, s.accelerometer_mps2)


def look(world, pose: Pose2D, yaw_rad: float, pitch_rad: float = PITCH_17, robot="a") -> CameraFrame:
    world.place_robot("b" if robot == "a" else "a", Pose2D(0.0, -3.2, 0.0))  # the other robot off the field
    world.place_robot(robot, pose)
    world.set_head(robot, yaw_rad, pitch_rad)
    world.step(15)
    return frame_of(world, robot)


def truth_of(world, landmark_id: LandmarkId, robot="a") -> tuple[float, float]:
    """True (bearing rad, distance m) of a landmark from the robot."""
    pose = world.robot_pose(robot)
    lm = FIELD.landmark(landmark_id)
    dx, dy = lm.x - pose.x, lm.y - pose.y
    return math.remainder(math.atan2(dy, dx) - pose.theta, 2 * math.pi), math.hypot(dx, dy)


# ---- bad input ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    "image",
    [np.zeros((120, 160), np.uint8), np.zeros((120, 160, 3), np.float32), np.zeros((160, 120, 3), np.uint8), [[0]]],
    ids=["grey", "float", "transposed", "list"],
)
def test_frames_of_the_wrong_shape_or_type_are_refused(image):
    with pytest.raises(VisionInputError, match="image must be"):
        CameraFrame(image, 0.0, 0.0)


@pytest.mark.parametrize("yaw, pitch", [(math.nan, 0.0), (0.0, math.inf), ("0", 0.0)])
def test_non_finite_head_angles_are_refused(yaw, pitch):
    with pytest.raises(VisionInputError, match="head_"):
        CameraFrame(blank(), yaw, pitch)


def test_bad_accelerometer_and_camera_are_refused():
    with pytest.raises(VisionInputError, match="accelerometer"):
        CameraFrame(blank(), 0.0, 0.0, CameraPosition.TOP, (0.0, math.nan, 9.8))
    with pytest.raises(VisionInputError, match="camera"):
        CameraFrame(blank(), 0.0, 0.0, "top")


def test_observation_with_the_camera_off_is_refused():
    space = observation_space()
    space.seed(0)
    obs = space.sample()
    obs.update(image=blank(), head=np.zeros(2, np.float32), camera=0, accelerometer=np.array([0, 0, 9.81], np.float32))
    with pytest.raises(VisionInputError, match="camera is off"):
        CameraFrame.from_observation(obs)
    obs["camera"] = 1
    assert CameraFrame.from_observation(obs).camera is CameraPosition.TOP
    with pytest.raises(VisionInputError, match="lacks"):
        CameraFrame.from_observation({"image": blank()})


@pytest.mark.parametrize(
    "rgb", [(0, 0, 0), (255, 255, 255), (36, 123, 43), (20, 40, 230), (200, 180, 20)], ids=str
)
def test_frames_of_one_colour_give_no_percepts(pipeline, rgb):
    result = pipeline.process(CameraFrame(blank(rgb), 0.0, PITCH_17))
    assert result.percepts == ()


def test_noise_frames_do_not_crash(pipeline):
    rng = np.random.default_rng(0)
    for _ in range(20):
        image = rng.integers(0, 256, (120, 160, 3), dtype=np.uint8)
        result = pipeline.process(CameraFrame(image, float(rng.uniform(-2, 2)), float(rng.uniform(-0.6, 0.5))))
        assert all(math.isfinite(p.distance_m) and math.isfinite(p.bearing_rad) for p in result.percepts)


def test_unknown_camera_model_is_refused():
    with pytest.raises(VisionConfigError, match="'fisheye'"):
        camera_model("fisheye")
    with pytest.raises(TypeError, match="CameraFrame"):
        VisionPipeline().process(blank())


# ---- camera models -----------------------------------------------------------------------


@pytest.mark.parametrize("yaw_deg", [-80, -40, 0, 25, 80])
@pytest.mark.parametrize("pitch_deg", [17, 25])
def test_the_two_models_agree_at_the_image_centre(yaw_deg, pitch_deg):
    frame = CameraFrame(blank(), math.radians(yaw_deg), math.radians(pitch_deg))
    u, v = 79.5, 59.5  # the image centre in pixel-index coordinates
    exact = ExactCameraModel().locate(frame, u, v)
    thesis = ThesisCameraModel().locate(frame, u, v)
    assert float(exact.bearing_rad) == pytest.approx(math.radians(yaw_deg), abs=1e-9)
    assert float(thesis.bearing_rad) == pytest.approx(math.radians(yaw_deg), abs=1e-9)
    # The thesis puts the camera 0.51 m up on the neck axis; the exact model 0.05 m ahead of it.
    assert float(thesis.distance_m) == pytest.approx(float(exact.distance_m), rel=0.08)


def test_pixels_above_the_horizon_have_no_ground_point():
    frame = CameraFrame(blank(), 0.0, 0.0)
    for model in (ExactCameraModel(), ThesisCameraModel()):
        points = model.locate(frame, np.array([80.0, 80.0]), np.array([5.0, 110.0]))
        assert not points.valid[0] and points.valid[1]


def test_level_rotation_undoes_a_tilt():
    tilt = math.radians(12.0)
    up_in_torso = (-math.sin(tilt) * 9.81, 0.0, math.cos(tilt) * 9.81)  # leaning forward
    rotation = level_rotation(up_in_torso)
    assert rotation @ np.asarray(up_in_torso) / 9.81 == pytest.approx([0.0, 0.0, 1.0], abs=1e-9)
    assert level_rotation((0.3, -0.2, 9.8)) == pytest.approx(np.eye(3))  # standing sway: ignored
    assert level_rotation((0.0, 0.0, 30.0)) == pytest.approx(np.eye(3))  # shaken: not gravity


@pytest.mark.render
def test_exact_model_matches_rendered_geometry_within_one_pixel(world):
    """A ground point projected by the exact model lands where the renderer drew it.

    The model is given the torso's true tilt as a noise-free accelerometer would read it (a
    standing robot sways by a few tenths of a degree, 1 px, below the real one's noise).
    """
    model = ExactCameraModel(min_tilt_rad=0.0)
    for pose, yaw in [(Pose2D(1.2, 0.3, 0.1), 0.2), (Pose2D(-0.5, -0.8, 2.5), -0.6)]:
        frame = look(world, pose, yaw)
        _, orientation = pb.getBasePositionAndOrientation(world.body_id("a"), physicsClientId=world.client)
        m = pb.getMatrixFromQuaternion(orientation)
        frame = dataclasses.replace(frame, accelerometer_mps2=(9.81 * m[6], 9.81 * m[7], 9.81 * m[8]))
        truth = world.robot_pose("a")
        rotation, position = world.camera_pose("a")
        angles = [truth.theta + yaw + dy for dy in (-0.2, 0.0, 0.2)]
        points = np.array([[truth.x + 1.5 * math.cos(a), truth.y + 1.5 * math.sin(a), 0.0] for a in angles])
        rendered = NAO_CAMERA.project(world_to_camera(points, rotation, position))
        c, s = math.cos(truth.theta), math.sin(truth.theta)
        local = points[:, :2] - [truth.x, truth.y]
        torso = np.stack([c * local[:, 0] + s * local[:, 1], -s * local[:, 0] + c * local[:, 1], np.zeros(3)], 1)
        predicted = model.project(frame, torso)
        assert np.abs(predicted - rendered).max() <= 1.0, (predicted, rendered)


# ---- field border ------------------------------------------------------------------------


def test_border_follows_a_sloping_edge_and_ignores_an_obstacle():
    labels = np.full((120, 160), int(ColorClass.WHITE), np.uint8)
    rows = np.clip(30 + (np.arange(160) * 0.15).astype(int), 0, 119)
    for u, r in enumerate(rows):
        labels[r:, u] = int(ColorClass.GREEN)
    labels[:70, 60:70] = int(ColorClass.WHITE)  # a robot standing in front of the edge
    border = find_border(labels)
    assert border.found
    assert border.row_at(np.array([0.0, 150.0])) == pytest.approx([30, 52.5], abs=1.5)
    ignored = border.columns[(border.rows < 0) & (border.columns < 155)]  # the last dot is never examined
    assert set(ignored) == {c for c in border.columns if 60 <= c < 70}
    assert border.row_at(65.0) == pytest.approx(30 + 65 * 0.15, abs=1.5)


def test_algorithm_1_loses_a_steep_edge_after_an_obstacle():
    """As written, Algorithm 1 compares with the last kept dot: a slope drifts past the threshold."""
    labels = np.full((120, 160), int(ColorClass.WHITE), np.uint8)
    for u in range(160):
        labels[30 + int(u * 0.4) :, u] = int(ColorClass.GREEN)
    labels[:90, 60:70] = int(ColorClass.WHITE)
    border = find_border(labels)
    assert border.found and (border.rows[border.columns > 75] == -1).all()


def test_no_green_means_no_border():
    assert not find_border(np.full((120, 160), int(ColorClass.WHITE), np.uint8)).found


def test_algorithm_1_rejects_scattered_dots_early():
    rng = np.random.default_rng(1)
    heights = rng.integers(0, 120, 54)
    found, _ = border_line_from_left(heights, 0)
    assert not found
    smooth = np.full(54, 40)
    found, line = border_line_from_left(smooth, 0)
    assert found and (line[:-1] == 40).all()


def test_algorithm_1_marks_jumps_and_stops_past_the_rejection_percentage():
    heights = np.full(20, 50)
    heights[5] = 90
    found, line = border_line_from_left(heights, 0)
    assert found and line[5] == -1 and (np.delete(line, 5)[:-1] == 50).all()
    heights[4:19] = 100  # most dots jump away from the first ones
    found, _ = border_line_from_left(heights, 0, rejection_percentage=0.5)
    assert not found


@pytest.mark.render
def test_a_frame_looking_at_the_sky_has_no_border(world, pipeline):
    frame = look(world, Pose2D(0.0, 0.0, 0.0), 0.0, math.radians(-38.0))
    result = pipeline.process(frame)
    assert not result.border.found and result.percepts == ()


# ---- goals -------------------------------------------------------------------------------


def _assert_close(percept: LandmarkPercept, bearing: float, distance: float) -> None:
    assert math.degrees(abs(math.remainder(percept.bearing_rad - bearing, 2 * math.pi))) <= 2.0
    assert percept.distance_m == pytest.approx(distance, rel=0.10)


@pytest.mark.render
@pytest.mark.parametrize("model", ["exact", "thesis"])
@pytest.mark.parametrize(
    "pose, yaw, goal",
    [(Pose2D(0.5, 0.0, 0.0), 0.0, GoalColor.YELLOW), (Pose2D(-0.3, 0.3, math.pi), 0.1, GoalColor.BLUE)],
)
def test_both_posts_and_the_goal_centre_at_known_poses(world, model, pose, yaw, goal):
    frame = look(world, pose, yaw)
    percepts = VisionPipeline(model).process(frame).percepts
    found = {p.landmark_id: p for p in percepts if p.goal is goal}
    for side in ("LEFT_POST", "RIGHT_POST", "CENTER"):
        landmark = LandmarkId[f"{goal.name}_GOAL_{side}"]
        assert landmark in found, (side, percepts)
        _assert_close(found[landmark], *truth_of(world, landmark))
    assert found[LandmarkId[f"{goal.name}_GOAL_LEFT_POST"]].post_side is PostSide.PAIR


@pytest.mark.render
def test_the_goals_back_frame_is_not_taken_for_a_post(world, pipeline):
    """Seen from the side, the goal's thin back frame stands beside the near post."""
    frame = look(world, Pose2D(1.4, -1.4, 0.55), 0.0)
    result = pipeline.process(frame)
    posts = [p for p in result.percepts if p.kind is LandmarkKind.GOAL_POST]
    assert posts and all(p.goal is GoalColor.YELLOW for p in posts)
    for post in posts:
        candidates = [lm.id for lm in FIELD.landmarks if lm.kind is LandmarkKind.GOAL_POST and lm.goal is post.goal]
        errors = [abs(post.distance_m - truth_of(world, c)[1]) / truth_of(world, c)[1] for c in candidates]
        assert min(errors) <= 0.1
    assert any(b.rejected for b in result.goals.posts)


@pytest.mark.render
def test_a_back_upright_seen_alone_is_not_taken_for_a_post(world, pipeline):
    """Beside the blue goal, looking across it: the near post's base is below the image, the far
    post is out of it on the right, and the far post's back upright (0.04 m, 2.5 m away: 5 pixels
    where a post would be 7.4) is the one goal-coloured column standing on the carpet."""
    frame = look(world, Pose2D(-2.26, -1.45, math.radians(105.0)), math.radians(32.0), math.radians(1.0))
    result = pipeline.process(frame)
    assert not [p for p in result.percepts if p.kind is LandmarkKind.GOAL_POST]
    thin = [b for b in result.goals.posts if b.rejected == "too thin for a post at its distance"]
    assert any(b.core_width_px >= 5 for b in thin)  # over 0.65 of a post's 7.4 pixels: kept as a post before


def _post_scene(model, base_row: int = 60, column: int = 80) -> tuple[np.ndarray, CameraFrame, int, int]:
    """Labels of a yellow post standing on the carpet, sized for the distance its base pixel gives:
    (labels, frame, width px, height px)."""
    frame = CameraFrame(blank(), 0.0, PITCH_17)
    distance = float(model.locate(frame, np.array([column]), np.array([base_row + 0.5])).distance_m[0])
    width = max(3, round(FIELD.goal_post_diameter / distance * NAO_CAMERA.focal_px))
    height = round(FIELD.goal_height / distance * NAO_CAMERA.focal_px * 0.8)
    labels = np.full((120, 160), int(ColorClass.GREEN), np.uint8)
    labels[:20] = int(ColorClass.WHITE)  # the hall above the field
    left = column - width // 2
    labels[max(0, base_row - height + 1) : base_row + 1, left : left + width] = int(ColorClass.YELLOW)
    return labels, frame, width, height


@pytest.mark.parametrize("model", ["exact", "thesis"])
def test_a_post_seen_whole_is_kept_and_one_whose_base_a_robot_hides_is_not(model):
    """A robot in front hides the post's base: its lowest visible pixel lies on the robot, not on the
    carpet, and the distance from it would be metres too long."""
    camera = camera_model(model)
    labels, frame, width, _ = _post_scene(camera)
    percepts, trace = detect_goals(labels, frame, camera)
    assert [p.kind for p in percepts] == [LandmarkKind.GOAL_POST] and not trace.posts[0].rejected
    labels[61:100, 60:100] = int(ColorClass.WHITE)  # a robot's body right under the base
    labels[50:61, 60:100] = int(ColorClass.WHITE)  # ... and over the post's lower part
    percepts, trace = detect_goals(labels, frame, camera)
    assert percepts == () and [p.rejected for p in trace.posts] == ["base hidden: no carpet below it"]


@pytest.mark.parametrize("model", ["exact", "thesis"])
def test_the_goals_ground_frame_seen_along_and_a_short_piece_of_it_are_not_posts(model):
    camera = camera_model(model)
    labels, frame, width, _ = _post_scene(camera)
    labels[labels == int(ColorClass.YELLOW)] = int(ColorClass.GREEN)
    labels[50:61, 30:150] = int(ColorClass.YELLOW)  # a wide band: the frame's side bar from close by
    percepts, trace = detect_goals(labels, frame, camera)
    assert percepts == () and [p.rejected for p in trace.posts] == ["too wide for a post at its distance"]
    labels[50:61, :] = int(ColorClass.GREEN)
    labels[55:61, 80 : 80 + width] = int(ColorClass.YELLOW)  # a post's width, six rows: far too short
    percepts, trace = detect_goals(labels, frame, camera)
    assert percepts == () and [p.rejected for p in trace.posts] == ["too short for a post at its distance"]


@pytest.mark.render
def test_head_scan_finds_a_lone_posts_side_by_tilting_up(world, pipeline):
    world.place_robot("b", Pose2D(0.0, -3.2, 0.0))
    world.place_robot("a", Pose2D(1.8, 0.2, 0.0))
    world.step(5)
    scan = HeadScan(pipeline)
    targets = []
    for _ in range(300):
        if scan.done:
            break
        target = scan.target
        targets.append(target.purpose)
        world.set_head("a", target.yaw_rad, target.pitch_rad)
        world.step(1)
        scan.feed(frame_of(world))
    assert scan.done and "crossbar" in targets
    result = scan.result()
    assert len(result.frames) == 5
    posts = {p.landmark_id: p for p in result.percepts if p.kind is LandmarkKind.GOAL_POST}
    for landmark in (LandmarkId.YELLOW_GOAL_LEFT_POST, LandmarkId.YELLOW_GOAL_RIGHT_POST):
        assert landmark in posts
        _assert_close(posts[landmark], *truth_of(world, landmark))
    assert any(p.post_side is PostSide.CROSSBAR for p in posts.values())


def test_scan_covers_about_206_degrees_and_refuses_bad_plans(pipeline):
    assert math.degrees(scan_coverage_rad()) == pytest.approx(206.0)
    with pytest.raises(VisionConfigError, match="yaws"):
        HeadScan(pipeline, yaws_rad=(3.0,))
    with pytest.raises(VisionConfigError, match="pitch"):
        HeadScan(pipeline, pitch_rad=1.2)


def test_a_scan_skips_frames_taken_while_the_head_moves(pipeline):
    scan = HeadScan(pipeline)
    target = scan.target
    assert not scan.feed(CameraFrame(blank(), target.yaw_rad - 0.2, target.pitch_rad))
    assert not scan.feed(CameraFrame(blank(), target.yaw_rad, target.pitch_rad))  # settling
    assert not scan.feed(CameraFrame(blank(), target.yaw_rad, target.pitch_rad))
    assert scan.feed(CameraFrame(blank(), target.yaw_rad, target.pitch_rad))
    assert scan.target.yaw_rad != target.yaw_rad


def _percept(bearing_deg, distance, kind=LandmarkKind.GOAL_POST, landmark=None, goal=GoalColor.BLUE, side=None):
    return LandmarkPercept(kind, (0.0, 0.0), math.radians(bearing_deg), distance, "exact", landmark, goal, post_side=side)


def test_fusion_merges_one_landmark_seen_twice_and_keeps_others_apart():
    left = LandmarkId.BLUE_GOAL_LEFT_POST
    fused = fuse_percepts(
        [
            _percept(10.0, 2.0, landmark=left, side=PostSide.PAIR),
            _percept(12.0, 2.1, side=PostSide.UNKNOWN),  # the same post, side unknown in that frame
            _percept(40.0, 2.0, landmark=LandmarkId.BLUE_GOAL_RIGHT_POST, side=PostSide.PAIR),
            _percept(11.0, 2.0, kind=LandmarkKind.L_CORNER, goal=None),
        ]
    )
    assert len(fused) == 3
    post = next(p for p in fused if p.landmark_id is left)
    assert post.frames == 2 and post.post_side is PostSide.PAIR
    assert math.degrees(post.bearing_rad) == pytest.approx(11.0, abs=0.2)
    assert post.distance_m == pytest.approx(2.05, abs=0.01)


def test_fusion_drops_non_finite_percepts_and_keeps_distinct_ids_apart():
    left, right = LandmarkId.BLUE_GOAL_LEFT_POST, LandmarkId.BLUE_GOAL_RIGHT_POST
    fused = fuse_percepts([_percept(10.0, 2.0, landmark=left), _percept(10.5, 2.0, landmark=right), _percept(0.0, math.nan)])
    assert {p.landmark_id for p in fused} == {left, right}
