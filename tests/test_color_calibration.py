"""Colour calibration (``robotstadium calibrate-colors``) and the segmentation it feeds."""

from __future__ import annotations

import json
import os
import time
from pathlib import Path

import numpy as np
import pytest

from agents.vision.ball import orange_mask
from agents.vision.colors import ColorClass
from agents.vision.errors import ColorTableError
from agents.vision.segmentation import ColorBox, ColorTable, ColorThresholds, clean_outliers, load_thresholds
from scenarios import cli
from scenarios.tools.color_calibration import (
    OTHER,
    ROBOT,
    TRUTH_NAMES,
    evaluate,
    fit_thresholds,
    render_truth_frames,
    report_path,
)
from world.ball import BALL_RGBA
from world.config import RenderConfig
from world.field import GoalColor
from world.robot_model import BODY_RGBA, LIMB_RGBA, TeamColor
from world.scene import FLOOR_RGBA, GOAL_RGBA, WALL_RGBA
from world.textures import CARPET_RGB, LINE_RGB

G, W, B, Y, O = (int(c) for c in (ColorClass.GREEN, ColorClass.WHITE, ColorClass.BLUE, ColorClass.YELLOW, ColorClass.ORANGE))
SHADES = (0.65, 0.75, 0.85, 0.95, 1.0)
"""Lighting factors a face can get: ambient 0.65 plus up to 0.35 diffuse."""
MIN_HELD_OUT = {"green": 0.99, "white": 0.99, "blue": 0.99, "yellow": 0.99, "orange": 0.95, "cyan": 0.95, "magenta": 0.95}


def _ground_shade() -> float:
    render = RenderConfig()
    light = np.asarray(render.light_direction, float)
    return render.ambient + render.diffuse * max(0.0, light[2] / np.linalg.norm(light))


def _shaded(rgb_0_255, shade: float) -> np.ndarray:
    return np.clip(np.asarray(rgb_0_255, float) * shade, 0, 255).astype(np.uint8)


def _rgba_shaded(rgba, shade: float) -> np.ndarray:
    return _shaded(np.asarray(rgba[:3]) * 255.0, shade)


# ---- truth -------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def fit_frames():
    return render_truth_frames(16, seed=11)  # the rendered colours (the calibration's default profile)


@pytest.fixture(scope="module")
def held_out_frames():
    return render_truth_frames(16, seed=12)


@pytest.mark.render
def test_truth_covers_every_class(fit_frames) -> None:
    labels = np.concatenate([f.labels.reshape(-1) for f in fit_frames])
    counts = {TRUTH_NAMES[k]: int(np.count_nonzero(labels == k)) for k in TRUTH_NAMES}
    assert all(n >= 100 for n in counts.values()), counts


@pytest.mark.render
def test_ground_truth_agrees_pixel_exactly_with_the_rendered_ground(fit_frames) -> None:
    carpet, line = _shaded(CARPET_RGB, _ground_shade()), _shaded(LINE_RGB, _ground_shade())
    for frame in fit_frames:
        image, labels = frame.image, frame.labels
        assert np.all(image[labels == G] == carpet)
        assert np.all(image[labels == W] == line)
        # no pixel drawn in carpet green is labelled as anything else
        assert not np.any(np.all(image == carpet, axis=-1) & (labels != G))


@pytest.mark.render
def test_body_truth_agrees_with_the_rendered_colours(fit_frames) -> None:
    """Each body pixel is its body's colour under some lighting factor in [0.65, 1]."""
    expected = {
        B: GOAL_RGBA[GoalColor.BLUE],
        Y: GOAL_RGBA[GoalColor.YELLOW],
        O: BALL_RGBA,
        int(ColorClass.CYAN): TeamColor.BLUE.rgba,
        int(ColorClass.MAGENTA): TeamColor.RED.rgba,
    }
    image = np.concatenate([f.image.reshape(-1, 3) for f in fit_frames]).astype(float)
    labels = np.concatenate([f.labels.reshape(-1) for f in fit_frames])
    for label, rgba in expected.items():
        colour = np.asarray(rgba[:3]) * 255.0
        pixels = image[labels == label]
        assert len(pixels) > 0, TRUTH_NAMES[label]
        assert np.all(pixels >= np.floor(colour * 0.64) - 1), TRUTH_NAMES[label]
        assert np.all(pixels <= np.ceil(colour) + 1), TRUTH_NAMES[label]
    robot = image[labels == ROBOT]
    assert np.all(np.abs(robot[:, 0] - robot[:, 1]) <= 1)  # grey body and limbs


@pytest.mark.render
def test_calibration_labels_held_out_frames(fit_frames, held_out_frames) -> None:
    thresholds = fit_thresholds(fit_frames, "test")
    scores = {s.name: s for s in evaluate(thresholds, held_out_frames)}
    for name, minimum in MIN_HELD_OUT.items():
        assert scores[name].pixels >= 50, name
        assert scores[name].correct >= minimum, (name, scores[name])
    # robots and everything else must not take a calibrated colour (white is right for them)
    assert scores["robot"].correct >= 0.99 and scores["other"].correct >= 0.99, scores


