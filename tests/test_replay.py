"""The replay page's data, the figures, refused logs and the replay command (no browser here).

The browser tests of the page are in tests/test_replay_browser.py.
"""

from __future__ import annotations

import argparse
import json
import re
import shutil
from dataclasses import replace
from pathlib import Path

import cv2
import numpy as np
import pytest

from scenarios import cli
from scenarios.cli import match as match_command
from scenarios.cli import replay as replay_command
from scenarios.replay import ReplayInputError, data, load_match, write_replay
from scenarios.replay.page import render_page
from scenarios.replay.synthetic import Fall, Goal, synthetic_match
from world.field import FIELD

HALF_S = 30.0
DT_MS = 40


@pytest.fixture(scope="module")
def synthetic(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Two halves of 30 s, 2 v 2, goals at 10 s of play in each half, home robots estimate."""
    return synthetic_match(tmp_path_factory.mktemp("synthetic"), half_seconds=HALF_S,
                           goals=(Goal(1, 10.0, "home"), Goal(2, 12.0, "away")))


@pytest.fixture
def match_dir(synthetic: Path, tmp_path: Path) -> Path:
    """A private copy of the synthetic match (tests may damage or add files)."""
    return Path(shutil.copytree(synthetic, tmp_path / "match"))


@pytest.fixture
def with_replay_command(monkeypatch: pytest.MonkeyPatch) -> None:
    """``robotstadium replay`` registered in the command line for this test."""
    if replay_command not in cli.SUBCOMMANDS:
        monkeypatch.setattr(cli, "SUBCOMMANDS", (*cli.SUBCOMMANDS, replay_command))


def _events(directory: Path) -> list[dict]:
    return [json.loads(line) for line in (directory / "events.jsonl").read_text().splitlines()]


def _embedded(page: str) -> dict:
    match = re.search(r'<script type="application/json" id="replay-data">(.*?)</script>', page, re.S)
    assert match, "no embedded data"
    return json.loads(match.group(1))


# ---- the data ---------------------------------------------------------------------------------


def test_record_reads_what_the_match_wrote(synthetic: Path) -> None:
    record = load_match(synthetic)
    assert record.agents == ("home_0", "home_1", "away_0", "away_1")
    assert record.robots.shape == (record.steps, 4, 3)
    assert record.half_seconds == HALF_S
    assert [record.has_estimates(i) for i in range(4)] == [True, True, False, False]
    assert len(record.events) == len(_events(synthetic))


def test_score_board_follows_the_goals_and_the_halves(synthetic: Path) -> None:
    built = data.replay_data(load_match(synthetic))
    goals = [e for e in built["events"] if e["kind"] == "goal"]
    assert [g["t"] for g in goals] == [round(e["time_s"] * 1000) for e in _events(synthetic) if e["kind"] == "goal"]

    def at(t_ms: int) -> dict:
        return [s for s in built["status"] if s["t"] <= t_ms][-1]

    states = built["match"]["states"]
    assert at(goals[0]["t"] - DT_MS)["score"] == [0, 0]
    assert at(goals[0]["t"])["score"] == [1, 0]
    assert states[at(goals[0]["t"])["state"]] == "READY"
    assert at(goals[1]["t"])["score"] == [1, 1]
    assert at(0)["home_color"] == "blue" and at(0)["half"] == 1
    assert at(goals[1]["t"])["home_color"] == "red" and at(goals[1]["t"])["half"] == 2
    # The half clock: full at the kick-off, 10 s of play gone at the first goal, stopped until play resumes.
    t = np.array(built["frames"]["t"])
    clock = np.array(built["frames"]["clock"]["data"]) / built["frames"]["clock"]["scale"]
    kickoff = next(e["t"] for e in built["events"] if e["kind"] == "kickoff")
    assert clock[t == kickoff][0] == pytest.approx(HALF_S)
    assert clock[t == goals[0]["t"]][0] == pytest.approx(HALF_S - 10.0, abs=0.05)
    assert clock[t == goals[0]["t"] + 5000][0] == pytest.approx(HALF_S - 10.0, abs=0.05)


def test_long_matches_are_sampled_but_events_stay_exact(synthetic: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    record = load_match(synthetic)
    monkeypatch.setattr(data, "MAX_FRAMES", 500)
    built = data.replay_data(record)
    stride = built["match"]["stride"]
    assert stride == -(-record.steps // 500)
    t = built["frames"]["t"]
    assert len(t) <= 501 and t[-1] == round(record.time_s[-1] * 1000) and t[1] - t[0] == stride * DT_MS
    robot = built["robots"][0]["channels"]["pose"]
    assert robot["dims"] == 3 and len(robot["data"]) == 3 * len(t)
    assert [e["t"] for e in built["events"]] == [round(e["time_s"] * 1000) for e in record.events]
    assert data.replay_data(record, stride=1)["frames"]["t"] == [round(s * 1000) for s in record.time_s]


def test_channels_hold_what_robots_report(synthetic: Path) -> None:
    built = data.replay_data(load_match(synthetic))
    channels = {r["id"]: r["channels"] for r in built["robots"]}
    assert set(channels["home_0"]) == {"pose", "fallen", "estimate"}
    assert set(channels["away_0"]) == {"pose", "fallen"}  # no estimate: no channel, so no toggle
    estimate = channels["home_0"]["estimate"]["data"]
    assert estimate[0] is None and any(v is not None for v in estimate)  # NaN before the first estimate
    assert set(channels["away_1"]["fallen"]["data"]) == {0, 1}


def test_per_robot_extras_become_channels(tmp_path: Path) -> None:
    directory = synthetic_match(tmp_path / "extras", half_seconds=10.0, goals=(), extras=True)
    built = data.replay_data(load_match(directory))
    home = built["robots"][0]
    assert {"estimate", "ball_estimate", "team_ball", "role", "landmarks"} <= set(home["channels"])
    assert home["channels"]["ball_estimate"]["dims"] == 2
    assert built["labels"]["role"][:2] == ["keeper", "striker"]
    masks = {v for v in home["channels"]["landmarks"]["data"] if v}
    assert masks == {1 | 1 << 6}  # a bit per landmark of FIELD.landmarks


def test_the_field_comes_from_world_field(synthetic: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    field = data.field_data()
    assert (field["length"], field["width"], field["carpet_margin"]) == (6.0, 4.0, 0.7)
    assert (field["line_width"], field["center_circle_radius"], field["goal_post_y"]) == (0.05, 0.6, 0.75)
    assert (field["goal_area_depth"], field["goal_area_width"]) == (0.6, 2.2)
    monkeypatch.setattr(data, "FIELD", replace(FIELD, length=9.0, goal_area_width=3.0))
    field = data.replay_data(load_match(synthetic))["field"]
    assert field["length"] == 9.0 and [4.5, -2.0, 4.5, 2.0] in field["lines"]
    assert [3.9, -1.5, 3.9, 1.5] in field["lines"]


def test_the_page_is_self_contained(synthetic: Path) -> None:
    page = render_page(data.replay_data(load_match(synthetic)))
    assert "<link" not in page and not re.search(r"<script[^>]+src=", page)
    assert not re.search(r"(https?:)?//[a-z0-9.-]+\.[a-z]{2,}/", page), "the page must not fetch anything"
    assert "@import" not in page and "url(" not in page
    assert "__DATA__" not in page and "__JS__" not in page and "__CSS__" not in page
    embedded = _embedded(page)
    assert embedded["format"] == data.FORMAT and len(embedded["robots"]) == 4


def test_embedded_text_cannot_close_the_script(synthetic: Path) -> None:
    built = data.replay_data(load_match(synthetic))
    built["events"].append({"t": 0, "kind": "fault", "error": "</script><script>alert(1)</script>"})
    page = render_page(built)
    assert page.count("</script>") == 2
    assert _embedded(page)["events"][-1]["error"] == "</script><script>alert(1)</script>"


# ---- the files -----------------------------------------------------------------------------


def _image(path: Path) -> np.ndarray:
    image = cv2.imread(str(path), cv2.IMREAD_COLOR)
    assert image is not None, f"{path} is not an image"
    return image


def test_replay_command_writes_the_page_and_the_figures(match_dir: Path, with_replay_command, capsys) -> None:
    assert cli.main(["replay", str(match_dir), "--plots"]) == 0
    printed = capsys.readouterr().out.split()
    assert printed == [str(match_dir / name) for name in ("replay.html", "traces.png", "localization.png")]
    traces, errors = _image(match_dir / "traces.png"), _image(match_dir / "localization.png")
    assert traces.shape[1] > 1000 and len(np.unique(traces.reshape(-1, 3), axis=0)) > 20  # two panels, drawn
    assert errors.shape[0] > 300 and len(np.unique(errors.reshape(-1, 3), axis=0)) > 20


def test_replay_command_out_and_stride(match_dir: Path, tmp_path: Path, with_replay_command) -> None:
    out = tmp_path / "elsewhere" / "page.html"
    assert cli.main(["replay", str(match_dir), "--out", str(out), "--stride", "3"]) == 0
    assert out.is_file() and not (match_dir / "replay.html").exists() and not (out.parent / "traces.png").exists()
    assert _embedded(out.read_text())["match"]["stride"] == 3


def test_figures_without_estimates(tmp_path: Path) -> None:
    directory = synthetic_match(tmp_path / "none", half_seconds=10.0, estimators=(), falls=())
    written = write_replay(directory, plots=True)
    assert [p.name for p in written] == ["replay.html", "traces.png", "localization.png"]
    assert _image(directory / "traces.png").shape[0] > 300


def test_the_parser_of_the_replay_command() -> None:
    parser = argparse.ArgumentParser()
    replay_command.add_arguments(parser)
    args = parser.parse_args(["out/match", "--plots"])
    assert args.match_dir == Path("out/match") and args.plots and args.out is None and args.stride is None
    assert replay_command.NAME == "replay" and replay_command.run.__name__ == "run"


# ---- refused logs ----------------------------------------------------------------------------


def _npz_rewrite(directory: Path, change) -> None:
    path = directory / "match_log.npz"
    with np.load(path) as npz:
        arrays = {k: npz[k] for k in npz.files}
    change(arrays)
    path.unlink()
    np.savez_compressed(path, **arrays)


def _truncate(path: Path, keep: float) -> None:
    raw = path.read_bytes()
    path.write_bytes(raw[: int(len(raw) * keep)])


CORRUPTIONS = {
    "missing log": (lambda d: (d / "match_log.npz").unlink(), "match_log.npz: missing"),
    "missing events": (lambda d: (d / "events.jsonl").unlink(), "events.jsonl: missing"),
    "not an npz": (lambda d: (d / "match_log.npz").write_bytes(b"not a zip file"), "match_log.npz: not a readable .npz"),
    "truncated npz": (lambda d: _truncate(d / "match_log.npz", 0.5), "match_log.npz: not a readable .npz"),
    "truncated events line": (
        lambda d: (d / "events.jsonl").write_text((d / "events.jsonl").read_text()[:-25]),
        "events.jsonl: line",
    ),
    "mismatched lengths": (
        lambda d: _npz_rewrite(d, lambda a: a.update(robots=a["robots"][:-1])),
        "match_log.npz: arrays of mismatched lengths: robots",
    ),
    "mismatched estimates": (
        lambda d: _npz_rewrite(d, lambda a: a.update(estimates=a["estimates"][:, :1])),
        "match_log.npz: arrays of mismatched lengths: estimates",
    ),
    "missing array": (lambda d: _npz_rewrite(d, lambda a: a.pop("fallen")), "match_log.npz: no array fallen"),
    "bad summary": (lambda d: _truncate(d / "summary.json", 0.5), "summary.json: not valid JSON"),
}


@pytest.mark.parametrize("case", list(CORRUPTIONS))
def test_a_damaged_log_is_refused_in_one_line_and_nothing_is_written(
    case: str, match_dir: Path, tmp_path: Path, with_replay_command, capsys
) -> None:
    damage, message = CORRUPTIONS[case]
    damage(match_dir)
    before = sorted(p.name for p in match_dir.iterdir())
    out = tmp_path / "out" / "page.html"
    assert cli.main(["replay", str(match_dir), "--plots"]) == 2
    assert cli.main(["replay", str(match_dir), "--out", str(out), "--plots"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 2 and err[0] == err[1], err
    assert err[0].startswith("robotstadium replay: error: ") and message in err[0], err[0]
    assert str(match_dir) in err[0]
    assert sorted(p.name for p in match_dir.iterdir()) == before
    assert not (tmp_path / "out").exists()
    with pytest.raises(ValueError):
        load_match(match_dir)


def test_truncated_events_line_is_named(match_dir: Path) -> None:
    path = match_dir / "events.jsonl"
    lines = path.read_text().splitlines()
    path.write_text("\n".join(lines[:-1]) + "\n" + lines[-1][:10])
    with pytest.raises(ReplayInputError, match=rf"events.jsonl: line {len(lines)}: not valid JSON .*truncated"):
        load_match(match_dir)


def test_not_a_match_directory(tmp_path: Path) -> None:
    with pytest.raises(ReplayInputError, match="not a directory"):
        load_match(tmp_path / "nowhere")


def test_a_match_without_summary_still_plays(match_dir: Path) -> None:
    (match_dir / "summary.json").unlink()  # an interrupted match leaves none
    record = load_match(match_dir)
    assert record.summary is None and record.half_seconds == 600.0
    assert _embedded(render_page(data.replay_data(record)))["match"]["summary"]["score"] is None


# ---- the match command -----------------------------------------------------------------------


class _FakeSummary:
    score = {"home": 1, "away": 1}
    shootout = None
    sim_seconds = 136.0
    wall_seconds = 1.0
    real_time_factor = 136.0
    played_by = {"policies": {"home_0": {"policy": "team"}, "away_0": {"policy": "scripted"}}}


@pytest.fixture
def fake_match(monkeypatch: pytest.MonkeyPatch):
    """``robotstadium match`` with a synthetic match instead of the simulator."""
    import scenarios.matches.play as play

    def run_lineup_match(out_dir, lineup, **kwargs):
        synthetic_match(out_dir, half_seconds=kwargs["half_seconds"], goals=(Goal(1, 5.0, "home"),),
                        falls=(Fall("home_0", 2, 3.0),))
        return _FakeSummary()

    monkeypatch.setattr(play, "run_lineup_match", run_lineup_match)


def test_match_writes_the_page_and_figures(fake_match, tmp_path: Path, capsys) -> None:
    out = tmp_path / "m"
    assert cli.main(["match", "--out", str(out), "--half-seconds", "10", "--no-progress"]) == 0
    printed = capsys.readouterr().out.splitlines()
    assert printed[0].startswith("team vs scripted: home 1 - 1 away; 136 s simulated")  # the teams by their policies
    assert printed[-3:] == [str(out / "replay.html"), str(out / "traces.png"), str(out / "localization.png")]
    assert _embedded((out / "replay.html").read_text())["match"]["half_seconds"] == 10.0


def test_match_no_replay(fake_match, tmp_path: Path) -> None:
    out = tmp_path / "m"
    assert cli.main(["match", "--out", str(out), "--half-seconds", "10", "--no-progress", "--no-replay"]) == 0
    assert sorted(p.name for p in out.iterdir()) == ["events.jsonl", "match_log.npz", "summary.json"]
    assert match_command.NAME == "match"


def test_the_teams_are_named_by_their_policies() -> None:
    from scenarios.replay.data import teams_by_policy

    played = {"played_by": {"policies": {"home_0": {"policy": "team"}, "home_1": {"policy": "team"},
                                         "away_0": {"policy": "scripted"}, "away_1": {"policy": "stand"}}}}
    assert teams_by_policy(played) == "team vs scripted+stand"
    assert teams_by_policy({}) is None and teams_by_policy({"played_by": {"policies": "x"}}) is None


def test_the_settings_panel_lists_what_the_summary_recorded_as_text() -> None:
    from scenarios.replay.data import SETTING_CHARS, match_settings

    summary = {"seed": 7, "played_by": {"policies": {"home_0": {"policy": "team:p.toml", "file_hash": "ab12"}},
                                        "controllers": {"in_process": False, "step_budget_s": 0.5}},
               "config": {"home_players": 1, "away_players": 2, "half_seconds": 30.0,
                          "world": {"camera_profile": "nao", "render": {"renderer": "numba"}}},
               "command_line": ["robotstadium", "match", "--seed", "7"], "versions": {"numpy": "2"},
               "machine": {"cpu": "<b>x</b>" * 200}}
    rows = dict(match_settings(summary))
    assert rows["home_0"] == "team:p.toml, file_hash ab12"
    assert (rows["seed"], rows["players"], rows["half"]) == ("7", "1 v 2", "30 s")
    assert (rows["camera profile"], rows["renderer"], rows["command"]) == ("nao", "numba", "robotstadium match --seed 7")
    assert rows["controllers"] == "in_process False, step_budget_s 0.5"
    assert len(rows["machine"]) == SETTING_CHARS  # cut; the page sets it as text, never as markup
    assert match_settings({}) == [] and match_settings({"config": "x", "played_by": 3}) == []


def test_a_settings_value_cannot_close_the_script(synthetic: Path) -> None:
    built = data.replay_data(load_match(synthetic))
    built["settings"] = [["command", "</script><script>alert(1)</script>"]]
    page = render_page(built)
    assert page.count("</script>") == 2
    assert _embedded(page)["settings"][0][1] == "</script><script>alert(1)</script>"
