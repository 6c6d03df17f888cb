"""The base of the drills (scenarios.drills): parameters checked and bounded, the registry, the settings and
their trial seeds, a trial's record and its checks, the drills' setups and observers, and the guide's
example of a new drill (docs/drills.md), run."""

from __future__ import annotations

import dataclasses
import json
import math
import re
from pathlib import Path
from types import SimpleNamespace

import pytest

from agents.policies import make_policy
from match.events import EventKind, MatchEvent
from match.protocol import GameState, Motion, Pose2D
from scenarios.drills.ball_drill import BallWatch
from scenarios.drills.base import Drill, DrillError, Role, Score
from scenarios.drills.duel import AWAY, HOME, Duel, DuelWatch
from scenarios.drills.goal_line import GoalLine
from scenarios.drills.records import TrialRecord, header, stored_record
from scenarios.drills.registry import DRILLS, drill_class
from scenarios.drills.settings import SEED_MAX, DrillSettings
from scenarios.drills.shooting import Shooting
from scenarios.drills.throw_in import ROLL_MPS, ThrowInWatch
from scenarios.drills.trial import Placed

GUIDE = Path(__file__).resolve().parents[1] / "docs" / "drills.md"


def _settings(name: str, **parameters) -> DrillSettings:
    drill = drill_class(name)(**parameters)
    return DrillSettings(drill, tuple((role.name, "stand") for role in drill.ROLES), trials=3, seed=5)


# ---- the registry and the parameters ----------------------------------------------------------


def test_the_registry_names_the_four_drills_and_refuses_another() -> None:
    assert list(DRILLS) == ["throw-in", "shooting", "duel", "goal-line"]
    with pytest.raises(DrillError, match=r"unknown drill 'corner'; expected one of throw-in, shooting, duel"):
        drill_class("corner")


@pytest.mark.parametrize(("name", "given", "message"), [
    ("throw-in", {"players": 5}, "--players 5: expected an integer from 1 to 4"),
    ("throw-in", {"players": 2.0}, "--players 2.0: expected an integer"),
    ("throw-in", {"seconds": True}, "--seconds True: expected an integer from 1 to 600 s"),
    ("duel", {"spread": math.nan}, "--spread nan: expected a number from 0 to 0.9 m"),
    ("duel", {"spread": "0.3"}, "--spread '0.3': expected a number"),
    ("goal-line", {"seconds": 0}, "--seconds 0: expected an integer from 1 to 600 s"),
])
def test_a_parameter_out_of_its_bounds_is_refused_naming_its_flag(name: str, given: dict, message: str) -> None:
    with pytest.raises(DrillError) as refused:
        drill_class(name)(**given)
    assert str(refused.value).startswith(message)


def _define(**body) -> type:
    """A drill class of ``body`` over a concrete drill whose roles, outcomes and columns it may replace."""
    return type("CornerKick", (Shooting,), {"__doc__": "Corner kicks.", **body})


def test_a_drill_is_named_by_its_class_and_told_by_its_docstring() -> None:
    corner = _define()
    assert (corner.NAME, corner.HELP) == ("corner-kick", "Corner kicks")
    assert (GoalLine.NAME, GoalLine.HELP[:30]) == ("goal-line", "The ball at the own goal line ")
    with pytest.raises(dataclasses.FrozenInstanceError):
        corner().seconds = 3  # type: ignore[misc]


@pytest.mark.parametrize(("body", "message"), [
    ({"NAME": "Two words"}, "NAME = 'Two words'; expected lower-case words"),
    ({"__doc__": None}, "no help"),
    ({"COLUMNS": {"seed": int}}, "column 'seed'"),
    ({"COLUMNS": {"x": list}}, "column 'x'"),
    ({"ROLES": (Role("a", ""), Role("a", ""))}, "expected one or more roles, distinct names"),
    ({"ROLES": (Role("trials", ""),)}, "none of trials"),
    ({"ROLES": ()}, "expected one or more roles"),
    ({"OUTCOMES": ("x", "x")}, "OUTCOMES = ('x', 'x')"),
])
def test_a_drill_class_that_describes_no_drill_is_refused_when_defined(body: dict, message: str) -> None:
    with pytest.raises(DrillError, match=re.escape(message)):
        _define(**body)


# ---- settings ----------------------------------------------------------------------------------


def test_trial_k_has_the_seed_plus_k_and_the_fingerprint_follows_every_setting() -> None:
    settings = _settings("duel")
    assert [(t.index, t.seed) for t in settings.tasks()] == [(0, 5), (1, 6), (2, 7)]
    assert settings.to_json() == {"drill": "duel", "parameters": {"seconds": 30, "spread": 0.3},
                                  "policies": {"home": "stand", "away": "stand"}, "trials": 3, "seed": 5}
    others = [_settings("duel", spread=0.0), dataclasses.replace(settings, seed=6),
              dataclasses.replace(settings, trials=4), dataclasses.replace(settings, policies=(("home", "team"),
                                                                                                ("away", "stand")))]
    assert len({settings.fingerprint(), *(o.fingerprint() for o in others)}) == 5


