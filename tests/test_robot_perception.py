"""Robots seen by their team markers (agents.vision.robots), the obstacle model
(agents.modelling.obstacle_model) and walking around obstacles (agents.behavior.skills.paths)."""

from __future__ import annotations

import math

import numpy as np
import pybullet as pb
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from agents.behavior import skills
from agents.behavior.skills.paths import LOOK_AHEAD_M, steer_around
from agents.modelling.obstacle_model import (
    ECHO_EXPIRY_S,
    EXPIRY_S,
    HEAR_BELOW_M,
    SONAR_FORWARD_M,
    SONAR_MIN_RANGE_M,
    SONAR_YAW_RAD,
    Obstacle,
    ObstacleKind,
    ObstacleModel,
    ObstacleModelError,
)
from agents.vision.colors import ColorClass
from agents.vision.errors import VisionInputError
from agents.vision.pipeline import VisionPipeline
from agents.vision.robots import (
    WAISTBAND_DEPTH_M,
    WAISTBAND_HEIGHT_M,
    WAISTBAND_TALL_M,
    WAISTBAND_WIDTH_M,
    RobotKind,
    RobotPercept,
    find_robots,
    marker_blobs,
    team_of,
)
from match.protocol import WALK_HIGH, WALK_LOW, Displacement
from match.protocol.spaces import SONAR_MAX_RANGE_M
from world.camera_model import CameraPosition
from world.config import RobotSpec, SonarConfig
from world.field import Pose2D
from world.robot_model import TORSO_CENTER_HEIGHT_M, Joint
from world.sensors import sonar_rays
from world.teams import TeamColor
from world.world import World

OBSERVER = "me"
PARKED = {"blue": Pose2D(-1.0, -3.5, math.pi / 2), "red": Pose2D(1.0, -3.5, math.pi / 2)}  # off the carpet
SETTLE_STEPS = 12
BEARING_TOLERANCE_RAD = math.radians(5.0)
DISTANCE_TOLERANCE = 0.2


@pytest.fixture(scope="module")
def world():
    with World([RobotSpec(OBSERVER, TeamColor.BLUE), RobotSpec("blue", TeamColor.BLUE), RobotSpec("red", TeamColor.RED)],
               seed=0) as w:
        yield w


@pytest.fixture(scope="module")
def pipeline() -> VisionPipeline:
    return VisionPipeline()


def _stage(world: World, observer: Pose2D, others: dict[str, Pose2D], head=(0.0, 0.3),
           camera=CameraPosition.TOP, ball=(3.5, -3.5)) -> None:
    world.place_robot(OBSERVER, observer)
    world.set_camera(OBSERVER, camera)
    world.set_head(OBSERVER, *head)
    for robot_id, parked in PARKED.items():
        world.place_robot(robot_id, others.get(robot_id, parked))
    world.place_ball(*ball)
    world.step(SETTLE_STEPS)


def _percepts(world: World, pipeline: VisionPipeline, own_team: TeamColor = TeamColor.BLUE) -> tuple[RobotPercept, ...]:
    s = world.sensors(OBSERVER)
    segmented = pipeline.table.segment(world.render_camera(OBSERVER))
    return find_robots(segmented, s.head_yaw_rad, s.head_pitch_rad, s.camera, own_team)


def _relative(world: World, robot_id: str) -> tuple[float, float]:
    """True (bearing rad, distance m) of a robot in the observer's torso frame."""
    me, other = world.robot_pose(OBSERVER), world.robot_pose(robot_id)
    dx, dy = other.x - me.x, other.y - me.y
    c, s = math.cos(me.theta), math.sin(me.theta)
    x, y = c * dx + s * dy, -s * dx + c * dy
    return math.atan2(y, x), math.hypot(x, y)


# ---- the agents' constants agree with the world ----------------------------------------------


