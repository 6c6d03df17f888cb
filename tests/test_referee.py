"""Referee rules as placed-position tests: ball put just over a line, a given last toucher."""

from __future__ import annotations

import math
import time

import pytest

from match.errors import MatchConfigError
from match.events import EventKind
from match.protocol.game_control import DropIn, GameState, SecondaryState
from match.protocol.ids import AgentId, Side
from match.protocol.kickoff import kickoff_pose
from match.protocol.throw_in import throw_in_spot
from match.referee import RefereeConfig
from tests.referee_pitch import advance, make_referee, to_playing
from world.field import GoalColor, Pose2D
from world.teams import TeamColor

R = 0.0325  # ball radius


def kinds(events) -> list[str]:
    return [e.kind.value for e in events]


def test_start_puts_everyone_at_kickoff_positions():
    referee, pitch = make_referee(4, 4)
    assert referee.state is GameState.INITIAL
    assert referee.kickoff is Side.HOME  # home starts blue; blue kicks off each half
    assert pitch.poses["home_1"] == kickoff_pose(1, True, GoalColor.BLUE)
    assert pitch.poses["home_0"].x == pytest.approx(-2.85)
    assert pitch.poses["away_0"] == kickoff_pose(0, False, GoalColor.YELLOW)
    assert pitch.poses["away_0"].x == pytest.approx(2.85)
    for player in range(4):  # the defenders stay outside the centre circle, in their half
        pose = pitch.poses[f"away_{player}"]
        assert pose.x > 0 and math.hypot(pose.x, pose.y) > 0.6
    assert (pitch.ball_state.x, pitch.ball_state.y) == (0.0, 0.0)
    assert pitch.colors["home_2"] is TeamColor.BLUE and pitch.colors["away_2"] is TeamColor.RED


def test_simulated_time_alone_drives_the_states(monkeypatch):
    referee, pitch = make_referee()

    def no_wall_clock(*_):
        raise AssertionError("the referee read the wall clock")

    for name in ("time", "monotonic", "perf_counter", "time_ns", "monotonic_ns", "perf_counter_ns"):
        monkeypatch.setattr(time, name, no_wall_clock)
    events = advance(referee, pitch, 25.0)
    states = [(round(e.time_s, 2), e.details["state"]) for e in events if e.kind is EventKind.STATE]
    assert states == [(2.0, "READY"), (17.0, "SET"), (20.0, "PLAYING")]
    assert referee.seconds_remaining == pytest.approx(600.0 - 5.0, abs=0.05)
    assert EventKind.KICKOFF in [e.kind for e in events]


def test_game_control_is_broadcast_every_half_second():
    referee, pitch = make_referee()
    times = set()
    for _ in range(50):
        advance(referee, pitch, 0.04)
        times.add(round(referee.broadcast.time_s, 2))
    assert sorted(times) == [0.0, 0.52, 1.0, 1.52, 2.0]  # the first step at or after each 0.5 s


def test_robot_in_wrong_half_at_set_is_placed_and_legal_one_stays():
    referee, pitch = make_referee(2, 2)
    advance(referee, pitch, 3.0)  # READY
    pitch.poses["home_0"] = Pose2D(1.0, 0.5, 0.0)  # in the opponent's half
    pitch.poses["away_1"] = Pose2D(0.3, 0.0, math.pi)  # defender inside the centre circle
    pitch.poses["home_1"] = Pose2D(-0.5, 0.2, 0.3)  # kicker: may be in the circle, own half
    events = advance(referee, pitch, 15.0)
    placed = {e.details["robot"] for e in events if e.kind is EventKind.ROBOT_PLACED}
    assert placed == {"home_0", "away_1"}
    assert pitch.poses["home_0"] == kickoff_pose(0, True, GoalColor.BLUE)
    assert pitch.poses["away_1"] == kickoff_pose(1, False, GoalColor.YELLOW)
    assert pitch.poses["home_1"] == Pose2D(-0.5, 0.2, 0.3)