@pytest.mark.parametrize(("change", "message"), [
    ({"policies": (("home", "team"),)}, "expects one for each of home, away"),
    ({"trials": 0}, "--trials 0: expected an integer from 1 to 10000"),
    ({"seed": -1}, "--seed -1: expected an integer from 0 to 4294967295"),
    ({"seed": SEED_MAX - 1}, f"--seed {SEED_MAX - 1} with --trials 3"),
])
def test_settings_a_batch_cannot_play_are_refused(change: dict, message: str) -> None:
    with pytest.raises(DrillError, match=re.escape(message)):
        dataclasses.replace(_settings("duel"), **change)


# ---- setups ------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", list(DRILLS))
def test_a_setup_is_a_function_of_the_seed(name: str) -> None:
    drill = drill_class(name)()
    first, again, other = drill.trial_setup(3), drill.trial_setup(3), drill.trial_setup(4)
    assert first.facts == again.facts and first.facts != other.facts
    assert set(first.roles.values()) == {role.name for role in drill.ROLES}
    assert list(first.facts) == list(drill.COLUMNS)[:len(first.facts)]


def test_the_throw_in_plays_its_players_per_side_and_the_goal_line_places_its_three_robots() -> None:
    setup = drill_class("throw-in")(players=2).trial_setup(0)
    assert setup.roles == {"home_0": "home", "home_1": "home", "away_0": "away", "away_1": "away"}
    assert abs(setup.facts["roll_y"]) == 1.2 and abs(setup.facts["roll_x"]) <= 2.0 and not setup.placed
    placed = drill_class("goal-line")().trial_setup(0).placed
    assert set(placed) == {"home_0", "home_1", "away_1"}


# ---- records -----------------------------------------------------------------------------------


def test_a_record_reads_back_as_written_and_a_failure_has_no_values() -> None:
    settings = _settings("throw-in")
    values = {"roll_x": 0.5, "roll_y": -1.2, "spot_x": 0.5, "spot_y": -1.6, "wait_s": 6.2, "toucher": "home_1",
              "home_nearest_m": 0.8, "away_nearest_m": 1.9}
    record = TrialRecord(1, 6, "ok", "home", values, 12.0, 3.5)
    assert stored_record(settings.tasks(), 1, json.loads(json.dumps(record.to_json()))) == record
    assert list(record.to_json()) == list(header(settings.drill))
    failed = TrialRecord.failure(settings.tasks()[2], "RuntimeError: x", 2)
    assert failed.values == dict.fromkeys(values) and stored_record(settings.tasks(), 2, failed.to_json()) == failed
    with pytest.raises(ValueError, match="toucher = a text of 300 characters"):
        stored_record(settings.tasks(), 1, {**record.to_json(), "toucher": "x" * 300})
    with pytest.raises(ValueError, match="outcome = 'goal'; expected one of home, away, none, in"):
        stored_record(settings.tasks(), 1, {**record.to_json(), "outcome": "goal"})


# ---- the drills' observers, on a match of stand-ins ----------------------------------------------


class _World:
    def __init__(self):
        self.time_s = 0.0
        self.ball_xy = (0.0, 0.0)
        self.placed: list[tuple[float, ...]] = []

    def ball(self):
        return SimpleNamespace(x=self.ball_xy[0], y=self.ball_xy[1])

    def place_ball(self, *args):
        self.placed.append(args)

    def robot_pose(self, robot):
        positions = {"home_1": (0.0, 1.0), "away_1": (0.3, 0.3)}
        x, y = positions.get(robot, (0.0, -1.0))
        return SimpleNamespace(x=x, y=y)


def _match(**fields) -> SimpleNamespace:
    physics = SimpleNamespace(control_step_s=0.04)
    return SimpleNamespace(world=_World(), step_index=0, config=SimpleNamespace(world=SimpleNamespace(physics=physics)),
                           **fields)


@pytest.mark.parametrize(("drill", "ball", "outcome"), [
    (Shooting, (3.1, 0.2), "goal"), (Shooting, (3.1, 1.2), "wide"), (Shooting, (1.0, 2.1), "out"),
    (Shooting, (-0.6, 0.0), "cleared"), (Shooting, (1.0, 0.0), None),
    (GoalLine, (-3.1, 0.3), "goal"), (GoalLine, (-3.1, 1.2), "out_end"), (GoalLine, (-2.5, 2.1), "out_side"),
    (GoalLine, (-1.9, 1.0), "cleared"), (GoalLine, (-2.5, 1.7), "cleared"), (GoalLine, (-2.8, 1.2), None),
    (Duel, (1.6, 0.0), "home"), (Duel, (-1.6, 0.0), "away"), (Duel, (0.2, -2.1), "out"), (Duel, (0.2, 0.5), None),
])
def test_a_ball_drill_ends_a_trial_by_where_the_ball_is(drill, ball: tuple[float, float], outcome: str | None) -> None:
    match = _match()
    match.world.ball_xy, match.step_index = ball, 25
    observer = drill(seconds=30).observe(drill().trial_setup(0))
    assert observer.done(match) is (outcome is not None)
    assert observer.score() == Score(outcome or "none", {"time_s": 1.0 if outcome else 30.0})