def test_waistband_geometry_is_the_world_robot_models(world: World) -> None:
    world.reset(0)
    body = world.body_id("blue")
    base_z = pb.getBasePositionAndOrientation(body, physicsClientId=world.client)[0][2]
    waist_z = pb.getLinkState(body, int(Joint.WAIST), computeForwardKinematics=True, physicsClientId=world.client)[4][2]
    assert waist_z - base_z + TORSO_CENTER_HEIGHT_M == pytest.approx(WAISTBAND_HEIGHT_M, abs=1e-6)
    shapes = {s[1]: s for s in pb.getVisualShapeData(body, physicsClientId=world.client)}
    depth, width, tall = shapes[int(Joint.WAIST)][3]
    assert (depth, width, tall) == pytest.approx((WAISTBAND_DEPTH_M, WAISTBAND_WIDTH_M, WAISTBAND_TALL_M), abs=1e-6)


def test_sonar_constants_are_the_worlds(world: World) -> None:
    sonar = SonarConfig()
    world.place_robot(OBSERVER, Pose2D(0.0, 0.0, 0.0))
    starts = {ray[0] for ray in sonar_rays(world.client, world.body_id(OBSERVER), sonar)}
    assert [x for x, _, _ in starts] == pytest.approx([SONAR_FORWARD_M] * len(starts), abs=2e-3)
    assert SONAR_YAW_RAD == pytest.approx(sonar.yaw_rad)
    assert SONAR_MIN_RANGE_M == pytest.approx(sonar.min_range_m)
    assert HEAR_BELOW_M < sonar.max_range_m == pytest.approx(SONAR_MAX_RANGE_M)


# ---- robots in rendered frames -------------------------------------------------------------


CASES = {
    # observer pose, head (yaw, pitch), the robots' poses (field frame)
    "1 m, facing": (Pose2D(-2.0, 0.0, 0.0), (0.0, 0.3),
                    {"blue": Pose2D(-1.0, 0.2, math.pi), "red": Pose2D(-1.05, -0.2, math.pi)}),
    "2 m, side-on": (Pose2D(-2.0, 0.0, 0.0), (0.0, 0.3),
                     {"blue": Pose2D(0.0, 0.45, math.pi / 2), "red": Pose2D(0.0, -0.4, -math.pi / 2)}),
    "3 m, from behind": (Pose2D(-2.0, 0.0, 0.0), (0.0, 0.3),
                         {"blue": Pose2D(1.0, -0.6, 0.3), "red": Pose2D(0.9, 0.8, -0.2)}),
    "head turned left": (Pose2D(0.5, -1.0, math.pi / 2), (0.6, 0.25),
                         {"blue": Pose2D(-0.5, 0.2, 1.0), "red": Pose2D(-0.9, 1.3, -2.0)}),
    "bottom camera, near": (Pose2D(1.0, 1.0, math.pi), (0.0, -0.35),
                            {"red": Pose2D(-0.3, 1.25, 0.5), "blue": Pose2D(-0.1, 0.7, 2.5)}),
}


@pytest.mark.render
@pytest.mark.parametrize("case", CASES, ids=list(CASES))
def test_each_robot_is_found_with_its_team_bearing_and_distance(world: World, pipeline: VisionPipeline, case: str) -> None:
    observer, head, others = CASES[case]
    camera = CameraPosition.BOTTOM if "bottom" in case else CameraPosition.TOP
    _stage(world, observer, others, head, camera)
    percepts = _percepts(world, pipeline, TeamColor.BLUE)
    assert sorted(p.team.value for p in percepts) == sorted(t.value for t in (TeamColor.BLUE, TeamColor.RED)), percepts
    for percept in percepts:
        robot_id = percept.team.value
        bearing, distance = _relative(world, robot_id)
        assert 0.9 <= distance <= 3.2  # the cases stay at 1-3 m
        assert percept.kind is (RobotKind.TEAMMATE if percept.team is TeamColor.BLUE else RobotKind.OPPONENT)
        assert abs(math.remainder(percept.bearing_rad - bearing, math.tau)) < BEARING_TOLERANCE_RAD, (percept, bearing)
        assert abs(percept.distance_m - distance) < DISTANCE_TOLERANCE * distance, (percept, distance)


