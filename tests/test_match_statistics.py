"""Match statistics (match.statistics) against a hand-built match: events, log and summary blocks."""

from __future__ import annotations

import math

import numpy as np
import pytest

from match.protocol import Motion, make_action, parse_action
from match.statistics import TEAM_KEYS, TeamRadio, attack_direction, match_statistics, side_of

INITIAL, READY, SET, PLAYING = 0, 1, 2, 3

# time, state, half, ball x, ball y
ROWS = [
    (0.0, INITIAL, 1, 2.0, 0.0),
    (1.0, PLAYING, 1, 2.0, 0.0),  # nobody touched it yet
    (2.0, PLAYING, 1, 2.2, 0.0),  # home_0 touches it
    (3.0, PLAYING, 1, 2.45, 0.0),  # enters the goal area home attacks (+x in half 1): a shot
    (4.0, PLAYING, 1, 2.65, 0.0),  # still the same touch: the same shot
    (5.0, PLAYING, 1, 2.6, 0.1),  # away_0 touches it
    (6.0, PLAYING, 1, 2.4, 0.1),  # away attacks -x: no shot of theirs
    (7.0, READY, 1, 0.0, 0.0),  # after the goal
    (8.5, INITIAL, 2, 0.0, 0.0),  # second half: home attacks -x
    (9.0, PLAYING, 2, -2.2, 0.5),  # placed there (a jump), away touched it last
    (10.0, PLAYING, 2, -2.45, 0.5),  # into home's target area, but away touched it last: no shot
    (11.0, PLAYING, 2, -2.7, 0.5),  # home_0 touches it toward its target: a shot
    (12.0, SET, 2, 1.2, 0.0),  # the penalty shoot-out
    (13.0, PLAYING, 2, 1.4, 0.0),
    (14.0, PLAYING, 2, 1.6, 0.0),
]

EVENTS = [
    {"time_s": 0.0, "kind": "state", "state": "INITIAL", "half": 1, "secondary": "NORMAL"},
    {"time_s": 1.0, "kind": "state", "state": "PLAYING", "half": 1, "secondary": "NORMAL"},
    {"time_s": 1.0, "kind": "kickoff", "team": "home", "half": 1},
    {"time_s": 2.0, "kind": "touch", "robot": "home_0", "x": 2.2, "y": 0.0},
    {"time_s": 3.0, "kind": "fall", "robot": "away_0", "x": 1.0, "y": 0.0},
    {"time_s": 4.5, "kind": "ball_out", "line": "side_line", "x": 1.0, "y": 2.1, "last_toucher": "home_0"},
    {"time_s": 5.0, "kind": "touch", "robot": "away_0", "x": 2.6, "y": 0.1},
    {"time_s": 6.5, "kind": "goal", "team": "home", "goal": "yellow", "last_toucher": "away_0",
     "score": {"home": 1, "away": 0}},
    {"time_s": 6.5, "kind": "state", "state": "READY", "half": 1, "secondary": "NORMAL"},
    {"time_s": 7.5, "kind": "half_time", "score": {"home": 1, "away": 0}},
    {"time_s": 8.0, "kind": "robot_replaced", "robot": "home_0", "reason": "off_carpet", "x": -1.2, "y": 2.0},
    {"time_s": 8.5, "kind": "state", "state": "PLAYING", "half": 2, "secondary": "NORMAL"},
    {"time_s": 11.0, "kind": "touch", "robot": "home_0", "x": -2.7, "y": 0.5},
    {"time_s": 12.0, "kind": "state", "state": "SET", "half": 2, "secondary": "PENALTY_SHOOTOUT"},
    {"time_s": 13.0, "kind": "touch", "robot": "away_0", "x": 1.4, "y": 0.0},  # shoot-out: not counted
    {"time_s": 13.5, "kind": "fall", "robot": "away_0", "x": 1.0, "y": 0.0},  # falls count all match long
    {"time_s": 14.0, "kind": "shootout_kick", "team": "away", "kicker": "away_0", "keeper": "home_0",
     "scored": False, "reason": "saved", "shootout": {"home": 0, "away": 0}},
    {"time_s": 14.0, "kind": "end", "winner": "home", "score": {"home": 1, "away": 0}, "shootout": None},
]