def test_a_ball_watch_ends_at_its_limit() -> None:
    match = _match()
    observer = BallWatch(lambda x, y: None, limit_s=2.0)
    match.step_index = 49
    assert not observer.done(match)
    match.step_index = 50
    assert observer.done(match) and observer.score() == Score("none", {"time_s": 2.0})


def test_the_duel_counts_a_kick_once_and_whether_it_was_contested() -> None:
    match = _match()
    observer = DuelWatch(Duel().judge, limit_s=30.0)
    kick, walk = SimpleNamespace(motion=Motion.KICK_LEFT), SimpleNamespace(motion=Motion.WALK)
    observer.decided(match, {HOME: kick, AWAY: walk})
    observer.decided(match, {HOME: kick, AWAY: walk})  # the same kick goes on: counted once
    assert observer.kicks == {HOME: 1, AWAY: 0} and observer.contested == {HOME: 1, AWAY: 0}  # away_1 0.42 m off
    match.world.ball_xy = (1.0, 0.4)
    observer.decided(match, {HOME: walk, AWAY: kick})
    assert observer.kicks == {HOME: 1, AWAY: 1} and observer.contested == {HOME: 1, AWAY: 0}  # home_1 1.17 m off


def test_the_throw_in_rolls_once_and_ends_at_the_first_touch_after_the_put_back() -> None:
    match = _match(state=GameState.SET, events=[], agent_names=("home_1", "away_1"))
    observer = ThrowInWatch((0.5, 1.2), limit_s=20.0)
    observer.decided(match, {})
    assert match.world.placed == []  # not playing yet
    match.state = GameState.PLAYING
    for time_s in (1.0, 1.3, 1.6):
        match.world.time_s = time_s
        observer.decided(match, {})
    assert match.world.placed == [(0.5, 1.2, 0.0, ROLL_MPS)]  # once, ROLL_AFTER_S into the play
    match.events = [MatchEvent(2.0, EventKind.TOUCH, {"robot": "home_1"}),  # before the put-back: not counted
                    MatchEvent(4.0, EventKind.THROW_IN, {"x": 0.5, "y": 1.6, "line": "side_line"})]
    match.world.time_s = 4.0
    assert not observer.done(match)
    assert observer.throw_in == {"time_s": 4.0, "x": 0.5, "y": 1.6, "home_nearest_m": 0.781, "away_nearest_m": 1.315}
    match.events.append(MatchEvent(9.5, EventKind.TOUCH, {"robot": "away_1"}))
    match.world.time_s = 9.5
    assert observer.done(match) and observer.outcome == ("away", 5.5, "away_1")


def test_a_put_back_nobody_touches_in_time_ends_the_throw_in_trial() -> None:
    match = _match(state=GameState.PLAYING, agent_names=("home_1",),
                   events=[MatchEvent(3.0, EventKind.THROW_IN, {"x": 0.0, "y": -1.6})])
    observer = ThrowInWatch((0.0, -1.2), limit_s=5.0)
    observer.decided(match, {})
    match.world.time_s = 0.5
    observer.decided(match, {})
    match.world.time_s = 7.9
    assert not observer.done(match)
    match.world.time_s = 8.0
    assert observer.done(match) and observer.outcome == ("none", None, None)


def test_a_placed_team_agent_believes_where_it_was_put() -> None:
    pose = Pose2D(-2.2, 1.1, 2.5)
    placed = Placed(make_policy("team"), pose)
    placed.reset("away_1", 0)
    believed = placed.policy.pose_estimate()
    assert math.dist(believed[:2], (pose.x, pose.y)) < 1e-9 and believed[2] == pytest.approx(pose.theta)


# ---- a new drill, as the guide writes it ----------------------------------------------------------


def _guide_code() -> str:
    blocks = re.findall(r"```python\n(.*?)```", GUIDE.read_text(encoding="utf-8"), flags=re.S)
    assert blocks, "docs/drills.md has no python block"
    return "\n".join(blocks)


@pytest.mark.render
def test_the_guides_new_drill_plays_through_the_base(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    namespace: dict = {"__name__": "drills_guide"}
    exec(compile(_guide_code(), str(GUIDE), "exec", dont_inherit=True), namespace)  # noqa: S102
    report = namespace["report"]
    assert len(report.played) == 2 and sum(report.summary["outcomes"].values()) == 2
    for name in ("results.csv", "summary.json", "table.md"):
        assert (tmp_path / "out" / "empty-goal" / name).is_file()
