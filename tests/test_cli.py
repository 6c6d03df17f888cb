"""The ``robotstadium`` command line: world-demo and bench outputs, and exit codes."""

from __future__ import annotations

import json
import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import cv2
import numpy as np
import pytest

from scenarios import cli
from scenarios.tools.bench import (
    QUICK_REPEATS,
    RENDER_WARMUP,
    BenchFileError,
    Comparison,
    bench_render,
    compare_results,
    format_comparison,
    read_bench_file,
    run_bench,
    worse_when,
)
from world.backdrop import HallBackdrop
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
def test_the_camera_frame_benchmark_draws_every_frame_from_a_new_pose(monkeypatch: pytest.MonkeyPatch) -> None:
    """A robot camera always moves in a match; the world keeps the hall of its last few camera poses, and
    a benchmark camera that never moved would be timed without the hall drawn."""
    drawn = []
    draw = HallBackdrop._draw
    monkeypatch.setattr(HallBackdrop, "_draw", lambda self, *args: drawn.append(1) or draw(self, *args))
    bench_render(5)
    assert len(drawn) == 5 + RENDER_WARMUP


@pytest.mark.render
def test_bench_writes_positive_timings(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert cli.main(["bench", "--out", str(tmp_path), "--quick"]) == 0
    results = json.loads((tmp_path / "bench.json").read_text(encoding="utf-8"))
    for key in ("render_ms_median", "render_ms_p90", "physics_step_ms_median", "physics_step_ms_p90",
                "agent_act_ms_median", "agent_act_frame_ms_median", "render_ms_median_tiny",
                "cameras_per_step_ms_median", "cameras_per_step_ms_median_serial", "cameras_per_step_ms_median_tiny"):
        value = results[key]
        assert isinstance(value, float) and math.isfinite(value) and value > 0.0, (key, value)
    assert results["render_ms_p90"] >= results["render_ms_median"]
    for key in ("env_steps_per_s", "render_physics_only_steps_per_s", "env_over_render_physics_ratio", "match_real_time_factor",
                "vec_env_steps_per_s", "vec_env_steps_per_s_cameras_off", "vec_env_agent_steps_per_s",
                "broadcast_render_fps", "env_steps_per_s_cameras_off", "env_step_cameras_off_ms_median",
                "env_steps_per_s_tiny", "env_step_ms_median_tiny", "learner_view_flat_steps_per_s",
                "learner_view_image_steps_per_s", "learner_view_percepts_steps_per_s",
                "learner_view_percepts_over_env_ratio"):
        assert isinstance(results[key], float) and results[key] > 0.0, (key, results[key])
    assert results["vec_env_agent_steps_per_s"] == pytest.approx(8 * results["vec_env_steps_per_s"])
    assert results["env_steps_per_s_cameras_off"] > results["env_steps_per_s"]  # no frames to render
    if sys.platform.startswith("linux"):
        simulator, controllers = results["peak_rss_simulator_mb"], results["peak_rss_controllers_mb"]
        assert simulator > 20.0 and controllers > 20.0, (simulator, controllers)
        assert results["peak_rss_mb"] == pytest.approx(simulator + controllers)
        assert results["memory_matches"] == 3.0  # a match per 10 repeats, 3 at least
        second, last = results["rss_second_match_mb"], results["rss_last_match_mb"]
        assert results["rss_first_match_mb"] > 20.0 and second > 20.0 and last > 20.0
        assert results["rss_growth_share"] == pytest.approx((last - second) / second)
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


@pytest.mark.parametrize(
    ("key", "direction"),
    [("render_ms_median", "higher"), ("env_step_cameras_off_ms_p90", "higher"), ("env_steps_per_s", "lower"),
     ("vec_env_steps_per_s_cameras_off", "lower"), ("broadcast_render_fps", "lower"),
     ("match_real_time_factor", "lower"), ("peak_rss_mb", "higher"), ("peak_rss_controllers_mb", "higher"),
     ("rss_last_match_mb", "higher"), ("rss_growth_share", "higher"),
     ("repeats", None), ("match_steps", None), ("env_over_render_physics_ratio", None)],
)
def test_which_way_a_bench_key_gets_worse(key: str, direction: str | None) -> None:
    assert worse_when(key) == direction


def test_compare_results_gives_ratios_and_marks_changes_beyond_10_percent() -> None:
    old = {"render_ms_median": 4.0, "agent_act_ms_median": 1.0, "physics_step_ms_median": 2.0,
           "env_steps_per_s": 20.0, "broadcast_render_fps": 50.0, "match_real_time_factor": 0.5,
           "peak_rss_mb": 300.0, "repeats": 200, "only_old_ms_median": 1.0, "machine": {"cpu": "x"}}
    new = {"render_ms_median": 5.0, "agent_act_ms_median": 0.8, "physics_step_ms_median": 2.1,
           "env_steps_per_s": 16.0, "broadcast_render_fps": 60.0, "match_real_time_factor": 0.5,
           "peak_rss_mb": 360.0, "repeats": 20, "only_new_fps": 3.0, "machine": {"cpu": "x"}}
    rows = {row.key: row for row in compare_results(new, old)}
    assert list(rows) == ["render_ms_median", "agent_act_ms_median", "physics_step_ms_median", "env_steps_per_s",
                          "broadcast_render_fps", "match_real_time_factor", "peak_rss_mb", "repeats"]
    assert rows["render_ms_median"] == Comparison("render_ms_median", 5.0, 4.0, 1.25, "higher", "worse")
    assert rows["agent_act_ms_median"].ratio == pytest.approx(0.8) and rows["agent_act_ms_median"].mark == "better"
    assert rows["physics_step_ms_median"].ratio == pytest.approx(1.05) and rows["physics_step_ms_median"].mark == ""
    assert (rows["env_steps_per_s"].ratio, rows["env_steps_per_s"].mark) == (0.8, "worse")
    assert (rows["broadcast_render_fps"].ratio, rows["broadcast_render_fps"].mark) == (1.2, "better")
    assert rows["match_real_time_factor"].mark == "" and rows["peak_rss_mb"].mark == "worse"
    assert (rows["repeats"].ratio, rows["repeats"].worse_when, rows["repeats"].mark) == (0.1, None, "")
    table = format_comparison(list(rows.values()), "old.json")
    assert "render_ms_median" in table and "1.250" in table
    assert table.splitlines()[-1] == "against old.json: 3 worse, 2 better by more than 10%"


def test_compare_results_skips_non_numbers_and_has_no_ratio_to_zero() -> None:
    old = {"render_ms_median": 0.0, "env_steps_per_s": float("nan"), "broadcast_render_fps": True,
           "agent_act_ms_median": "1.0"}
    new = {"render_ms_median": 1.0, "env_steps_per_s": 20.0, "broadcast_render_fps": 50.0, "agent_act_ms_median": 1.0}
    assert compare_results(new, old) == [Comparison("render_ms_median", 1.0, 0.0, None, "higher", "")]


def test_bench_compare_prints_the_ratios_and_writes_compare_json(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    old_file = tmp_path / "old.json"
    old_file.write_text(json.dumps({"render_ms_median": 4.0, "env_steps_per_s": 20.0, "repeats": 20}))
    new = {"repeats": 20, "render_ms_median": 5.0, "env_steps_per_s": 21.0}
    monkeypatch.setattr(cli.bench, "run_bench", lambda out_dir, repeats: new)  # no benchmark run here
    assert read_bench_file(old_file)["render_ms_median"] == 4.0
    assert cli.main(["bench", "--out", str(tmp_path / "out"), "--quick", "--compare", str(old_file)]) == 0
    out = capsys.readouterr().out
    assert "worse" in out and f"against {old_file}: 1 worse, 0 better" in out
    compare = json.loads((tmp_path / "out" / "compare.json").read_text(encoding="utf-8"))
    assert compare["old"] == str(old_file) and compare["worse"] == ["render_ms_median"] and compare["better"] == []
    assert compare["rows"]["env_steps_per_s"] == {"new": 21.0, "old": 20.0, "ratio": 1.05, "worse_when": "lower",
                                                  "mark": ""}


def test_read_bench_file_names_the_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    Path("old.json").write_text('{"repeats": 20, "machine": {}}', encoding="utf-8")
    with pytest.raises(BenchFileError, match=r"^old\.json: no benchmark figure; expected a bench\.json"):
        read_bench_file(Path("old.json"))


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


@pytest.mark.parametrize("delay_s", [0.0, 3.0], ids=["starting", "playing"])
def test_a_sigterm_stops_a_match_as_ctrl_c_does_and_leaves_its_outputs(tmp_path: Path, delay_s: float) -> None:
    """``kill PID`` of ``robotstadium match``, while its controllers start or while it plays: exit code 130,
    a one-line message, and the outputs of what was played (``summary.json`` with ``completed`` false), as
    after Ctrl-C."""
    out = tmp_path / "match"
    command = [sys.executable, "-m", "scenarios.cli", "match", "--home-players", "1", "--away-players", "1",
               "--half-seconds", "60", "--no-progress", "--no-replay", "--out", str(out)]
    root = Path(__file__).resolve().parents[1]
    match = subprocess.Popen(command, cwd=root, env={**os.environ, "PYTHONPATH": str(root)},
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 120
        while not (out / "events.jsonl").exists() and time.monotonic() < deadline:  # the match is being set up
            time.sleep(0.1)
        time.sleep(delay_s)
        match.send_signal(signal.SIGTERM)
        _, stderr = match.communicate(timeout=60)
    finally:
        match.kill()
    assert match.returncode == 130, stderr
    assert "robotstadium match: interrupted" in stderr and "Traceback" not in stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["completed"] is False and summary["stopped_reason"] == "interrupted"


def _interrupt(*_args, **_kwargs):
    raise KeyboardInterrupt


def test_a_match_interrupted_before_it_began_says_nothing_was_written(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    import scenarios.matches.play as play

    monkeypatch.setattr(play, "run_lineup_match", _interrupt)
    code = cli.main(["match", "--home", "stand", "--away", "stand", "--out", str(tmp_path / "never")])
    stderr = capsys.readouterr().err
    assert code == cli.EXIT_INTERRUPTED and "nothing was written" in stderr and "never" not in stderr
    assert not (tmp_path / "never").exists()


def test_a_match_interrupted_while_its_replay_page_is_written_ends_with_130(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    import scenarios.replay as replay

    monkeypatch.setattr(replay, "write_replay", _interrupt)
    code = cli.main(["match", "--home", "stand", "--away", "stand", "--home-players", "1", "--away-players", "1",
                     "--half-seconds", "1", "--no-shootout", "--no-progress", "--in-process",
                     "--out", str(tmp_path)])
    stderr = capsys.readouterr().err
    assert code == cli.EXIT_INTERRUPTED and "replay page" in stderr and "Traceback" not in stderr
    assert json.loads((tmp_path / "summary.json").read_text(encoding="utf-8"))["completed"] is True


def test_any_command_interrupted_ends_with_130_and_one_line(
        monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    from scenarios.cli import localize

    monkeypatch.setattr(localize, "run", _interrupt)  # read when the parser is built
    assert cli.main(["localize"]) == cli.EXIT_INTERRUPTED
    assert capsys.readouterr().err.strip() == "robotstadium localize: interrupted"