def test_goal_counts_and_conceding_team_kicks_off():
    referee, pitch = make_referee()
    to_playing(referee, pitch)
    pitch.put_ball(1.0, 0.0, toucher="away_1")  # touched by the other team: the kick-off shot rule is over
    advance(referee, pitch, 0.04)
    pitch.put_ball(3.0 + 0.025 + R + 0.01, 0.2)  # whole ball over the yellow goal line
    update_events = advance(referee, pitch, 0.04)
    assert "goal" in kinds(update_events)
    assert referee.score == {Side.HOME: 1, Side.AWAY: 0}
    assert referee.state is GameState.READY and referee.kickoff is Side.AWAY
    assert (pitch.ball_state.x, pitch.ball_state.y) == (0.0, 0.0)


def test_ball_on_the_goal_line_is_no_goal():
    referee, pitch = make_referee()
    to_playing(referee, pitch)
    pitch.put_ball(1.0, 0.0, toucher="away_1")
    advance(referee, pitch, 0.04)
    pitch.put_ball(3.0 + 0.025 + R - 0.01, 0.2)  # part of the ball still over the line
    assert kinds(advance(referee, pitch, 0.2)).count("goal") == 0


def test_kickoff_shot_cannot_score_and_goes_to_the_halfway_line():
    referee, pitch = make_referee()
    to_playing(referee, pitch)
    pitch.put_ball(3.1, 0.2, toucher="home_1")  # the kicker shot straight in
    events = advance(referee, pitch, 0.04)
    assert "goal_disallowed" in kinds(events) and referee.score[Side.HOME] == 0
    advance(referee, pitch, 1.8)
    assert pitch.ball_state.x == pytest.approx(3.1)  # left to roll 2 s
    events = advance(referee, pitch, 0.4)
    assert "throw_in" in kinds(events)
    assert (pitch.ball_state.x, pitch.ball_state.y) == pytest.approx((0.0, 1.6))


def test_kickoff_team_scores_after_ball_left_circle_and_was_touched_again():
    referee, pitch = make_referee()
    to_playing(referee, pitch)
    pitch.put_ball(0.1, 0.0, toucher="home_1")
    advance(referee, pitch, 0.04)
    pitch.put_ball(1.5, 0.0)  # left the circle
    advance(referee, pitch, 0.4)
    pitch.put_ball(1.6, 0.0, toucher="home_1")  # touched again by the kick-off team
    advance(referee, pitch, 0.04)
    pitch.put_ball(3.1, -0.3)
    assert "goal" in kinds(advance(referee, pitch, 0.04))
    assert referee.score[Side.HOME] == 1


@pytest.mark.parametrize(
    "ball, toucher, expected",
    [
        ((1.0, 2.1), "home_1", (0.0, 1.6)),  # side line: 1 m back toward home's goal (blue, -x)
        ((1.0, 2.1), "away_1", (2.0, 1.6)),  # toward away's goal (+x), clamped to |x| <= 2
        ((-1.5, -2.1), "home_1", (-2.0, -1.6)),
        ((0.4, -2.1), "away_0", (1.4, -1.6)),
        ((-3.1, 1.0), "home_1", (-2.0, 1.6)),  # end line by the defending team: end of the throw-in line
        ((-3.1, 1.0), "away_1", (0.0, 1.6)),  # end line by the attacking team: halfway line
        ((3.1, -1.2), "away_1", (2.0, -1.6)),
        ((3.1, -1.2), "home_1", (0.0, -1.6)),
    ],
)
def test_ball_out_placement(ball, toucher, expected):
    referee, pitch = make_referee()
    to_playing(referee, pitch)
    pitch.put_ball(0.3, 0.3, toucher="away_1")  # ends the kick-off-shot rule
    advance(referee, pitch, 0.04)
    pitch.put_ball(*ball, toucher=toucher)
    events = advance(referee, pitch, 0.04)
    assert "ball_out" in kinds(events)
    events = advance(referee, pitch, 2.0)
    assert "throw_in" in kinds(events)
    assert (pitch.ball_state.x, pitch.ball_state.y) == pytest.approx(expected)
    assert (pitch.ball_state.vx, pitch.ball_state.vy) == (0.0, 0.0)