@pytest.mark.render
def test_the_own_team_colour_decides_teammate_or_opponent(world: World, pipeline: VisionPipeline) -> None:
    observer, head, others = CASES["2 m, side-on"]
    _stage(world, observer, others, head)
    as_red = {p.team: p.kind for p in _percepts(world, pipeline, TeamColor.RED)}
    assert as_red == {TeamColor.BLUE: RobotKind.OPPONENT, TeamColor.RED: RobotKind.TEAMMATE}


NO_ROBOT_VIEWS = {
    # observer pose, head (yaw, pitch), camera, ball, the colours the view shows
    "empty field": (Pose2D(0.0, 1.0, -math.pi / 4), (0.0, 0.3), CameraPosition.TOP, (3.5, -3.5), ()),
    "blue goal and ball": (Pose2D(-1.2, 0.0, math.pi), (0.0, 0.2), CameraPosition.TOP, (-2.5, 0.1),
                           (ColorClass.BLUE, ColorClass.ORANGE)),
    "yellow goal and ball": (Pose2D(1.5, 0.3, 0.0), (0.0, 0.15), CameraPosition.TOP, (2.6, -0.1),
                             (ColorClass.YELLOW, ColorClass.ORANGE)),
    "ball at the feet": (Pose2D(0.0, 0.0, 0.0), (0.0, 0.45), CameraPosition.BOTTOM, (0.2, 0.0), (ColorClass.ORANGE,)),
    "own waistband": (Pose2D(0.0, 0.0, 0.0), (-0.4, 0.51), CameraPosition.BOTTOM, (3.5, -3.5), (ColorClass.CYAN,)),
}


@pytest.mark.render
@pytest.mark.parametrize("view", NO_ROBOT_VIEWS, ids=list(NO_ROBOT_VIEWS))
def test_no_robot_in_view_gives_no_percepts(world: World, pipeline: VisionPipeline, view: str) -> None:
    observer, head, camera, ball, shown = NO_ROBOT_VIEWS[view]
    _stage(world, observer, {}, head, camera, ball)
    s = world.sensors(OBSERVER)
    segmented = pipeline.table.segment(world.render_camera(OBSERVER))
    assert all(np.count_nonzero(segmented == int(color)) >= 20 for color in shown)
    assert find_robots(segmented, s.head_yaw_rad, s.head_pitch_rad, s.camera, TeamColor.BLUE) == ()


# ---- marker blobs on synthetic label images --------------------------------------------------


def _labels(*boxes: tuple[ColorClass, int, int, int, int]) -> np.ndarray:
    labels = np.full((120, 160), int(ColorClass.GREEN), np.uint8)
    for color, left, top, width, height in boxes:
        labels[top:top + height, left:left + width] = int(color)
    return labels


def test_fragments_of_one_band_are_joined_and_noise_dropped() -> None:
    labels = _labels(
        (ColorClass.CYAN, 20, 30, 4, 3), (ColorClass.CYAN, 28, 30, 5, 3),  # one band split by an arm
        (ColorClass.CYAN, 90, 30, 6, 3),  # another blue robot
        (ColorClass.MAGENTA, 60, 50, 2, 1),  # noise
        (ColorClass.MAGENTA, 120, 40, 12, 4),
    )
    blobs = marker_blobs(labels)
    assert [(b.color, b.box, b.pixels) for b in blobs] == [
        (ColorClass.CYAN, (20, 30, 13, 3), 27),
        (ColorClass.CYAN, (90, 30, 6, 3), 18),
        (ColorClass.MAGENTA, (120, 40, 12, 4), 48),
    ]
    assert blobs[0].center == (26.0, 31.0)


