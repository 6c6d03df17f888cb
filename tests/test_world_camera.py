"""The rendered image agrees with the pinhole model that world.camera_model exposes."""

from __future__ import annotations

import math

import numpy as np
import pytest

from world.camera_model import NAO_CAMERA, NAO_HEAD, CameraPosition, world_to_camera
from world.field import FIELD, LandmarkId, Pose2D

pytestmark = pytest.mark.render

def _ball_centroid(image: np.ndarray) -> tuple[float, float] | None:
    r, g, b = (image[:, :, k].astype(int) for k in range(3))
    mask = (r > 150) & (g * 10 > 4 * r) & (g * 10 < 7 * r) & (b < 40)  # orange: green 0.55 of red
    if mask.sum() < 4:
        return None
    rows, cols = np.nonzero(mask)
    return float(cols.mean()), float(rows.mean())


CASES = [
    # robot pose, head yaw/pitch (deg), camera, landmark looked at
    (Pose2D(-1.5, 0.2, 0.0), 0.0, 17.0, CameraPosition.TOP, LandmarkId.CENTER_CIRCLE),
    (Pose2D(1.0, 1.0, 0.3), -10.0, 17.0, CameraPosition.TOP, LandmarkId.GOAL_AREA_CORNER_YELLOW_LEFT),
    (Pose2D(0.5, -0.5, -2.0), 5.0, 10.0, CameraPosition.TOP, LandmarkId.T_JUNCTION_RIGHT),
    (Pose2D(-2.0, -1.0, math.pi), 40.0, 5.0, CameraPosition.TOP, LandmarkId.FIELD_CORNER_BLUE_LEFT),
    (Pose2D(-0.6, 0.1, 0.0), 0.0, 0.0, CameraPosition.BOTTOM, LandmarkId.CENTER_CIRCLE),
    (Pose2D(2.0, 0.8, -0.4), -55.0, -20.0, CameraPosition.BOTTOM, LandmarkId.GOAL_AREA_CORNER_YELLOW_RIGHT),
]


@pytest.mark.parametrize("pose, yaw_deg, pitch_deg, camera, landmark_id", CASES)
def test_landmark_pixel_matches_pinhole_model(world, pose, yaw_deg, pitch_deg, camera, landmark_id):
    """The ball put on a landmark is drawn where the pinhole model projects its centre."""
    world.place_robot("a", pose)
    world.place_robot("b", Pose2D(-3.5, 3.0, 0.0))
    world.set_head("a", math.radians(yaw_deg), math.radians(pitch_deg))
    world.set_camera("a", camera)
    world.step(15)
    landmark = FIELD.landmark(landmark_id)
    world.place_ball(landmark.x, landmark.y)
    point = np.array([landmark.x, landmark.y, FIELD.ball_radius])
    rotation, position = world.camera_pose("a")
    predicted = NAO_CAMERA.project(world_to_camera(point, rotation, position))[0]
    assert NAO_CAMERA.in_image(predicted[None])[0], f"test case does not look at {landmark_id}: {predicted}"
    rendered = _ball_centroid(world.render_camera("a"))
    assert rendered is not None, "ball not visible"
    assert abs(rendered[0] - predicted[0]) <= 1.0 and abs(rendered[1] - predicted[1]) <= 1.0, (rendered, predicted)


def test_camera_pose_matches_head_kinematics(world):
    """The camera pose of the physical head equals the public kinematic model's."""
    world.place_robot("a", Pose2D(0.3, -0.2, 0.7))
    yaw, pitch = math.radians(40.0), math.radians(20.0)
    world.set_head("a", yaw, pitch)
    for camera in CameraPosition:
        world.set_camera("a", camera)
        world.step(20)
        sensors = world.sensors("a")
        truth = world.robot_truth("a")
        rot_model, pos_model = NAO_HEAD.camera_in_torso(sensors.head_yaw_rad, sensors.head_pitch_rad, camera)
        c, s = math.cos(truth.pose.theta), math.sin(truth.pose.theta)
        torso_to_world = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        ground = np.array([truth.pose.x, truth.pose.y, truth.z_m - 0.34])
        rotation, position = world.camera_pose("a")
        assert np.allclose(torso_to_world @ pos_model + ground, position, atol=0.004)
        assert np.allclose(torso_to_world @ rot_model, rotation, atol=0.01)
        assert abs(sensors.head_yaw_rad - yaw) < 0.01 and abs(sensors.head_pitch_rad - pitch) < 0.01


def test_standing_top_camera_is_at_thesis_height(world):
    world.place_robot("a", Pose2D(0.0, 1.0, 0.0))
    world.step(10)
    _, position = world.camera_pose("a")
    assert position[2] == pytest.approx(0.51, abs=0.005)


def test_camera_image_shape_and_content(world):
    world.place_robot("a", Pose2D(-1.5, 0.0, 0.0))
    world.set_head("a", 0.0, math.radians(17.0))
    world.step(10)
    image = world.render_camera("a")
    assert image.shape == (120, 160, 3) and image.dtype == np.uint8
    green = (image[:, :, 1] > image[:, :, 0] + 40) & (image[:, :, 1] > image[:, :, 2] + 40)
    white = image.min(axis=2) > 200
    assert green.mean() > 0.5 and white.mean() > 0.01


@pytest.fixture(scope="module")
def quad_ground_world():
    """The same world drawing the ground with TinyRenderer's textured quads."""
    from world.config import RenderConfig, RobotSpec, WorldConfig
    from world.robot_model import TeamColor
    from world.world import World

    world = World(
        [RobotSpec("a", TeamColor.BLUE), RobotSpec("b", TeamColor.RED)],
        WorldConfig(render=RenderConfig(analytic_ground=False, renderer="tiny")),
    )
    yield world
    world.close()


@pytest.mark.parametrize(
    "pose, pitch_deg",
    [(Pose2D(-1.5, 0.2, 0.1), 17.0), (Pose2D(2.0, 1.0, 0.5), 25.0), (Pose2D(0.0, -1.5, 2.5), 5.0)],
)
def test_analytic_ground_matches_textured_quad(world, quad_ground_world, pose, pitch_deg):
    """world.ground draws what TinyRenderer draws for the carpet, up to line-edge texels."""
    images = []
    for each in (world, quad_ground_world):
        each.reset(0)
        each.place_robot("a", pose)
        each.place_robot("b", Pose2D(pose.x + 1.0 * math.cos(pose.theta), pose.y + 1.0 * math.sin(pose.theta), 0.0))
        each.set_head("a", 0.0, math.radians(pitch_deg))
        each.step(10)
        images.append(each.render_camera("a").astype(int))
    difference = np.abs(images[0] - images[1]).max(axis=2)
    assert (difference <= 6).mean() > 0.95
    assert np.abs(images[0].mean(axis=(0, 1)) - images[1].mean(axis=(0, 1))).max() < 2.0
