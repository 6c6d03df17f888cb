"""Camera image profiles (world.camera_profiles): each effect against its model, determinism, and a
profile that never touches the physics."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from match.game import Match, MatchConfig
from match.protocol import make_action
from world.camera_model import NAO_CAMERA
from world.camera_profiles import (
    CAMERA_PROFILES,
    NAO,
    ROBOTSTADIUM,
    CameraEffects,
    CameraPose,
    CameraProfile,
    FrameEffects,
    apply_frame_effects,
    frame_effects,
    image_motion_px,
    image_velocity_pxps,
)
from world.config import RobotSpec, WorldConfig
from world.errors import UnknownCameraProfileError
from world.field import Pose2D
from world.robot_model import TeamColor
from world.world import World

H, W = NAO_CAMERA.height_px, NAO_CAMERA.width_px
NOISELESS = CameraProfile("noiseless", yuv422=False)
"""Blur, shear and gains only (the effects of a frame are given directly)."""


def _effects(blur=(0.0, 0.0), shear=(0.0, 0.0), gains=(1.0, 1.0, 1.0), key=7) -> FrameEffects:
    return FrameEffects(blur, shear, np.asarray(gains, np.float32), key, False)


def _flat(level: int) -> np.ndarray:
    return np.full((H, W, 3), level, np.uint8)


def _luma(image: np.ndarray) -> np.ndarray:
    rgb = image.astype(float)
    return 0.299 * rgb[..., 0] + 0.587 * rgb[..., 1] + 0.114 * rgb[..., 2]


def _chroma(image: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    r, g, b = (image[..., k].astype(float) for k in range(3))
    return -0.168736 * r - 0.331264 * g + 0.5 * b, 0.5 * r - 0.418688 * g - 0.081312 * b


# ---- configuration ---------------------------------------------------------------------------


def test_profiles_are_named_and_an_unknown_name_is_refused():
    assert set(CAMERA_PROFILES) == {"clean", "robotstadium", "nao"}
    assert WorldConfig().camera_profile == "robotstadium"
    with pytest.raises(UnknownCameraProfileError, match=r"'fancy'.*clean, robotstadium, nao"):
        WorldConfig(camera_profile="fancy")
    with pytest.raises(UnknownCameraProfileError, match="None"):
        WorldConfig(camera_profile=None)


def test_bad_profile_parameters_are_refused():
    with pytest.raises(ValueError, match="read_noise"):
        CameraProfile("x", read_noise=-1.0)
    with pytest.raises(ValueError, match="corner_shading"):
        CameraProfile("x", corner_shading=1.5)


# ---- each effect against its model ---------------------------------------------------------


@pytest.mark.parametrize("level", [40, 128, 180])
def test_yuv_noise_variance_is_shot_plus_read(level):
    """On a flat grey frame the luma's variance is shot * Y + read^2 (plus the rounding of R, G and B:
    (0.299^2 + 0.587^2 + 0.114^2) / 12); the chroma noise does not reach Y."""
    profile = replace(NAO, corner_shading=1.0, exposure_swing=0.0, cast_swing=0.0)
    out = apply_frame_effects(profile, _flat(level), _effects())
    luma = _luma(out)
    expected = profile.shot_noise * level + profile.read_noise**2 + (0.299**2 + 0.587**2 + 0.114**2) / 12.0
    assert luma.mean() == pytest.approx(level, abs=0.1)
    assert luma.var() == pytest.approx(expected, rel=0.06)


def test_rgb_noise_of_the_robotstadium_profile():
    out = apply_frame_effects(ROBOTSTADIUM, _flat(100), _effects()).astype(float)
    expected = ROBOTSTADIUM.read_noise**2 + 1.0 / 12.0
    for c in range(3):
        assert out[..., c].var() == pytest.approx(expected, rel=0.06)
    # channels independent
    assert abs(np.corrcoef(out[..., 0].ravel(), out[..., 1].ravel())[0, 1]) < 0.03


@pytest.mark.parametrize("length", [3.0, 6.0, 10.0])
def test_blur_of_a_bright_column_has_the_blur_length(length):
    """A one-pixel column blurred horizontally by L px spreads over L to L + 1 pixels, its light kept, with
    the second moment of a box of width L."""
    image = np.zeros((H, W, 3), np.uint8)
    image[:, 80] = 252
    out = apply_frame_effects(NOISELESS, image, _effects(blur=(length, 0.0)))
    row = out[60, :, 0].astype(float)
    assert row.sum() == pytest.approx(252.0, abs=0.5 * (length + 2))
    lit = np.nonzero(row)[0]
    assert length <= lit.max() - lit.min() + 1 <= length + 1
    assert lit.max() - 80 == 80 - lit.min()
    centre = (row * np.arange(W)).sum() / row.sum()
    spread = math.sqrt((row * (np.arange(W) - centre) ** 2).sum() / row.sum())
    assert centre == pytest.approx(80.0, abs=0.05)
    assert spread == pytest.approx(length / math.sqrt(12.0), rel=0.08)  # a box of width L


def test_blur_follows_the_head_turn():
    """A camera turned by d about its vertical axis moves the image by -f tan d; over the exposure that
    is the blur vector, and the rolling shutter's shear is the motion over a row's readout."""
    turn = math.radians(2.0)
    rotation = np.eye(3)
    turned = rotation @ np.array([[math.cos(turn), 0, math.sin(turn)], [0, 1, 0], [-math.sin(turn), 0, math.cos(turn)]])
    before = CameraPose(1.0, "top", rotation, np.zeros(3))
    after = CameraPose(1.04, "top", turned, np.zeros(3))
    du, dv = image_motion_px(before, after)
    assert du == pytest.approx(-NAO_CAMERA.focal_px * math.tan(turn), rel=1e-9)
    assert dv == pytest.approx(0.0, abs=1e-9)
    velocity = image_velocity_pxps(before, after)
    assert velocity[0] == pytest.approx(du / 0.04)
    effects = frame_effects(NAO, velocity, turned, (1, 2**63))
    assert effects.blur_px[0] == pytest.approx(du / 0.04 * NAO.exposure_s)
    assert effects.shear_px_per_row[0] == pytest.approx(du / 0.04 * NAO.readout_s / (H - 1))
    # no motion across a camera switch, a placement gap or from nothing
    assert image_velocity_pxps(None, after) == (0.0, 0.0)
    assert image_velocity_pxps(replace(before, camera="bottom"), after) == (0.0, 0.0)
    assert image_velocity_pxps(replace(before, time_s=0.0), after) == (0.0, 0.0)


def test_yuv422_pairs_share_their_chroma():
    """After the YUV422 round trip the two pixels of a horizontal pair have the same U and V (up to the
    rounding of R, G and B), though the input's pairs differ."""
    rng = np.random.default_rng(3)
    image = rng.integers(90, 160, (H, W, 3), dtype=np.uint8)
    profile = CameraProfile("chroma", yuv422=True)
    out = apply_frame_effects(profile, image, _effects())
    u_in, v_in = _chroma(image)
    u_out, v_out = _chroma(out)
    assert np.abs(u_in[:, 0::2] - u_in[:, 1::2]).mean() > 10.0
    unclipped = ((out > 0) & (out < 255)).all(axis=2)
    pairs = unclipped[:, 0::2] & unclipped[:, 1::2]
    assert pairs.mean() > 0.95
    assert np.abs(u_out[:, 0::2] - u_out[:, 1::2])[pairs].max() <= 1.0
    assert np.abs(v_out[:, 0::2] - v_out[:, 1::2])[pairs].max() <= 1.0
    assert np.abs(_luma(out) - _luma(image)).max() <= 1.0  # luma kept per pixel


