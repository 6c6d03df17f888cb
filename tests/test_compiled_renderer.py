"""The compiled renderer (world.raster) draws what the reference renderer draws.

The reference is TinyRenderer with the analytic hall (``RenderConfig(renderer="tiny")``).
Frames are compared on the bodies' poses of a team-v-team match and on random camera poses:
at least 99.9% of pixels must be identical, and every other one must lie on an edge of the
reference image (its 3x3 neighbourhood holds another colour), where the two renderers'
last-bit arithmetic may put a boundary one pixel apart.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from match.game import Match
from match.runner import run_match
from scenarios.matches.play import Lineup, match_config
from tests.image_edges import near_edge
from world import rendering
from world.camera_model import NAO_CAMERA, CameraPosition
from world.config import RenderConfig, RobotSpec, WorldConfig
from world.field import Pose2D
from world.robot_model import TeamColor
from world.world import World

pytestmark = pytest.mark.render

ROSTER = [RobotSpec(f"{side}_{i}", TeamColor.BLUE if side == "home" else TeamColor.RED)
          for side in ("home", "away") for i in range(4)]
QUICK = {"initial_seconds": 0.0, "ready_seconds": 1.0, "set_seconds": 0.0}
MATCH_STEPS = 200  # the cameras of every other step: 800 frames
RANDOM_VIEWS = 200
MIN_IDENTICAL = 0.999


@pytest.fixture(scope="module")
def worlds():
    """The same roster drawn by the compiled renderer and by the reference."""
    compiled = World(ROSTER, WorldConfig(render=RenderConfig(renderer="numba"), camera_profile="clean"))
    reference = World(ROSTER, WorldConfig(render=RenderConfig(renderer="tiny"), camera_profile="clean"))
    yield compiled, reference
    compiled.close()
    reference.close()


class _Tally:
    """Identical pixels, and differing pixels off the reference's edges, over many frames."""

    def __init__(self) -> None:
        self.pixels = self.differing = self.off_edges = 0

    def add(self, compiled: np.ndarray, reference: np.ndarray) -> None:
        differ = (compiled != reference).any(axis=2)
        self.pixels += differ.size
        self.differing += int(differ.sum())
        self.off_edges += int((differ & ~near_edge(reference)).sum())

    def check(self, what: str) -> None:
        identical = 1.0 - self.differing / self.pixels
        assert identical >= MIN_IDENTICAL, f"{what}: {identical:.6f} of pixels identical"
        assert self.off_edges == 0, f"{what}: {self.off_edges} differing pixels off the reference's edges"


class _PoseRecorder:
    """A match observer that keeps every other step's body poses and camera poses."""

    def __init__(self, steps: int):
        self.steps, self.played, self.records = steps, 0, []

    def decided(self, match: Match, actions) -> None:
        self.played += 1
        if self.played % 2 == 0:
            world = match.world
            self.records.append((world.body_poses(), [world.camera_pose(r) for r in world.robot_ids]))

    def done(self, match: Match) -> bool:
        return self.played >= self.steps


def test_frames_of_a_team_match_are_the_reference_frames(worlds) -> None:
    compiled, reference = worlds
    config = match_config(camera_profile="clean")  # the poses of the match these frames were chosen from
    config = replace(config, referee=replace(config.referee, **QUICK))
    recorder = _PoseRecorder(MATCH_STEPS)
    match = Match(config)
    try:
        run_match(config, Lineup("team", "team").policies(match.agents), seed=3, progress=False, match=match,
                  observer=recorder)
    finally:
        match.close()
    tally = _Tally()
    for poses, cameras in recorder.records:
        for world in worlds:
            world.set_body_poses(poses)
        for rotation, position in cameras:
            tally.add(compiled.render_camera_at(rotation, position), reference.render_camera_at(rotation, position))
    assert tally.pixels == 800 * 160 * 120
    tally.check("team-v-team match")


def _scatter(world: World, rng: np.random.Generator) -> None:
    for robot in world.robot_ids:
        world.place_robot(robot, Pose2D(rng.uniform(-3.0, 3.0), rng.uniform(-2.2, 2.2), rng.uniform(-3.1, 3.1)))
        world.command_walk(robot, 0.1, 0.0, 0.4)
        world.set_head(robot, rng.uniform(-1.5, 1.5), rng.uniform(-0.6, 0.5))
    world.place_ball(rng.uniform(-3.0, 3.0), rng.uniform(-2.0, 2.0), 0.4, -0.2)
    world.step(4)


def test_random_camera_poses_are_drawn_as_the_reference_draws_them(worlds) -> None:
    """Cameras anywhere in the hall at 5 cm to 4.5 m, any heading, looking 60 deg up to straight down."""
    compiled, reference = worlds
    rng = np.random.default_rng(11)
    tally = _Tally()
    for view in range(RANDOM_VIEWS):
        if view % 20 == 0:
            _scatter(compiled, rng)
            reference.set_body_poses(compiled.body_poses())
        eye = np.array([rng.uniform(-4.5, 4.5), rng.uniform(-3.5, 3.5), rng.uniform(0.05, 0.7 if view % 4 else 4.5)])
        heading, pitch = rng.uniform(-math.pi, math.pi), rng.uniform(-math.pi / 3, math.pi / 2)
        ahead = np.array([math.cos(heading) * math.cos(pitch), math.sin(heading) * math.cos(pitch), -math.sin(pitch)])
        rotation, position = rendering.look_at(eye, eye + ahead, (0.0, 0.0, 1.0) if abs(pitch) < 1.5 else (1, 0, 0))
        tally.add(compiled.render_camera_at(rotation, position), reference.render_camera_at(rotation, position))
    tally.check("random camera poses")


