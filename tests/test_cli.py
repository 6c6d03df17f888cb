"""The ``robotstadium`` command line: world-demo and bench outputs, and exit codes."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import cv2
import numpy as np
import pytest

from scenarios import cli
from scenarios.tools.bench import QUICK_REPEATS, run_bench
from world.errors import InvalidPoseError

CAMERA_FRAMES = (
    "camera_blue_goal",
    "camera_yellow_goal",
    "camera_center_circle",
    "camera_field_corner",
    "camera_bottom_ball",
)
OVERVIEWS = ("overview", "top_view", "kick_strip")


def _read_rgb(path: Path) -> np.ndarray:
    image = cv2.imread(str(path), cv2.IMREAD_COLOR)
    assert image is not None, f"{path} is not a readable image"
    return cv2.cvtColor(image, cv2.COLOR_BGR2RGB)


def _green(image: np.ndarray) -> np.ndarray:
    r, g, b = (image[..., i].astype(int) for i in range(3))
    return (g > r + 40) & (g > b + 40)


def _distinct_colours(image: np.ndarray) -> int:
    return len(np.unique(image.reshape(-1, 3), axis=0))


@pytest.fixture(scope="module")
def demo_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("world-demo")
    assert cli.main(["world-demo", "--out", str(out), "--seed", "1"]) == 0
    return out


@pytest.mark.render
@pytest.mark.parametrize("name", CAMERA_FRAMES)
def test_camera_frames_are_enlarged_and_show_the_field(demo_dir: Path, name: str) -> None:
    image = _read_rgb(demo_dir / f"{name}.png")
    assert image.shape == (480, 640, 3)
    # Nearest-neighbour 4x: every 4x4 block is one camera pixel.
    assert np.array_equal(image, np.repeat(np.repeat(image[::4, ::4], 4, axis=0), 4, axis=1))
    assert _distinct_colours(image) >= 4
    assert _green(image).mean() > 0.2


@pytest.mark.render
@pytest.mark.parametrize(
    ("name", "colour"),
    [
        ("camera_blue_goal", lambda r, g, b: (b > r + 80) & (b > g + 60)),
        ("camera_yellow_goal", lambda r, g, b: (r > b + 80) & (g > b + 80)),
        ("camera_bottom_ball", lambda r, g, b: (r > g + 60) & (g > b + 20)),
    ],
)
def test_camera_frames_show_what_the_index_says(demo_dir: Path, name: str, colour) -> None:
    image = _read_rgb(demo_dir / f"{name}.png")
    r, g, b = (image[..., i].astype(int) for i in range(3))
    assert colour(r, g, b).mean() > 0.005


@pytest.mark.render
@pytest.mark.parametrize("name", OVERVIEWS)
def test_overviews_are_not_blank(demo_dir: Path, name: str) -> None:
    image = _read_rgb(demo_dir / f"{name}.png")
    assert image.shape[0] >= 480 and image.shape[1] >= 640
    assert _distinct_colours(image) >= 20
    assert _green(image).mean() > 0.1


@pytest.mark.render
def test_index_lists_every_image(demo_dir: Path) -> None:
    index = (demo_dir / "index.md").read_text(encoding="utf-8")
    for name in CAMERA_FRAMES + OVERVIEWS:
        assert f"({name}.png)" in index
    assert sorted(p.stem for p in demo_dir.glob("*.png")) == sorted(CAMERA_FRAMES + OVERVIEWS)


@pytest.mark.render
def test_bench_writes_positive_timings(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert cli.main(["bench", "--out", str(tmp_path), "--quick"]) == 0
    results = json.loads((tmp_path / "bench.json").read_text(encoding="utf-8"))
    for key in ("render_ms_median", "render_ms_p90", "physics_step_ms_median", "physics_step_ms_p90",
                "agent_act_ms_median", "agent_act_frame_ms_median"):
        value = results[key]
        assert isinstance(value, float) and math.isfinite(value) and value > 0.0, (key, value)
    assert results["render_ms_p90"] >= results["render_ms_median"]
    for key in ("env_steps_per_s", "render_physics_only_steps_per_s", "env_over_render_physics_ratio", "match_real_time_factor",
                "vec_env_steps_per_s", "vec_env_steps_per_s_cameras_off", "vec_env_agent_steps_per_s",
                "broadcast_render_fps", "env_steps_per_s_cameras_off", "env_step_cameras_off_ms_median"):
        assert isinstance(results[key], float) and results[key] > 0.0, (key, results[key])
    assert results["vec_env_agent_steps_per_s"] == pytest.approx(8 * results["vec_env_steps_per_s"])
    assert results["env_steps_per_s_cameras_off"] > results["env_steps_per_s"]  # no frames to render
    if sys.platform.startswith("linux"):
        simulator, controllers = results["peak_rss_simulator_mb"], results["peak_rss_controllers_mb"]
        assert simulator > 20.0 and controllers > 20.0, (simulator, controllers)
        assert results["peak_rss_mb"] == pytest.approx(simulator + controllers)
    assert results["repeats"] == QUICK_REPEATS
    machine = results["machine"]
    assert machine["cpu_count"] >= 1 and machine["pybullet_api_version"] > 0 and machine["python"]
    assert "numpy_simd" in machine and machine["architecture"]
    assert "render" in capsys.readouterr().out


@pytest.mark.parametrize(
    "argv",
    [
        ["bench", "--out", "unused", "--repeats", "-1"],
        ["bench", "--out", "unused", "--repeats", "many"],
        ["bench", "--out", "unused", "--quick", "--repeats", "5"],
        ["bench"],
        ["localize", "--methods", "thesis,kalman"],
        ["localize", "--methods", "thesis,thesis"],
        ["localize", "--samples", "0"],
        ["no-such-command"],
        [],
    ],
)
def test_bad_arguments_exit_with_2(argv: list[str]) -> None:
    with pytest.raises(SystemExit) as exit_info:
        cli.main(argv)
    assert exit_info.value.code == 2


def test_library_errors_give_one_line_and_exit_2(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    def refuse(out_dir: Path, seed: int = 0) -> list[Path]:
        raise InvalidPoseError("robot 'home_0' pose (9.0, 0.0) outside the world")

    monkeypatch.setattr(cli.world_demo, "run_world_demo", refuse)
    assert cli.main(["world-demo", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "outside the world" in err and "Traceback" not in err
    assert len(err.strip().splitlines()) == 1


def test_run_bench_refuses_non_positive_repeats(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="repeats"):
        run_bench(tmp_path, repeats=0)


def test_module_entry_point(tmp_path: Path) -> None:
    result = subprocess.run(
        [sys.executable, "-m", "scenarios.cli", "bench", "--out", str(tmp_path), "--repeats", "0"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode == 2
    assert "argument --repeats: expected an integer in [1, " in result.stderr


def test_localize_prints_one_row_per_method(capsys: pytest.CaptureFixture[str]) -> None:
    assert cli.main(["localize", "--samples", "2", "--seed", "1", "--methods", "thesis,odometry"]) == 0
    out = capsys.readouterr().out
    assert "| thesis | " in out and "| odometry | " in out and "2 samples" in out


@pytest.mark.parametrize("command", [c.NAME for c in cli.SUBCOMMANDS])
def test_every_command_prints_its_help(command: str, capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exit_info:
        cli.main([command, "--help"])
    assert exit_info.value.code == 0 and command in capsys.readouterr().out