def test_bad_inputs_raise_typed_errors() -> None:
    with pytest.raises(VisionInputError):
        team_of(ColorClass.GREEN)
    with pytest.raises(VisionInputError):
        marker_blobs(np.zeros((120, 160, 3), np.uint8))
    with pytest.raises(VisionInputError):
        find_robots(_labels(), 0.0, 0.3, CameraPosition.TOP, "blue")  # type: ignore[arg-type]
    assert team_of(ColorClass.CYAN) is TeamColor.BLUE and team_of(ColorClass.MAGENTA) is TeamColor.RED


# ---- the obstacle model ------------------------------------------------------------------------


def _seen(x: float, y: float, kind: RobotKind = RobotKind.OPPONENT) -> RobotPercept:
    team = TeamColor.BLUE if kind is RobotKind.TEAMMATE else TeamColor.RED
    return RobotPercept(math.atan2(y, x), math.hypot(x, y), team, kind, (0, 0, 1, 1), (0.0, 0.0), 10)


def test_odometry_carries_the_obstacles_into_the_new_frame() -> None:
    model = ObstacleModel()
    model.see([_seen(1.0, 0.5)])
    model.predict(Displacement(0.5, 0.0, math.pi / 2), dt_s=0.1)
    (obstacle,) = model.obstacles()
    assert (obstacle.x_m, obstacle.y_m) == pytest.approx((0.5, -0.5))
    assert obstacle.kind is ObstacleKind.OPPONENT and obstacle.age_s == pytest.approx(0.1)


def test_obstacles_expire_when_not_seen_or_heard() -> None:
    model = ObstacleModel()
    model.see([_seen(1.0, 0.0)])
    model.hear_sonar((0.5, 2.55, 2.55, 2.55))
    assert len(model.obstacles()) == 2
    step = 0.04
    for _ in range(round(ECHO_EXPIRY_S / step) + 1):
        model.predict(Displacement(), step)
    assert [o.kind for o in model.obstacles()] == [ObstacleKind.OPPONENT]
    for _ in range(round((EXPIRY_S - ECHO_EXPIRY_S) / step) + 1):
        model.predict(Displacement(), step)
    assert model.obstacles() == ()


def test_close_sightings_merge_and_keep_the_known_kind() -> None:
    model = ObstacleModel()
    model.hear_sonar((2.55, 2.55, 2.55, 2.55))
    assert model.obstacles() == ()
    model.hear_sonar((0.6, 0.62, 2.55, 2.55))  # both sides alike: one obstacle straight ahead
    (echo,) = model.obstacles()
    assert echo.kind is ObstacleKind.UNKNOWN and abs(echo.y_m) < 1e-9 and echo.x_m == pytest.approx(0.71)
    model.see([_seen(0.75, 0.1, RobotKind.TEAMMATE)])
    (robot,) = model.obstacles()
    assert robot.kind is ObstacleKind.TEAMMATE and robot.age_s == 0.0
    model.see([_seen(0.8, 0.12, RobotKind.TEAMMATE), _seen(0.8, -0.3, RobotKind.OPPONENT)])
    assert sorted(o.kind.value for o in model.obstacles()) == ["opponent", "teammate"]
    model.predict(Displacement(), 0.5)
    model.hear_sonar((0.7, 2.55, 2.55, 2.55))  # the left sonar hears the teammate: it is still there
    teammate = next(o for o in model.obstacles() if o.kind is ObstacleKind.TEAMMATE)
    assert teammate.age_s == 0.0 and len(model.obstacles()) == 2


@pytest.mark.render
def test_a_robot_heard_and_seen_close_ahead_is_one_obstacle_where_it_stands(world: World, pipeline: VisionPipeline) -> None:
    _stage(world, Pose2D(0.0, 0.0, 0.0), {"red": Pose2D(0.5, 0.0, 2.0)}, (0.0, 0.0), CameraPosition.BOTTOM)
    model = ObstacleModel()
    model.hear_sonar(world.sensors(OBSERVER).sonar_m)
    (echo,) = model.obstacles()
    model.see(_percepts(world, pipeline))
    (obstacle,) = model.obstacles()
    bearing, distance = _relative(world, "red")
    assert echo.kind is ObstacleKind.UNKNOWN and obstacle.kind is ObstacleKind.OPPONENT
    for found in (echo, obstacle):
        assert math.hypot(found.x_m - distance * math.cos(bearing), found.y_m - distance * math.sin(bearing)) < 0.1