def test_broadcast_views_are_the_reference_views(worlds) -> None:
    compiled, reference = worlds
    rng = np.random.default_rng(5)
    tally = _Tally()
    for _ in range(3):
        _scatter(compiled, rng)
        reference.set_body_poses(compiled.body_poses())
        for camera in ({}, {"eye": (0.0, 0.0, 9.0), "target": (0.0, 0.0, 0.0)}):
            tally.add(compiled.render_overview(**camera), reference.render_overview(**camera))
    tally.check("broadcast view")


def test_frames_are_the_same_on_threads_and_on_one(worlds) -> None:
    compiled, _ = worlds
    _scatter(compiled, np.random.default_rng(2))
    renderer = compiled.compiled_renderer
    was = renderer.parallel
    try:
        renderer.parallel = False
        one = np.stack([image for _, image in compiled.render_cameras(compiled.robot_ids)])
        renderer.parallel = True
        threads = np.stack([image for _, image in compiled.render_cameras(compiled.robot_ids)])
        again = np.stack([image for _, image in compiled.render_cameras(compiled.robot_ids)])
    finally:
        renderer.parallel = was
    assert one.tobytes() == threads.tobytes() == again.tobytes()
    singles = np.stack([compiled.render_camera(robot) for robot in compiled.robot_ids])
    assert singles.tobytes() == one.tobytes()


def test_a_large_lone_frame_is_the_same_in_bands_of_rows(worlds) -> None:
    compiled, _ = worlds
    _scatter(compiled, np.random.default_rng(3))
    renderer = compiled.compiled_renderer
    teams = {compiled.body_id(robot): compiled.robot_truth(robot).team for robot in compiled.robot_ids}
    camera = rendering.look_at((1.0, -4.5, 2.5), (0.0, 0.0, 0.0), (0.0, 0.0, 1.0))
    was = renderer.parallel
    drawn = []
    try:
        for parallel in (False, True):
            renderer.parallel = parallel
            drawn.append(renderer.frames([camera], 640, 480, 0.8, teams))
    finally:
        renderer.parallel = was
    (one, one_labels), (bands, band_labels) = drawn
    assert one.tobytes() == bands.tobytes() and one_labels.tobytes() == band_labels.tobytes()


def test_labels_are_pybullet_segmentation_labels(worlds) -> None:
    """Where a body shows, its label is the one pybullet's segmentation mask gives; the hall is -1."""
    compiled, reference = worlds
    rng = np.random.default_rng(8)
    agree = shown = 0
    for _ in range(4):
        _scatter(compiled, rng)
        reference.set_body_poses(compiled.body_poses())
        for robot in compiled.robot_ids:
            compiled.set_camera(robot, CameraPosition.TOP)
            rotation, position = compiled.camera_pose(robot)
            _, labels = compiled.camera_labels(robot)
            _, depth, mask = rendering.camera_buffers(reference.client, rotation, position, NAO_CAMERA.width_px,
                                                      NAO_CAMERA.height_px, NAO_CAMERA.vertical_fov_rad,
                                                      reference.config.render, segmentation=True)
            hall = reference.ground.backdrop(rotation, position, NAO_CAMERA.width_px, NAO_CAMERA.height_px,
                                             rendering.focal_length_px(NAO_CAMERA.height_px,
                                                                       NAO_CAMERA.vertical_fov_rad))
            expected = np.where(depth >= hall.min_depth, -1, mask)  # the hall in front: no body shows
            shown += int((expected >= 0).sum())
            agree += int(((labels == expected) & (expected >= 0)).sum())
            assert ((labels == -1) == (expected == -1)).mean() >= MIN_IDENTICAL
    assert shown > 1000 and agree / shown >= MIN_IDENTICAL


def test_a_team_colour_change_shows_at_once(worlds) -> None:
    compiled, reference = worlds
    _scatter(compiled, np.random.default_rng(4))
    try:
        for world in worlds:
            world.set_team_color("home_0", TeamColor.RED)
        reference.set_body_poses(compiled.body_poses())
        for robot in compiled.robot_ids:
            rotation, position = compiled.camera_pose(robot)
            tally = _Tally()
            tally.add(compiled.render_camera_at(rotation, position), reference.render_camera_at(rotation, position))
            tally.check(f"{robot}'s camera after the colour change")
    finally:
        for world in worlds:
            world.set_team_color("home_0", TeamColor.BLUE)


def test_the_renderer_is_chosen_by_name_only() -> None:
    with pytest.raises(ValueError, match="renderer = 'opengl'; expected one of numba, tiny"):
        RenderConfig(renderer="opengl")
    with pytest.raises(ValueError, match="renderer='tiny'"):
        RenderConfig(analytic_ground=False)