def test_vignetting_darkens_the_corners_by_the_configured_ratio():
    profile = CameraProfile("vignette", corner_shading=0.75)
    out = apply_frame_effects(profile, _flat(200), _effects()).astype(float)
    centre = out[59:61, 79:81].mean()
    assert centre == pytest.approx(200.0, abs=0.6)
    for corner in (out[0, 0], out[0, -1], out[-1, 0], out[-1, -1]):
        assert corner.mean() / centre == pytest.approx(0.75, abs=0.5 / 200)
    assert out[:, :, 0].min() == out[0, 0, 0]  # darkest in the corners


def test_rolling_shutter_shifts_rows_in_proportion_to_their_index():
    image = np.zeros((H, W, 3), np.uint8)
    image[:, 80] = 250
    shear = 0.08  # px per row
    out = apply_frame_effects(NOISELESS, image, _effects(shear=(shear, 0.0))).astype(float)[..., 0]
    columns = np.arange(W)
    centres = (out * columns).sum(axis=1) / out.sum(axis=1)
    rows = np.arange(H)
    slope, intercept = np.polyfit(rows, centres, 1)
    assert slope == pytest.approx(shear, rel=0.02)
    assert intercept + slope * (H - 1) / 2 == pytest.approx(80.0, abs=0.05)  # the centre row unmoved
    assert np.abs(centres - (intercept + slope * rows)).max() < 0.05