SUMMARY = {
    "faults": {"total": 3, "by_agent": {"away_0": 3}, "details": []},
    "radio": {"sent": 10, "by_side": {"home": {"sent": 10, "dropped": 2, "received": 9},
                                      "away": {"sent": 0, "dropped": 0, "received": 0}}},
}


def hand_built_log() -> dict[str, np.ndarray]:
    time_s, state, half, bx, by = (np.array(column) for column in zip(*ROWS))
    n = len(ROWS)
    robots = np.zeros((n, 2, 3))
    robots[:, :, 2] = 3.0  # both face almost -x
    estimates = np.full((n, 2, 3), np.nan)  # away_0 reports no estimate
    estimates[:, 0] = robots[:, 0] + (3.0, 4.0, 0.0)  # 5 m off outside playing time: never counted
    playing = (state == PLAYING) & (time_s <= 12.0)
    estimates[playing, 0] = robots[playing, 0] + (0.3, 0.4, 0.0)  # 0.5 m off while playing ...
    estimates[11, 0, :2] = robots[11, 0, :2] + (0.6, 0.8)  # ... 1 m off once
    estimates[:, 0, 2] = -3.0  # 2 pi - 6 rad = 16.23 degrees off
    return {
        "agents": np.array(["home_0", "away_0"]),
        "time_s": time_s.astype(float),
        "state": state.astype(np.int8),
        "half": half.astype(np.int8),
        "ball": np.stack([bx, by, np.full(n, 0.0325)], axis=1),
        "robots": robots,
        "fallen": np.zeros((n, 2), dtype=bool),
        "estimates": estimates,
    }


@pytest.fixture(scope="module")
def statistics() -> dict:
    return match_statistics(EVENTS, hand_built_log(), SUMMARY)


def test_counts_from_the_events(statistics: dict) -> None:
    home, away = statistics["home"], statistics["away"]
    assert set(home) == set(TEAM_KEYS) == set(away)
    assert (home["goals"], away["goals"]) == (1, 0)
    # away_0 touched the ball last, but home_0's touch before was a shot on target: home_0's goal
    assert (home["own_goals"], away["own_goals"]) == (0, 0)
    assert (home["touches"], away["touches"]) == (2, 1)  # the shoot-out's touch does not count
    assert (home["balls_out"], away["balls_out"]) == (1, 0)
    assert (home["falls"], away["falls"]) == (0, 2)
    assert (home["robots_replaced"], away["robots_replaced"]) == (1, 0)
    assert (home["faults"], away["faults"]) == (0, 3)
    assert (home["radio_sent"], home["radio_dropped"], home["radio_received"]) == (10, 2, 9)
    assert away["radio_sent"] == 0


def test_an_own_goal_is_a_defender_s_last_touch_after_no_shot_on_target() -> None:
    rows = [(0.0, PLAYING, 1, 1.0, 0.5), (1.0, PLAYING, 1, 0.8, 0.5),  # home_0 plays it back: no shot
            (2.0, PLAYING, 1, 2.2, 0.3), (3.0, PLAYING, 1, 2.7, 0.2),  # away_0 clears it into its own goal
            (4.0, PLAYING, 1, 3.1, 0.2)]
    log = hand_built_log()
    log.update(time_s=np.array([r[0] for r in rows]), state=np.array([r[1] for r in rows], dtype=np.int8),
               half=np.array([r[2] for r in rows], dtype=np.int8),
               ball=np.array([(r[3], r[4], 0.0325) for r in rows]))
    for key in ("robots", "fallen", "estimates"):
        log[key] = log[key][: len(rows)]
    events = [
        {"time_s": 0.5, "kind": "touch", "robot": "home_0", "x": 1.0, "y": 0.5},
        {"time_s": 1.5, "kind": "touch", "robot": "away_0", "x": 0.9, "y": 0.5},
        {"time_s": 4.0, "kind": "goal", "team": "home", "goal": "yellow", "last_toucher": "away_0",
         "score": {"home": 1, "away": 0}},
    ]
    statistics = match_statistics(events, log, {})
    assert (statistics["home"]["goals"], statistics["away"]["own_goals"]) == (1, 1)
    assert statistics["home"]["shots_on_target"] == 0


