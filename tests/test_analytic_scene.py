"""The analytically drawn scene (ground, walls, banners, roof) matches TinyRenderer's own drawing.

Two worlds with the reference renderer (TinyRenderer) hold the same robots and ball: one draws the static scene in numpy
(:mod:`world.ground`, :mod:`world.backdrop`), the other with TinyRenderer
(``RenderConfig(analytic_ground=False, renderer="tiny")``). Their images must be the same pixel for pixel,
except at edges: the ground is sampled at pixel centres, half a pixel from TinyRenderer's
sample points (see :mod:`world.pixel_rays`), the two rasterize the same edges with different
arithmetic, and TinyRenderer leaves cracks where the floor strips meet the carpet.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from tests.image_edges import near_edge
from world import rendering
from world.camera_model import NAO_CAMERA, CameraPosition
from world.config import RenderConfig, RobotSpec, WorldConfig
from world.field import Pose2D
from world.robot_model import TeamColor
from world.world import World

pytestmark = pytest.mark.render

ROBOTS = {
    "a": (TeamColor.BLUE, Pose2D(-1.0, -0.4, 0.3)),
    "b": (TeamColor.RED, Pose2D(0.6, 0.5, math.pi)),
    "c": (TeamColor.BLUE, Pose2D(-3.2, 0.4, 0.0)),
    "d": (TeamColor.RED, Pose2D(2.9, -2.0, 2.0)),
}
CAMERA_FOV_DEG = math.degrees(NAO_CAMERA.vertical_fov_rad)
VIEWS = {  # (eye, target) m of a 160x120 camera with the robots' field of view
    "wall and banners": ((0.5, 0.0, 0.5), (0.5, 3.9, 0.6)),
    "blue goal": ((-1.5, 0.3, 0.5), (-4.5, 0.0, 0.3)),
    "robots": ((-2.0, -1.5, 0.5), (0.6, 0.5, 0.3)),
    "floor outside the carpet": ((4.2, -3.2, 0.5), (4.8, -3.8, 0.0)),
    "roof and wall top": ((0.0, 0.0, 0.5), (1.0, 0.5, 1.5)),
    "field lines, steeply down": ((0.1, 0.2, 0.5), (0.4, 0.5, 0.0)),
    "along a wall": ((2.0, 3.4, 0.4), (4.9, 3.7, 0.4)),
    "hall corner": ((3.0, 2.0, 0.5), (4.9, 3.9, 0.8)),
    "yellow goal from behind": ((4.6, 0.5, 0.6), (3.0, 0.0, 0.2)),
}
RANDOM_CAMERAS = 40  # seeded cameras at robot head height, anywhere in the hall, any heading, pitch -20..40 deg
HEAD_POSES = [(0.0, -15.0, CameraPosition.TOP), (30.0, 29.0, CameraPosition.TOP), (-40.0, 10.0, CameraPosition.BOTTOM)]


def _world(render: RenderConfig) -> World:
    world = World([RobotSpec(rid, team) for rid, (team, _) in ROBOTS.items()],
                  WorldConfig(render=render, camera_profile="clean"))
    for rid, (_, pose) in ROBOTS.items():
        world.place_robot(rid, pose)
    world.place_ball(-0.2, 0.1)
    world.step(2)
    return world


@pytest.fixture(scope="module")
def worlds():
    analytic, reference = _world(RenderConfig(renderer="tiny")), _world(RenderConfig(analytic_ground=False, renderer="tiny"))
    yield analytic, reference
    analytic.close()
    reference.close()


def _differing(analytic: np.ndarray, reference: np.ndarray, what: str) -> np.ndarray:
    """Pixels (h, w) where the images differ; each must lie at an edge of one of them."""
    assert analytic.shape == reference.shape and analytic.dtype == reference.dtype == np.uint8
    differ = np.any(analytic != reference, axis=2)
    off_edge = differ & ~near_edge(reference) & ~near_edge(analytic)
    assert not off_edge.any(), f"{what}: {off_edge.sum()} differing pixels off edges: {np.argwhere(off_edge)[:3]}"
    return differ


@pytest.fixture(scope="module")
def camera_views(worlds) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """(analytic, reference) 160x120 images of each of :data:`VIEWS` and :data:`HEAD_POSES`."""
    images = {}
    for view, (eye, target) in VIEWS.items():
        images[view] = tuple(
            world.render_overview(eye=eye, target=target, width_px=160, height_px=120, fov_deg=CAMERA_FOV_DEG)
            for world in worlds
        )
    for yaw_deg, pitch_deg, camera in HEAD_POSES:
        for world in worlds:
            world.set_head("a", math.radians(yaw_deg), math.radians(pitch_deg))
            world.set_camera("a", camera)
            world.step(8)
        images[f"robot camera {camera.value}, yaw {yaw_deg}, pitch {pitch_deg}"] = tuple(
            world.render_camera("a") for world in worlds
        )
    return images


def test_camera_views_differ_only_at_edges(camera_views):
    for view, images in camera_views.items():
        _differing(*images, view)


def _random_cameras(count: int, seed: int = 0) -> list[tuple[tuple[float, ...], tuple[float, ...]]]:
    """(eye, target) of ``count`` cameras at robot head height looking anywhere in the hall."""
    rng = np.random.default_rng(seed)
    cameras = []
    for _ in range(count):
        eye = (rng.uniform(-4.6, 4.6), rng.uniform(-3.6, 3.6), rng.uniform(0.3, 0.55))
        yaw, pitch = rng.uniform(-math.pi, math.pi), math.radians(rng.uniform(-20.0, 40.0))
        ahead = (math.cos(yaw) * math.cos(pitch), math.sin(yaw) * math.cos(pitch), -math.sin(pitch))
        cameras.append((eye, tuple(e + a for e, a in zip(eye, ahead))))
    return cameras


def test_random_camera_views_are_99_percent_identical(worlds):
    differ = []
    for number, (eye, target) in enumerate(_random_cameras(RANDOM_CAMERAS)):
        images = [
            world.render_overview(eye=eye, target=target, width_px=160, height_px=120, fov_deg=CAMERA_FOV_DEG)
            for world in worlds
        ]
        differ.append(_differing(*images, f"random camera {number}").mean())
    assert np.mean(differ) <= 0.01, f"{np.mean(differ):.2%} of pixels differ"


def test_broadcast_view_differs_only_at_edges(worlds):
    """The default broadcast camera is above the roof: it sees the hall through the roof's back face."""
    differ = _differing(*(world.render_overview() for world in worlds), "broadcast view")
    assert differ.mean() <= 0.015


