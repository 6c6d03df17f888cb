"""The duel drill (examples/duel_drill.py): a trial ends on its outcome, kicks are recorded, the results
are written, bad flags end it with exit code 2 before anything is written."""

from __future__ import annotations

import importlib.util
import json
import sys
from pathlib import Path

import pytest

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "duel_drill.py"


@pytest.fixture(scope="module")
def drill():
    spec = importlib.util.spec_from_file_location("duel_drill", EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclasses look their module up
    spec.loader.exec_module(module)
    return module


@pytest.mark.render
def test_a_short_drill_plays_its_trials_and_writes_them(drill, tmp_path) -> None:
    out = tmp_path / "duel"
    assert drill.main(["--trials", "2", "--seconds", "2", "--spread", "0", "--out", str(out)]) == 0
    results = json.loads((out / "results.json").read_text())
    assert [t["seed"] for t in results["trials"]] == [0, 1]
    for trial in results["trials"]:  # 2 s: neither striker, 1 m away, has reached the ball
        assert trial["outcome"] == "none" and trial["time_s"] == pytest.approx(2.0)
        assert trial["ball_x"] == 0.0 and abs(trial["ball_y"]) <= drill.BALL_Y_M
        assert trial["kicks"] == []
    assert results["summary"]["outcomes"] == {"home": 0, "away": 0, "out": 0, "none": 2}
    assert results["settings"]["spread"] == 0.0


def test_the_referee_decides_by_the_ball_and_records_kicks_with_the_other_robots_distance(drill) -> None:
    from types import SimpleNamespace

    from match.protocol import Motion

    class World:
        def __init__(self):
            self.ball_xy = (0.0, 0.0)

        def ball(self):
            return SimpleNamespace(x=self.ball_xy[0], y=self.ball_xy[1])

        def robot_pose(self, robot):
            return SimpleNamespace(x=0.3 if robot == drill.AWAY else -0.2, y=0.4)

    world = World()
    match = SimpleNamespace(world=world, step_index=25,
                            config=SimpleNamespace(world=SimpleNamespace(physics=SimpleNamespace(control_step_s=0.04))))
    referee = drill.Referee(limit_s=30.0)
    kick = SimpleNamespace(motion=Motion.KICK_LEFT)
    walk = SimpleNamespace(motion=Motion.WALK)
    referee.decided(match, {drill.HOME: kick, drill.AWAY: walk})
    referee.decided(match, {drill.HOME: kick, drill.AWAY: walk})  # the same kick goes on: recorded once
    assert referee.kicks == [drill.Kick(drill.HOME, 1.0, 0.5)]
    assert not referee.done(match)
    world.ball_xy = (-drill.WIN_X_M - 0.01, 0.0)
    assert referee.done(match) and referee.outcome == ("away", 1.0)


@pytest.mark.parametrize("flags", [
    ["--trials", "0"], ["--trials", "nan"], ["--seconds", "601"], ["--seed", "-1"], ["--spread", "1.5"],
    ["--spread", "nan"], ["--home", "no_such_policy"], ["--away", "no.such.module:Player"],
])
def test_bad_flags_exit_2_and_write_nothing(drill, tmp_path, capsys, flags) -> None:
    out = tmp_path / "duel"
    with pytest.raises(SystemExit) as stopped:
        drill.main([*flags, "--out", str(out)])
    assert stopped.value.code == 2
    assert not out.exists()
    assert flags[0] in capsys.readouterr().err