def test_a_left_echo_is_on_the_left_and_bad_sonars_raise() -> None:
    model = ObstacleModel()
    model.hear_sonar((2.55, 2.55, 0.5, 1.0))
    left, right = model.obstacles()
    assert left.y_m > 0.0 > right.y_m and left.bearing_rad == pytest.approx(SONAR_YAW_RAD, abs=0.05)
    with pytest.raises(ObstacleModelError):
        model.hear_sonar((1.0, 1.0))
    with pytest.raises(ObstacleModelError):
        model.predict(Displacement(), -1.0)


def test_blocking_is_the_nearest_obstacle_in_the_way() -> None:
    model = ObstacleModel()
    model.see([_seen(1.5, 0.1), _seen(0.8, -0.15), _seen(0.5, 0.9)])
    assert model.blocking(0.0, 2.0).x_m == pytest.approx(0.8)
    assert model.blocking(0.0, 0.7) is None
    assert model.blocking(math.atan2(0.9, 0.5), 1.5).y_m == pytest.approx(0.9)
    assert model.blocking(math.pi, 3.0) is None


# ---- walking around obstacles -----------------------------------------------------------------


def _obstacle(x: float, y: float) -> Obstacle:
    return Obstacle(x, y, ObstacleKind.OPPONENT, 0.0)


def test_a_clear_path_leaves_the_walk_untouched() -> None:
    walk = (0.15, 0.02, 0.3)
    obstacles = (_obstacle(0.6, 0.5), _obstacle(-0.5, 0.0), _obstacle(LOOK_AHEAD_M + 0.3, 0.0))
    assert steer_around(walk, obstacles) is walk
    assert steer_around(walk, ()) is walk
    turning = (0.0, 0.0, 0.8)
    assert steer_around(turning, (_obstacle(0.3, 0.0),)) is turning


def test_an_obstacle_ahead_slightly_left_steers_right_and_slows_when_near() -> None:
    vx, vy, omega = steer_around((0.2, 0.0, 0.1), (_obstacle(0.7, 0.05),))
    assert vy < 0.0 and vx == pytest.approx(0.2) and omega == 0.1
    vx_near, vy_near, _ = steer_around((0.2, 0.0, 0.1), (_obstacle(0.35, 0.05),))
    assert vy_near < 0.0 and vx_near < 0.5 * 0.2
    _, vy_right, _ = steer_around((0.2, 0.0, 0.0), (_obstacle(0.7, -0.05),))
    assert vy_right > 0.0
    # Centred, with another obstacle to its left: the right is freer.
    _, vy_free, _ = steer_around((0.2, 0.0, 0.0), (_obstacle(0.6, 0.0), _obstacle(0.7, 0.6)))
    assert vy_free < 0.0
    # Walking backward, the obstacle behind on the robot's left: step to its right.
    vx_back, vy_back, _ = steer_around((-0.1, 0.0, 0.0), (_obstacle(-0.5, 0.05),))
    assert vx_back < 0.0 and vy_back < 0.0


walks = st.tuples(*(st.floats(lo, hi) for lo, hi in zip(WALK_LOW, WALK_HIGH)))
obstacle_lists = st.lists(st.builds(_obstacle, st.floats(-2.0, 2.0), st.floats(-2.0, 2.0)), max_size=6)


@settings(max_examples=300, deadline=None)
@given(walk=walks, obstacles=obstacle_lists)
def test_steering_never_exceeds_the_walk_limits(walk, obstacles) -> None:
    steered = steer_around(walk, obstacles)
    assert all(lo <= v <= hi for v, lo, hi in zip(steered, WALK_LOW, WALK_HIGH))
    assert steered[2] == walk[2]
    assert skills.walk_command(*steered) == pytest.approx(steered)