def test_gains_scale_the_channels():
    out = apply_frame_effects(NOISELESS, _flat(100), _effects(gains=(1.1, 1.0, 0.9))).astype(float)
    assert out[..., 0].mean() == pytest.approx(110, abs=0.5)
    assert out[..., 1].mean() == pytest.approx(100, abs=0.5)
    assert out[..., 2].mean() == pytest.approx(90, abs=0.5)


def test_lost_frames_repeat_the_previous_frame_at_their_rate():
    """Over 5000 frames of a still camera about 1 % are the previous frame again (noise makes every
    fresh frame differ)."""
    effects = CameraEffects(NAO, np.random.default_rng(11))
    image = np.full((8, 16, 3), 120, np.uint8)
    pose = CameraPose(0.0, "top", np.eye(3), np.zeros(3))
    previous, repeats, frames = None, 0, 5000
    for i in range(frames):
        out = effects.apply("a", image, replace(pose, time_s=0.04 * i))
        if previous is not None and np.array_equal(out, previous):
            repeats += 1
        previous = out
    expected = NAO.lost_frame_probability * (frames - 1)
    assert abs(repeats - expected) <= 4 * math.sqrt(expected)


# ---- in the world ------------------------------------------------------------------------


@pytest.fixture(scope="module")
def worlds():
    built = {name: World([RobotSpec("a", TeamColor.BLUE), RobotSpec("b", TeamColor.RED)],
                         WorldConfig(camera_profile=name)) for name in ("clean", "nao")}
    yield built
    for world in built.values():
        world.close()


def _frames(world: World, seed: int, steps: int = 6) -> list[np.ndarray]:
    world.reset(seed)
    world.place_robot("a", Pose2D(-1.0, 0.3, 0.2))
    world.step(2)
    frames = []
    for i in range(steps):
        world.set_head("a", 0.15 * i, 0.3)
        world.step(1)
        frames.append(world.render_camera("a"))
    return frames


@pytest.mark.render
def test_clean_frames_are_the_rendered_frames_byte_for_byte(worlds):
    """Under ``clean`` a robot's frame is the renderer's image at its camera pose, and the profile does
    nothing at all (the image object itself is handed on)."""
    world = worlds["clean"]
    world.reset(0)
    world.place_robot("a", Pose2D(-1.0, 0.3, 0.2))
    for i in range(3):
        world.set_head("a", 0.3 * i, 0.3)
        world.step(1)
        frame = world.render_camera("a").copy()
        assert frame.tobytes() == world.render_camera_at(*world.camera_pose("a")).tobytes()
        frames = dict(world.render_cameras(["a", "b"]))
        assert frames["a"].tobytes() == frame.tobytes()
    image = np.zeros((H, W, 3), np.uint8)
    clean = CameraEffects(CAMERA_PROFILES["clean"], np.random.default_rng(0))
    state = clean.rng.bit_generator.state
    assert clean.apply("a", image, CameraPose(0.0, "top", np.eye(3), np.zeros(3))) is image
    assert clean.rng.bit_generator.state == state


@pytest.mark.render
def test_nao_frames_are_deterministic_per_seed_and_differ_from_clean(worlds):
    world = worlds["nao"]
    first, again, other = _frames(world, 5), _frames(world, 5), _frames(world, 6)
    assert all(a.tobytes() == b.tobytes() for a, b in zip(first, again))
    assert any(a.tobytes() != b.tobytes() for a, b in zip(first, other))
    clean = _frames(worlds["clean"], 5)
    assert all(a.tobytes() != b.tobytes() for a, b in zip(first, clean))
    # the image moves while the head turns: those frames are blurred (fewer strong horizontal edges)
    rendered = world.render_camera_at(*world.camera_pose("a"))
    assert np.abs(np.diff(first[-1].astype(int), axis=1)).max() < np.abs(np.diff(rendered.astype(int), axis=1)).max()


@pytest.mark.render
def test_a_restored_world_replays_its_camera_frames(worlds):
    world = worlds["nao"]
    _frames(world, 2, 3)
    saved = world.save_state()
    ahead = _frames_from_here(world)
    world.restore_state(saved)
    assert [f.tobytes() for f in _frames_from_here(world)] == [f.tobytes() for f in ahead]
    world.discard_state(saved)