def test_shots_possession_and_playing_time_from_the_log(statistics: dict) -> None:
    home, away = statistics["home"], statistics["away"]
    assert (home["shots_on_target"], away["shots_on_target"]) == (2, 0)
    # playing rows 1-6 (1 s each), 9 (0.5 s), 10 and 11; row 1 belongs to nobody
    assert statistics["playing_seconds"] == pytest.approx(8.5)
    assert home["possession"] == pytest.approx(4.0 / 7.5, abs=1e-4)
    assert away["possession"] == pytest.approx(3.5 / 7.5, abs=1e-4)


def test_pose_errors_while_playing_only(statistics: dict) -> None:
    home, away = statistics["home"], statistics["away"]
    assert home["pose_estimates"] == 9
    assert home["position_error_mean_m"] == pytest.approx((8 * 0.5 + 1.0) / 9, abs=1e-4)
    assert home["position_error_p95_m"] == pytest.approx(0.5 + 0.6 * 0.5, abs=1e-4)  # 7.6th of 9 sorted values
    assert home["orientation_error_mean_deg"] == pytest.approx(math.degrees(2 * math.pi - 6.0), abs=1e-3)
    assert away["pose_estimates"] == 0 and away["position_error_mean_m"] is None
    assert away["orientation_error_p95_deg"] is None


def test_pose_errors_leave_out_the_steps_a_robot_lies() -> None:
    """The row 1 m off is one where home_0 lay fallen: it is not counted, the rest are."""
    log = hand_built_log()
    log["fallen"][11, 0] = True
    home = match_statistics(EVENTS, log, SUMMARY)["home"]
    assert home["pose_estimates"] == 8
    assert home["position_error_mean_m"] == pytest.approx(0.5, abs=1e-4)
    assert home["lost_share"] == 0.0


def test_a_summary_without_per_team_radio_gives_none() -> None:
    result = match_statistics(EVENTS, hand_built_log(), {"faults": {}, "radio": {"sent": 3}})
    assert result["home"]["radio_sent"] is None and result["home"]["faults"] == 0


def test_sides_and_directions() -> None:
    assert side_of("home_3") == "home" and side_of("away_0") == "away"
    assert side_of(None) is None and side_of("referee") is None
    assert attack_direction("home", 1) == 1 and attack_direction("home", 2) == -1
    assert attack_direction("away", 1) == -1 and attack_direction("away", 2) == 1


def test_team_radio_counts_packets_drops_and_inboxes() -> None:
    radio = TeamRadio()
    packet = parse_action("home_0", make_action(Motion.STAND, radio=b"hi"))
    silent = parse_action("away_0", make_action(Motion.STAND))
    radio.actions({"home_0": packet, "home_1": packet, "away_0": silent, "away_1": None})
    radio.observations({"home_0": {"radio": {"dropped": 1, "count": 0}}, "home_1": {"radio": {"dropped": 0, "count": 1}},
                        "away_0": {"radio": {"dropped": 0, "count": 0}}})
    assert radio.to_json() == {"home": {"sent": 1, "dropped": 1, "received": 1},
                               "away": {"sent": 0, "dropped": 0, "received": 0}}


def test_lost_share_stillness_and_restarts(statistics: dict) -> None:
    home, away = statistics["home"], statistics["away"]
    assert home["lost_share"] == pytest.approx(1 / 9, abs=1e-4)  # the one estimate 1 m off (0.5 m is not lost)
    assert away["lost_share"] is None
    assert home["field_lost_share"] is None and home["field_pose_estimates"] == 0  # a goalkeeper alone
    # nobody moves: the longest stretch of play without a stop is rows 1-6 (1 s to 6 s)
    assert home["longest_still_s"] == pytest.approx(5.0) and away["longest_still_s"] == pytest.approx(5.0)
    assert home["longest_still_field_s"] == away["longest_still_field_s"] == 0.0  # goalkeepers alone
    assert statistics["restart_max_s"] == pytest.approx(1.0)  # the kick-off at 1 s, the first touch at 2 s
    assert statistics["restart_waits_s"] == [pytest.approx(1.0)] and statistics["restarts_slow"] == 0