def test_game_control_tells_who_put_the_ball_out_and_when_it_was_put_back():
    referee, pitch = make_referee()
    to_playing(referee, pitch)
    assert referee.game_control().seconds_since_drop_in == math.inf
    assert referee.game_control().view_for(Side.HOME).drop_in_team is DropIn.NONE
    pitch.put_ball(0.3, 0.3, toucher="away_1")
    advance(referee, pitch, 0.04)
    pitch.put_ball(1.0, 2.1, toucher="home_1")
    advance(referee, pitch, 2.0)
    assert referee.game_control().drop_in_team is None  # out, not yet put back
    advance(referee, pitch, 0.04)
    advance(referee, pitch, 0.4)
    control = referee.game_control()
    assert control.drop_in_team is Side.HOME and control.seconds_since_drop_in == pytest.approx(0.4, abs=0.05)
    assert control.view_for(Side.HOME).drop_in_team is DropIn.OWN_TEAM
    assert control.view_for(Side.AWAY).drop_in_team is DropIn.OPPONENT
    # the rule players know gives the spot the referee used
    assert throw_in_spot(1.0, 2.1, False, GoalColor.BLUE) == pytest.approx((pitch.ball_state.x, pitch.ball_state.y))


def test_placed_ball_moves_toward_the_centre_off_a_robot():
    referee, pitch = make_referee()
    to_playing(referee, pitch)
    pitch.put_ball(0.3, 0.3, toucher="away_1")
    advance(referee, pitch, 0.04)
    pitch.poses["home_0"] = Pose2D(0.0, 1.6, 0.0)  # standing on the throw-in spot
    pitch.put_ball(1.0, 2.1, toucher="home_1")
    advance(referee, pitch, 2.1)
    assert (pitch.ball_state.x, pitch.ball_state.y) == pytest.approx((0.0, 1.4))


def test_half_time_swaps_sides_and_colours():
    referee, pitch = make_referee(2, 2, half_seconds=5.0)
    to_playing(referee, pitch)
    events = advance(referee, pitch, 5.0)
    assert "half_time" in kinds(events)
    assert referee.half == 2 and referee.state is GameState.INITIAL
    assert referee.color_of(Side.HOME) is TeamColor.RED and pitch.colors["home_1"] is TeamColor.RED
    assert referee.defended_goal(Side.HOME) is GoalColor.YELLOW
    assert referee.kickoff is Side.AWAY  # the blue team kicks off each half
    assert pitch.poses["away_1"] == kickoff_pose(1, True, GoalColor.BLUE)
    assert pitch.poses["home_0"].x == pytest.approx(2.85)
    assert referee.seconds_remaining == pytest.approx(5.0)


def test_match_without_tie_finishes_after_second_half():
    referee, pitch = make_referee(1, 1, half_seconds=2.0, initial_seconds=0.0, ready_seconds=0.0, set_seconds=0.0)
    to_playing(referee, pitch)
    pitch.put_ball(1.0, 0.0, toucher="away_0")
    advance(referee, pitch, 0.04)
    pitch.put_ball(3.1, 0.0)
    advance(referee, pitch, 0.04)
    events = advance(referee, pitch, 6.0)
    assert referee.finished and referee.secondary is SecondaryState.NORMAL
    end = [e for e in events if e.kind is EventKind.END][0]
    assert end.details["winner"] == "home"


def test_tie_without_shootout_is_a_draw():
    referee, pitch = make_referee(1, 1, half_seconds=1.0, initial_seconds=0.0, ready_seconds=0.0, set_seconds=0.0,
                                  shootout=False)
    events = advance(referee, pitch, 4.0)
    assert referee.finished
    assert [e for e in events if e.kind is EventKind.END][0].details["winner"] is None