def _frames_from_here(world: World) -> list[np.ndarray]:
    frames = []
    for i in range(3):
        world.set_head("a", -0.2 * i, 0.2)
        world.step(1)
        frames.append(world.render_camera("a"))
    return frames


@pytest.mark.render
def test_a_robots_frames_do_not_depend_on_another_robots(worlds):
    """Robot ``b`` taking frames between ``a``'s (or none at all: a dead controller, a camera left off)
    changes nothing in ``a``'s: each frame's draws come from the key, the robot and its frame number."""
    world = worlds["nao"]
    alone = _frames(world, 7, 4)
    world.reset(7)
    world.place_robot("a", Pose2D(-1.0, 0.3, 0.2))
    world.step(2)
    beside = []
    for i in range(4):
        world.set_head("a", 0.15 * i, 0.3)
        world.step(1)
        world.render_camera("b")
        beside.append(dict(world.render_cameras(["b", "a"]))["a"])
    assert [f.tobytes() for f in beside] == [f.tobytes() for f in alone]


@pytest.mark.render
@pytest.mark.slow
def test_the_profile_does_not_change_the_physics():
    """The same seed and actions, with cameras on: the world's state digest is the same step by step
    under ``clean`` and ``nao``."""
    digests = {}
    for name in ("clean", "nao"):
        match = Match(MatchConfig(home_players=2, away_players=1, world=WorldConfig(camera_profile=name)))
        try:
            match.reset(seed=4)
            trace = []
            for step in range(90):
                yaw = 0.8 * math.sin(step / 5.0)
                actions = {agent: make_action("walk", walk=(0.15, 0.0, 0.3), head=(yaw, 0.2)) for agent in
                           match.agent_names}
                match.step(actions)
                trace.append(match.world.state_digest())
            digests[name] = trace
        finally:
            match.world.close()
    assert digests["clean"] == digests["nao"]


# ---- choosing a profile ------------------------------------------------------------------------


@pytest.mark.render
def test_a_match_records_its_profile_and_a_rerun_plays_it(tmp_path):
    import json

    from scenarios.matches.play import Lineup, run_lineup_match
    from scenarios.matches.rerun import rerun_plan

    run_lineup_match(tmp_path, Lineup("stand", "stand"), home=1, away=1, half_seconds=1.0, seed=3, shootout=False,
                     progress=False, max_steps=5, camera_profile="robotstadium")
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["config"]["world"]["camera_profile"] == "robotstadium"
    assert rerun_plan(summary).camera_profile == "robotstadium"
    del summary["config"]["world"]["camera_profile"]  # a record from before the profiles: clean
    assert rerun_plan(summary).camera_profile == "clean"


def test_scenarios_and_perception_take_a_profile_and_refuse_unknown_ones():
    from scenarios.localization.batch import with_overrides
    from scenarios.localization.file import load_scenario
    from scenarios.perception.records import PerceptionConfig, PerceptionConfigError

    spec = load_scenario("1")
    assert spec.camera_profile == "robotstadium"
    nao = with_overrides(spec, camera_profile="nao")
    assert nao.camera_profile == "nao" and nao.fingerprint() != spec.fingerprint()
    with pytest.raises(UnknownCameraProfileError, match="'fancy'"):
        with_overrides(spec, camera_profile="fancy")
    assert PerceptionConfig(1, camera_profile="nao").camera_profile == "nao"
    with pytest.raises(PerceptionConfigError, match="'fancy'"):
        PerceptionConfig(1, camera_profile="fancy")


@pytest.mark.render
def test_frames_taken_together_are_the_frames_taken_one_by_one(worlds):
    """:meth:`World.render_cameras` draws every frame through the profile in one call: the same images as
    :meth:`World.render_camera` robot after robot, also when a robot is named twice (its second frame
    follows from its first)."""
    world = worlds["nao"]

    def play(take) -> list[bytes]:
        world.reset(3)
        world.place_robot("a", Pose2D(-1.0, 0.3, 0.2))
        world.step(2)
        out = []
        for i in range(3):
            world.set_head("a", 0.2 * i, 0.3)
            world.set_head("b", -0.2 * i, 0.2)
            world.step(1)
            out += [image.tobytes() for image in take()]
        return out

    one_by_one = play(lambda: [world.render_camera(r) for r in ("a", "b", "a")])
    together = play(lambda: [image for _, image in world.render_cameras(["a", "b", "a"])])
    assert together == one_by_one