def test_every_restart_s_wait_is_timed_to_the_next_touch_or_restart() -> None:
    events = [
        {"time_s": 0.0, "kind": "state", "state": "PLAYING", "half": 1, "secondary": "NORMAL"},
        {"time_s": 0.0, "kind": "kickoff", "team": "home", "half": 1},
        {"time_s": 2.5, "kind": "touch", "robot": "home_1", "x": 0.0, "y": 0.0},
        {"time_s": 3.5, "kind": "touch", "robot": "away_1", "x": 0.1, "y": 0.0},  # not a restart's
        {"time_s": 6.0, "kind": "ball_out", "line": "side_line", "x": 1.0, "y": 2.1, "last_toucher": "away_1"},
        {"time_s": 8.0, "kind": "throw_in", "x": 2.0, "y": 1.6, "line": "side_line"},
        {"time_s": 18.5, "kind": "touch", "robot": "home_2", "x": 2.0, "y": 1.6},  # 10.5 s: slow
        {"time_s": 20.0, "kind": "ball_out", "line": "side_line", "x": 1.0, "y": -2.1, "last_toucher": "home_2"},
        {"time_s": 22.0, "kind": "throw_in", "x": 0.0, "y": -1.6, "line": "side_line"},
        {"time_s": 29.0, "kind": "half_time", "score": {"home": 0, "away": 0}},  # untouched: counts to half-time
    ]
    log = hand_built_log()
    statistics = match_statistics(events, log, {})
    assert statistics["restart_waits_s"] == [pytest.approx(2.5), pytest.approx(10.5), pytest.approx(7.0)]
    assert statistics["restarts_slow"] == 1 and statistics["restart_max_s"] == pytest.approx(10.5)


def test_a_robot_that_moves_is_not_still() -> None:
    log = hand_built_log()
    log["robots"] = log["robots"].copy()
    log["robots"][:, 0, 0] = np.arange(len(ROWS)) * 0.2  # home_0 walks 0.2 m every row
    statistics = match_statistics(EVENTS, log, SUMMARY)
    assert statistics["home"]["longest_still_s"] == pytest.approx(0.0)
    assert statistics["away"]["longest_still_s"] == pytest.approx(5.0)



def test_a_field_player_counts_in_the_field_figures_where_a_goalkeeper_does_not() -> None:
    log = hand_built_log()
    log["agents"] = np.array(["home_1", "away_0"])
    statistics = match_statistics(EVENTS, log, SUMMARY)
    home = statistics["home"]
    assert home["longest_still_field_s"] == pytest.approx(5.0)
    assert statistics["away"]["longest_still_field_s"] == 0.0
    assert home["field_lost_share"] == home["lost_share"] == pytest.approx(1 / 9, abs=1e-4)
    assert home["field_position_error_mean_m"] == home["position_error_mean_m"]


def kicked_ball_log(start_xy: tuple[float, float], velocity: tuple[float, float], seconds: float) -> dict:
    """A hand-built log with 40 ms rows of a ball rolling in a straight line, in half 1's playing time."""
    time_s = np.arange(0.0, seconds, 0.04)
    log = hand_built_log()
    log.update(time_s=time_s, state=np.full(time_s.size, PLAYING, dtype=np.int8),
               half=np.ones(time_s.size, dtype=np.int8),
               ball=np.stack([start_xy[0] + velocity[0] * time_s, start_xy[1] + velocity[1] * time_s,
                              np.full(time_s.size, 0.0325)], axis=1))
    for key in ("robots", "fallen", "estimates"):
        log[key] = np.repeat(log[key][:1], time_s.size, axis=0)
    return log


@pytest.mark.parametrize(("velocity_y", "own_goal"), [(-0.05, False), (-0.9, True)])
def test_a_shot_deflected_at_once_is_the_shooter_s_goal(velocity_y: float, own_goal: bool) -> None:
    # away attacks -x in half 1: away_0 kicks from (-1.8, -0.2) at 1.5 m/s toward its target; home_0 touches
    # the ball 0.08 s later and it goes in. On a line between the posts it was a shot on target (the area rule
    # never sees it: the next touch comes long before the goal area); aimed wide, home_0 turned it in.
    log = kicked_ball_log((-1.8, -0.2), (-1.5, velocity_y), 1.0)
    events = [
        {"time_s": 0.0, "kind": "touch", "robot": "away_0", "x": -1.8, "y": -0.2},
        {"time_s": 0.08, "kind": "touch", "robot": "home_0", "x": -1.92, "y": -0.2},
        {"time_s": 0.96, "kind": "goal", "team": "away", "goal": "blue", "last_toucher": "home_0",
         "score": {"home": 0, "away": 1}},
    ]
    statistics = match_statistics(events, log, {})
    assert statistics["home"]["own_goals"] == int(own_goal)
    assert statistics["away"]["shots_on_target"] == int(not own_goal)
    assert statistics["away"]["shots_scored"] == int(not own_goal)  # the deflection still scores
    assert statistics["away"]["shots_saved"] == 0  # the keeper's touch did not keep it out