def test_frames_are_deterministic(worlds):
    """The same view is byte-identical whether its backdrop is drawn afresh or remembered."""
    analytic, _ = worlds

    def view(name: str) -> np.ndarray:
        eye, target = VIEWS[name]
        return analytic.render_overview(eye=eye, target=target, width_px=160, height_px=120, fov_deg=CAMERA_FOV_DEG)

    first, remembered = view("wall and banners"), view("wall and banners")
    for other in VIEWS:  # push the first view out of the backdrop cache
        view(other)
    redrawn = view("wall and banners")
    assert first.tobytes() == remembered.tobytes() == redrawn.tobytes()


SCATTERED = 6  # seeded layouts of the robots and the ball, half of them in and around the goals


def test_broadcast_view_with_its_static_scene_cached_is_byte_identical(worlds):
    """The broadcast view draws its hall and goals once per camera pose (world.static_scene): every pixel
    is the one drawn with the goals by TinyRenderer each frame, whatever stands in front of or in the goals."""
    analytic, _ = worlds
    rng = np.random.default_rng(1)
    cameras = [{}, {"eye": (0.0, 0.0, 9.0), "target": (0.0, 0.0, 0.0)},
               {"eye": (-4.5, -1.0, 1.2), "target": (-3.0, 0.0, 0.3)}]
    try:
        for layout in range(SCATTERED):
            for rid in ROBOTS:
                x = rng.choice([-3.1, -2.95, 2.95, 3.1]) + rng.uniform(-0.2, 0.2) if layout % 2 else rng.uniform(-3, 3)
                analytic.place_robot(rid, Pose2D(x, rng.uniform(-1.0, 1.0), rng.uniform(-math.pi, math.pi)))
            analytic.place_ball(rng.uniform(-3.2, 3.2), rng.uniform(-0.8, 0.8))
            analytic.step(3)
            for camera in cameras:
                cached = analytic.render_overview(**camera)
                every_frame = rendering.render_overview(analytic.client, analytic.config.render, analytic.ground,
                                                        **camera)  # no static scene: the goals drawn every frame
                assert cached.shape == (480, 640, 3) and cached.tobytes() == every_frame.tobytes(), (layout, camera)
    finally:
        for rid, (_, pose) in ROBOTS.items():
            analytic.place_robot(rid, pose)
        analytic.place_ball(-0.2, 0.1)
        analytic.step(2)


def test_a_broadcast_frame_leaves_the_goals_as_the_robots_see_them(worlds):
    """The broadcast frame hides the world's goals while TinyRenderer draws it; they are back afterwards."""
    analytic, _ = worlds
    analytic.place_robot("a", Pose2D(-1.6, 0.0, math.pi))  # facing the blue goal
    analytic.set_head("a", 0.0, math.radians(5.0))
    analytic.set_camera("a", CameraPosition.TOP)
    analytic.step(8)
    try:
        before = analytic.render_camera("a")
        blue = (before[..., 2] > 150) & (before[..., 0] < 100) & (before[..., 1] < 120)
        assert blue.sum() > 100  # the goal is in view
        analytic.render_overview()
        assert analytic.render_camera("a").tobytes() == before.tobytes()
    finally:
        analytic.place_robot("a", ROBOTS["a"][1])
        analytic.step(2)
