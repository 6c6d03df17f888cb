"""The throw-in drill (examples/throw_in_drill.py): the ball is rolled out once the play has begun, the
referee's put-back and the first touch after it end a trial, the results are written, bad flags end it
with exit code 2 before anything is written."""

from __future__ import annotations

import importlib.util
import json
import sys
from pathlib import Path
from types import SimpleNamespace

import pytest

from match.events import EventKind, MatchEvent
from match.protocol import GameState

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "throw_in_drill.py"


@pytest.fixture(scope="module")
def drill():
    spec = importlib.util.spec_from_file_location("throw_in_drill", EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclasses look their module up
    spec.loader.exec_module(module)
    return module


@pytest.mark.render
def test_a_short_drill_rolls_the_ball_out_and_writes_its_trials(drill, tmp_path) -> None:
    out = tmp_path / "throw_in"
    assert drill.main(["--players", "1", "--trials", "1", "--seconds", "1", "--out", str(out)]) == 0
    results = json.loads((out / "results.json").read_text())
    [trial] = results["trials"]
    assert trial["seed"] == 0 and abs(trial["roll_y"]) == drill.ROLL_FROM_Y_M
    # the keepers stay in their goals: the ball goes out and is put back on the throw-in line, 1 s passes untouched
    assert trial["spot_y"] == pytest.approx(1.6 if trial["roll_y"] > 0 else -1.6, abs=0.01)
    assert trial["outcome"] == "none" and trial["wait_s"] is None
    assert trial["home_nearest_m"] > 1.0 and trial["away_nearest_m"] > 1.0
    assert results["summary"]["put_back"] == 1 and results["summary"]["touched_within_10_s"] == 0
    assert results["settings"]["players"] == 1


class _World:
    def __init__(self):
        self.time_s = 0.0
        self.placed: list[tuple[float, ...]] = []

    def place_ball(self, *args):
        self.placed.append(args)

    def robot_pose(self, robot):
        return SimpleNamespace(x=0.0, y=1.0 if robot == "home_1" else -1.0)


def test_the_referee_rolls_once_and_ends_at_the_first_touch_after_the_put_back(drill) -> None:
    world = _World()
    match = SimpleNamespace(world=world, state=GameState.SET, events=[], agent_names=("home_1", "away_1"))
    referee = drill.Referee((0.5, 1.2), limit_s=20.0)
    referee.decided(match, {})
    assert world.placed == []  # not playing yet
    match.state = GameState.PLAYING
    for time_s in (1.0, 1.3, 1.6):
        world.time_s = time_s
        referee.decided(match, {})
    assert world.placed == [(0.5, 1.2, 0.0, drill.ROLL_MPS)]  # once, ROLL_AFTER_S into the play
    match.events = [MatchEvent(2.0, EventKind.TOUCH, {"robot": "home_1"}),  # before the put-back: not counted
                    MatchEvent(4.0, EventKind.THROW_IN, {"x": 0.5, "y": 1.6, "line": "side_line"})]
    world.time_s = 4.0
    assert not referee.done(match)
    assert referee.throw_in == {"time_s": 4.0, "x": 0.5, "y": 1.6, "home_nearest_m": 0.781, "away_nearest_m": 2.648}
    match.events.append(MatchEvent(9.5, EventKind.TOUCH, {"robot": "away_1"}))
    world.time_s = 9.5
    assert referee.done(match) and referee.outcome == ("away", 5.5, "away_1")


def test_a_put_back_nobody_touches_in_time_ends_the_trial(drill) -> None:
    world = _World()
    match = SimpleNamespace(world=world, state=GameState.PLAYING, agent_names=("home_1",),
                            events=[MatchEvent(3.0, EventKind.THROW_IN, {"x": 0.0, "y": -1.6})])
    referee = drill.Referee((0.0, -1.2), limit_s=5.0)
    referee.decided(match, {})
    world.time_s = 0.5
    referee.decided(match, {})
    world.time_s = 7.9
    assert not referee.done(match)
    world.time_s = 8.0
    assert referee.done(match) and referee.outcome == ("none", None, None)


@pytest.mark.parametrize("flags", [
    ["--trials", "0"], ["--trials", "nan"], ["--seconds", "601"], ["--seed", "-1"], ["--players", "5"],
    ["--players", "x"], ["--home", "no_such_policy"], ["--away", "no.such.module:Player"],
])
def test_bad_flags_exit_2_and_write_nothing(drill, tmp_path, capsys, flags) -> None:
    out = tmp_path / "throw_in"
    with pytest.raises(SystemExit) as stopped:
        drill.main([*flags, "--out", str(out)])
    assert stopped.value.code == 2
    assert not out.exists()
    assert flags[0] in capsys.readouterr().err