@pytest.mark.parametrize(("after", "shots", "outcomes"), [
    ([(0.6, "touch", "home_0"), (0.9, "ball_out", None)], 1, (0, 1, 0)),  # the other team's goalkeeper first: saved
    ([(0.6, "touch", "home_2"), (0.7, "touch", "home_0")], 1, (0, 0, 1)),  # another robot of theirs first: blocked
    # the kick's second contact (a shot of its own, on the same line), then a deflection in: both scored
    ([(0.2, "touch", "away_0"), (0.6, "touch", "home_2"), (0.9, "goal", None)], 2, (2, 0, 0)),
    # played on by a teammate (whose touch is a shot too), then out: neither saved nor blocked
    ([(0.6, "touch", "away_1"), (0.9, "ball_out", None)], 2, (0, 0, 0)),
    ([(0.9, "ball_out", None), (2.9, "throw_in", None)], 1, (0, 0, 0)),  # over the line beside the post
])
def test_what_became_of_a_shot(after: list, shots: int, outcomes: tuple[int, int, int]) -> None:
    # away_0 shoots from (-1.8, -0.2) at 1.5 m/s on a line between the posts of the goal it attacks (-x in half 1)
    log = kicked_ball_log((-1.8, -0.2), (-1.5, -0.05), 1.0)
    events = [{"time_s": 0.0, "kind": "touch", "robot": "away_0", "x": -1.8, "y": -0.2}]
    for time_s, kind, robot in after:
        event = {"time_s": time_s, "kind": kind}
        if robot is not None:
            event.update(robot=robot, x=-1.8 - 1.5 * time_s, y=-0.2)
        if kind == "goal":
            event.update(team="away", goal="blue", last_toucher="home_2", score={"home": 0, "away": 1})
        events.append(event)
    away = match_statistics(events, log, {})["away"]
    assert away["shots_on_target"] == shots
    assert (away["shots_scored"], away["shots_saved"], away["shots_blocked"]) == outcomes


def test_a_still_robot_is_stuck_only_while_its_own_actions_ask_it_to_move() -> None:
    """Both robots stand still through rows 1-6 (1 s to 6 s). home_1 walks into something all along: stuck
    for 5 s; away_1 stands on purpose, and asks for a walk of zero speed at 3 s and a turn at 4 s: stuck
    for 1 s. A log without actions gives no stuck figures."""
    from match.log import MOTIONS, NO_ACTION

    log = hand_built_log()
    log["agents"] = np.array(["home_1", "away_1"])
    n = len(ROWS)
    log["motion_names"] = np.array([m.value for m in MOTIONS])
    motions = np.full((n, 2), MOTIONS.index(Motion.STAND), dtype=np.int8)
    walks = np.zeros((n, 2, 3), dtype=np.float32)
    motions[:, 0] = MOTIONS.index(Motion.WALK)
    walks[:, 0] = (0.2, 0.0, 0.0)
    motions[0] = NO_ACTION  # the first row: no action led to it
    motions[3, 1] = motions[4, 1] = MOTIONS.index(Motion.WALK)
    walks[4, 1] = (0.0, 0.0, 0.3)
    log["motions"], log["walks"] = motions, walks
    statistics = match_statistics(EVENTS, log, SUMMARY)
    home, away = statistics["home"], statistics["away"]
    assert home["longest_still_field_s"] == away["longest_still_field_s"] == pytest.approx(5.0)
    assert home["longest_stuck_s"] == home["longest_stuck_field_s"] == pytest.approx(5.0)
    assert away["longest_stuck_s"] == away["longest_stuck_field_s"] == pytest.approx(1.0)
    log["robots"] = log["robots"].copy()
    log["robots"][:, 0, 0] = np.arange(n) * 0.2  # home_1 walks 0.2 m every row: neither still nor stuck
    assert match_statistics(EVENTS, log, SUMMARY)["home"]["longest_stuck_s"] == pytest.approx(0.0)
    assert match_statistics(EVENTS, hand_built_log(), SUMMARY)["home"]["longest_stuck_s"] is None