@pytest.mark.render
def test_frames_are_reproducible() -> None:
    a, b = render_truth_frames(2, seed=3), render_truth_frames(2, seed=3)
    for fa, fb in zip(a, b):
        assert np.array_equal(fa.image, fb.image) and np.array_equal(fa.labels, fb.labels)


@pytest.mark.render
def test_cli_writes_thresholds_and_report(tmp_path: Path, capsys) -> None:
    out = tmp_path / "colors.json"
    assert cli.main(["calibrate-colors", "--frames", "3", "--seed", "4", "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "magenta" in printed and "held-out" in printed
    thresholds = load_thresholds(out)
    assert thresholds.source == "robotstadium calibrate-colors --frames 3 --seed 4 --camera-profile clean"
    report = json.loads(report_path(out).read_text())
    assert report["frames"] == 3 and set(report["calibration"]) == set(TRUTH_NAMES.values())


def test_cli_refuses_zero_frames(tmp_path: Path) -> None:
    with pytest.raises(SystemExit) as exit_info:
        cli.main(["calibrate-colors", "--frames", "0", "--out", str(tmp_path / "x.json")])
    assert exit_info.value.code == 2
    with pytest.raises(SystemExit) as exit_info:
        cli.main(["calibrate-colors", "--camera-profile", "webcam", "--out", str(tmp_path / "x.json")])
    assert exit_info.value.code == 2
    assert not (tmp_path / "x.json").exists()


@pytest.mark.render
def test_a_profile_is_calibrated_on_the_frames_it_delivers(tmp_path: Path) -> None:
    """The frames of a calibration under a camera profile are the profile's (the truth labels stay the
    rendered image's), and the thresholds name the profile in their command."""
    clean, nao = render_truth_frames(2, seed=3), render_truth_frames(2, seed=3, camera_profile="nao")
    for a, b in zip(clean, nao):
        assert np.array_equal(a.labels, b.labels)
        assert not np.array_equal(a.image, b.image)
    out = tmp_path / "nao.json"
    assert cli.main(["calibrate-colors", "--frames", "2", "--seed", "4", "--camera-profile", "nao", "--out",
                     str(out)]) == 0
    assert load_thresholds(out).source == "robotstadium calibrate-colors --frames 2 --seed 4 --camera-profile nao"


# ---- the shipped thresholds --------------------------------------------------------------


def test_shipped_thresholds_name_the_command() -> None:
    thresholds = load_thresholds()
    assert thresholds.source.startswith("robotstadium calibrate-colors --frames ")
    assert {box.color for box in thresholds.boxes} == set(ColorClass)


def _blocks(colours) -> np.ndarray:
    """An image of 6x6 blocks, one per colour, so that no block is an isolated pixel."""
    image = np.zeros((6, 6 * len(colours), 3), np.uint8)
    for i, colour in enumerate(colours):
        image[:, 6 * i : 6 * i + 6] = colour
    return image


def _block_labels(colours) -> list[ColorClass]:
    labels = ColorTable(load_thresholds()).segment(_blocks(colours))
    out = []
    for i in range(len(colours)):
        block = labels[:, 6 * i : 6 * i + 6]
        assert np.all(block == block[0, 0])
        out.append(ColorClass(int(block[0, 0])))
    return out


def test_shipped_thresholds_segment_the_scene_colours() -> None:
    shade = _ground_shade()
    assert _block_labels([_shaded(CARPET_RGB, shade), _shaded(LINE_RGB, shade)]) == [ColorClass.GREEN, ColorClass.WHITE]
    cases = {
        ColorClass.BLUE: GOAL_RGBA[GoalColor.BLUE],
        ColorClass.YELLOW: GOAL_RGBA[GoalColor.YELLOW],
        ColorClass.ORANGE: BALL_RGBA,
        ColorClass.CYAN: TeamColor.BLUE.rgba,
        ColorClass.MAGENTA: TeamColor.RED.rgba,
    }
    for expected, rgba in cases.items():
        colours = [_rgba_shaded(rgba, s) for s in SHADES]
        assert _block_labels(colours) == [expected] * len(SHADES), (expected, colours)


def test_robots_and_surroundings_stay_white() -> None:
    colours = [_rgba_shaded(rgba, s) for rgba in (BODY_RGBA, LIMB_RGBA, WALL_RGBA, FLOOR_RGBA) for s in SHADES]
    assert _block_labels(colours) == [ColorClass.WHITE] * len(colours)


def test_ball_finder_rejects_the_waistbands() -> None:
    for team in TeamColor:
        colours = np.stack([_rgba_shaded(team.rgba, s) for s in SHADES])
        assert not orange_mask(colours[None]).any(), team
    assert orange_mask(np.stack([_rgba_shaded(BALL_RGBA, s) for s in SHADES])[None]).all()


# ---- outlier cleaning --------------------------------------------------------------------


def _field(size: int = 5, fill: int = G) -> np.ndarray:
    return np.full((size, size), fill, np.uint8)


def test_isolated_colour_pixel_becomes_white() -> None:
    labels = _field()
    labels[2, 2] = B
    cleaned = clean_outliers(labels)
    assert cleaned[2, 2] == W and labels[2, 2] == B  # the input is not modified
    assert np.all(np.delete(cleaned.reshape(-1), 12) == G)


def test_pixel_with_a_same_class_neighbour_is_kept() -> None:
    labels = _field()
    labels[2, 2] = labels[3, 3] = Y  # diagonal neighbours count
    assert np.array_equal(clean_outliers(labels), labels)


def test_isolated_white_pixel_becomes_green_or_orange() -> None:
    labels = _field()
    labels[2, 2] = W
    assert clean_outliers(labels)[2, 2] == G
    among_orange = _field(fill=O)
    among_orange[2, 2] = W
    assert clean_outliers(among_orange)[2, 2] == O
    few_orange = _field()
    few_orange[1, 1:4] = O  # three orange neighbours of five: still green
    few_orange[2, 2] = W
    assert clean_outliers(few_orange)[2, 2] == G


def test_white_line_is_kept() -> None:
    labels = _field()
    labels[:, 2] = W
    assert np.array_equal(clean_outliers(labels), labels)


# ---- malformed threshold files -----------------------------------------------------------


def _valid_json() -> dict:
    return ColorThresholds((ColorBox(ColorClass.GREEN, (10, 100, 10), (60, 160, 60)),), "test").to_json()


def test_valid_json_round_trips(tmp_path: Path) -> None:
    path = tmp_path / "t.json"
    ColorThresholds.from_json(_valid_json()).save(path)
    assert load_thresholds(path).to_json() == _valid_json()


@pytest.mark.parametrize(
    ("edit", "words"),
    [
        (lambda d: d["classes"].update(purple={"low": [0, 0, 0], "high": [1, 1, 1]}), ("unknown colour class", "purple")),
        (lambda d: d["classes"]["green"].update(low=[70, 100, 10]), ("green", "empty", "(70, 100, 10)")),
        (lambda d: d["classes"]["green"].update(high=[60, 256, 60]), ("green", "[0, 255]", "256")),
        (lambda d: d["classes"]["green"].update(low=[-1, 100, 10]), ("green", "[0, 255]", "-1")),
        (lambda d: d["classes"]["green"].update(low=[10, 100]), ("green", "three integers")),
        (lambda d: d["classes"]["green"].pop("high"), ("green", "'low' and 'high'")),
        (lambda d: d.pop("classes"), ("'classes'",)),
    ],
)
def test_malformed_thresholds_are_refused(edit, words, tmp_path: Path) -> None:
    data = _valid_json()
    edit(data)
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(data))
    with pytest.raises(ColorTableError) as error:
        load_thresholds(path)
    for word in words:
        assert word in str(error.value)


def test_not_json_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "bad.json"
    path.write_text("{ green: [1, 2, 3] ")
    with pytest.raises(ColorTableError, match="not valid JSON") as error:
        load_thresholds(path)
    assert str(path) in str(error.value)


HOSTILE_THRESHOLDS = {
    "nested deep": "[" * 100_000 + "]" * 100_000,
    "a number of 5,000 digits": '{"classes": {"green": {"low": [1, 2, ' + "9" * 5000 + '], "high": [1, 2, 3]}}}',
    "ends not lists": '{"classes": {"green": {"low": 5, "high": "abc"}}}',
    "over a megabyte": '{"source": "' + "a" * (1 << 20) + '", "classes": {}}',
    "not UTF-8": b"\xff\xfe{}",
    "a link to /dev/zero": Path("/dev/zero"),
    "a pipe": None,
}


@pytest.mark.parametrize("content", list(HOSTILE_THRESHOLDS.values()), ids=list(HOSTILE_THRESHOLDS))
def test_a_hostile_thresholds_file_is_refused_at_once_naming_it(content, tmp_path: Path) -> None:
    path = tmp_path / "hostile.json"
    if content is None:
        os.mkfifo(path)
    elif isinstance(content, Path):
        path.symlink_to(content)
    else:
        path.write_bytes(content if isinstance(content, bytes) else content.encode())
    started = time.perf_counter()
    with pytest.raises(ColorTableError) as error:
        load_thresholds(path)
    assert time.perf_counter() - started < 1.0
    assert str(path) in str(error.value) and len(str(error.value)) < 400


def test_missing_file_is_refused(tmp_path: Path) -> None:
    with pytest.raises(ColorTableError, match="cannot read"):
        load_thresholds(tmp_path / "missing.json")


def test_labels_are_not_colour_classes() -> None:
    assert ROBOT not in {int(c) for c in ColorClass} and OTHER not in {int(c) for c in ColorClass}