def test_shootout_places_kicker_keeper_and_others_off_the_field():
    referee, pitch = make_referee(3, 2, half_seconds=1.0, initial_seconds=0.0, ready_seconds=0.0, set_seconds=0.5)
    while referee.secondary is SecondaryState.NORMAL:
        advance(referee, pitch, 0.04)
    assert referee.secondary is SecondaryState.PENALTY_SHOOTOUT
    assert referee.state is GameState.SET
    # first kick: the blue team of the second half (away), at the yellow goal
    assert referee.kickoff is Side.AWAY
    assert (pitch.ball_state.x, pitch.ball_state.y) == (1.2, 0.0)
    assert pitch.poses["away_1"].x == pytest.approx(1.2 - 0.22)
    assert pitch.poses["home_0"].x == pytest.approx(2.85)
    for robot in ("home_1", "home_2", "away_0"):
        assert abs(pitch.poses[robot].y) > 2.7  # off the carpet
    assert referee.holds(AgentId(Side.HOME, 0))  # everyone is held in SET
    advance(referee, pitch, 0.6)
    assert referee.state is GameState.PLAYING
    assert referee.holds(AgentId(Side.HOME, 1)) and not referee.holds(AgentId(Side.HOME, 0))
    assert not referee.holds(AgentId(Side.AWAY, 1))
    assert referee.defended_goal(Side.HOME) is GoalColor.YELLOW


def test_shootout_five_kicks_each_then_sudden_death():
    referee, pitch = make_referee(2, 2, half_seconds=1.0, initial_seconds=0.0, ready_seconds=0.0, set_seconds=0.0,
                                  shootout_attempt_seconds=1.0, max_sudden_death_rounds=2)
    advance(referee, pitch, 2.5)
    kicks = []
    for _ in range(200):
        if referee.finished:
            break
        if referee.state is GameState.PLAYING and referee.kickoff is Side.HOME and len(kicks) == 9:
            pitch.put_ball(3.2, 0.1, toucher="home_1")  # the home team's fifth kick goes in
        kicks += [e for e in advance(referee, pitch, 0.2) if e.kind is EventKind.SHOOTOUT_KICK]
    assert referee.finished
    assert len(kicks) == 10  # 1-0 after five each: decided, no sudden death
    assert sum(k.details["scored"] for k in kicks) == 1
    end = [e for e in referee.events if e.kind is EventKind.END][0]
    assert end.details["winner"] == "home" and end.details["shootout"] == {"home": 1, "away": 0}


def test_shootout_sudden_death_runs_out_as_draw():
    referee, pitch = make_referee(1, 1, half_seconds=1.0, initial_seconds=0.0, ready_seconds=0.0, set_seconds=0.0,
                                  shootout_attempt_seconds=0.2, max_sudden_death_rounds=2)
    advance(referee, pitch, 30.0)
    kicks = [e for e in referee.events if e.kind is EventKind.SHOOTOUT_KICK]
    assert referee.finished and len(kicks) == 14  # 5 + 5, then 2 pairs of sudden death
    assert all(k.details["reason"] == "time" for k in kicks)


def test_robot_off_the_carpet_goes_back_to_the_side_line():
    referee, pitch = make_referee()
    to_playing(referee, pitch)
    pitch.put_ball(0.5, 1.0)
    pitch.poses["home_1"] = Pose2D(0.5, -2.9, 0.0)  # off the carpet (|y| > 2.7)
    events = advance(referee, pitch, 0.04)
    assert "robot_replaced" in kinds(events)
    # own penalty-mark x, on the side line away from the ball, facing into the field
    assert pitch.poses["home_1"] == Pose2D(-1.2, -2.0, math.pi / 2)


def test_robot_down_too_long_is_placed_back():
    referee, pitch = make_referee(fallen_limit_s=3.0)
    to_playing(referee, pitch)
    pitch.put_ball(0.5, -1.0)
    pitch.fallen["away_1"] = True
    events = advance(referee, pitch, 2.0)
    assert kinds(events).count("fall") == 1 and "robot_replaced" not in kinds(events)
    events = advance(referee, pitch, 1.2)
    assert "robot_replaced" in kinds(events)
    assert pitch.poses["away_1"] == Pose2D(1.2, 2.0, -math.pi / 2)


def test_bad_referee_settings_are_refused():
    with pytest.raises(MatchConfigError, match="half_seconds"):
        RefereeConfig(half_seconds=-1)
    with pytest.raises(MatchConfigError, match="fallen_limit_s"):
        RefereeConfig(fallen_limit_s=float("nan"))
