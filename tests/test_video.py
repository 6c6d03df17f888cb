"""``robotstadium match --video``: a robot's camera video, and robots that are not on the field."""

from __future__ import annotations

from pathlib import Path

import imageio.v2 as imageio
import numpy as np
import pytest

from match.game import MatchConfig
from match.referee import RefereeConfig
from scenarios import cli
from scenarios.matches.video import MAP_WIDTH_PX, SCALE

pytestmark = pytest.mark.render

ARGS = ["--home", "team", "--home-players", "2", "--away-players", "1", "--half-seconds", "1", "--seed", "5",
        "--no-progress", "--no-shootout", "--no-replay"]


@pytest.fixture
def quick_matches(monkeypatch: pytest.MonkeyPatch) -> None:
    """Matches of the match command with short pauses before the kick-off."""
    import scenarios.matches.play as play

    original = play.match_config

    def quick_config(*args, **kwargs):
        config = original(*args, **kwargs)
        return MatchConfig(config.home_players, config.away_players,
                           referee=RefereeConfig(half_seconds=config.referee.half_seconds, initial_seconds=0.2,
                                                 ready_seconds=0.4, set_seconds=0.2, shootout=config.referee.shootout))

    monkeypatch.setattr(play, "match_config", quick_config)


def test_video_of_a_robot_is_a_playable_mp4_and_changes_nothing(
    tmp_path: Path, quick_matches: None, capsys: pytest.CaptureFixture[str]
) -> None:
    filmed, plain = tmp_path / "filmed", tmp_path / "plain"
    assert cli.main(["match", *ARGS, "--video", "home_1", "--video", "away_0", "--out", str(filmed)]) == 0
    assert str(filmed / "video_home_1.mp4") in capsys.readouterr().out
    reader = imageio.get_reader(filmed / "video_home_1.mp4")
    frames = [frame for frame in reader]
    fps = reader.get_meta_data()["fps"]
    reader.close()
    assert len(frames) > 10 and fps == pytest.approx(12.5)  # the team agent's camera: every other 40 ms step
    assert frames[0].shape == (120 * SCALE, 2 * 160 * SCALE + MAP_WIDTH_PX, 3)
    assert np.std(frames[len(frames) // 2]) > 10  # not blank
    assert (filmed / "video_away_0.mp4").stat().st_size > 0
    assert sorted(p.name for p in filmed.glob("video_*")) == ["video_away_0.mp4", "video_home_1.mp4"]
    # Evaluation only: the same match without the video plays the same.
    assert cli.main(["match", *ARGS, "--out", str(plain)]) == 0
    with np.load(filmed / "match_log.npz") as a, np.load(plain / "match_log.npz") as b:
        assert np.array_equal(a["robots"], b["robots"]) and np.array_equal(a["estimates"], b["estimates"], equal_nan=True)


@pytest.mark.parametrize("flags, words", [
    (["--video", "nobody_9"], ["--video", "nobody_9"]),
    (["--video", "home_3"], ["home_3 is not on the field"]),
    (["--video", "home_1", "--video", "away_2"], ["away_2 is not on the field"]),
])
def test_video_of_a_robot_not_on_the_field_is_refused_before_writing(
    flags: list[str], words: list[str], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "out"
    try:
        code = cli.main(["match", *ARGS, *flags, "--out", str(out)])
    except SystemExit as exit_info:
        code = exit_info.code
    assert code == 2 and not out.exists()
    message = capsys.readouterr().err
    for word in words:
        assert word in message


def test_a_frames_caption_names_the_robots_policy(tmp_path: Path) -> None:
    from types import SimpleNamespace

    from scenarios.matches.video import HEADER_PX, VideoRecorder

    match = SimpleNamespace(world=SimpleNamespace(time_s=1.0), state=SimpleNamespace(name="PLAYING"))
    captions = []
    for policies in (None, {"home_1": "team"}, {"home_1": "examples.my_team:Team" * 3}):
        recorder = VideoRecorder(tmp_path, ["home_1"], policies=policies)
        panel = recorder._panel(360, "home_1", match, (0.0, 0.0, 0.0), (0, 0, 255), None, (0.0, 0.0))
        captions.append(panel[:HEADER_PX])
        recorder.close()
    assert not np.array_equal(captions[0], captions[1])  # the policy's name is written
    assert not np.array_equal(captions[1], captions[2])
