"""Tournament statistics against hand-computed cases, and the report of a hand-made round robin."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest

from scenarios.tournament.game_flow import game_flow
from scenarios.tournament.report import RESULT_COLUMNS, build_report, table_markdown, winner_name
from scenarios.tournament.run import write_report
from scenarios.tournament.settings import TournamentError, TournamentSettings
from scenarios.tournament.statistics import (
    Game,
    Standing,
    bradley_terry,
    elo,
    mean_interval,
    ratings,
    verdict,
    wilson_interval,
)
from match.statistics import TEAM_KEYS


def test_wilson_interval_by_hand() -> None:
    # 8 of 10, z = 1.96: centre (0.8 + z^2/20) / (1 + z^2/10), half-width z sqrt(0.016 + z^2/400) / (1 + z^2/10)
    low, high = wilson_interval(8, 10)
    assert low == pytest.approx(0.49016, abs=1e-5) and high == pytest.approx(0.94332, abs=1e-5)
    low, high = wilson_interval(6, 6)  # all won: the upper end is 1, the lower z^2/n away
    assert high == 1.0 and low == pytest.approx(1 / (1 + 1.959964**2 / 6), abs=1e-5)
    assert wilson_interval(0, 6) == pytest.approx((0.0, 1 - 1 / (1 + 1.959964**2 / 6)), abs=1e-5)
    assert all(math.isnan(v) for v in wilson_interval(0, 0))


def test_goal_difference_interval_by_hand() -> None:
    centre, (low, high) = mean_interval([1.0, 2.0, 3.0])  # sd 1, t(0.975, 2) = 4.302653
    assert centre == 2.0 and high - centre == pytest.approx(4.302653 / math.sqrt(3), abs=1e-5)
    assert low == pytest.approx(2.0 - 4.302653 / math.sqrt(3), abs=1e-5)


def test_standing_counts_a_draw_as_half_a_win() -> None:
    games = [Game(2, 0, 1.0), Game(1, 1, 0.5), Game(0, 1, 0.0), Game(3, 0, 1.0)]
    st = Standing.of("A", games)
    assert (st.matches, st.wins, st.draws, st.losses) == (4, 2, 1, 1)
    assert st.win_rate == 2.5 / 4 and st.win_rate_ci95 == wilson_interval(2.5, 4)
    assert st.goals_for_per_match == 1.5 and st.goals_against_per_match == 0.5 and st.goal_difference == 1.0


def test_bradley_terry_recovers_a_known_table() -> None:
    # strengths 4 : 2 : 1 and win counts equal to their expectations: the fit is exact
    wins = np.array([[0, 4, 4], [2, 0, 2], [1, 1, 0]], dtype=float)
    strength = bradley_terry(wins, prior=0.0)
    assert strength / strength[2] == pytest.approx([4.0, 2.0, 1.0], rel=1e-6)
    rating = elo(strength)
    assert rating.mean() == pytest.approx(0.0, abs=1e-9)
    assert rating[0] - rating[1] == pytest.approx(400 * math.log10(2), rel=1e-6)
    with pytest.raises(ValueError, match="without a win"):
        bradley_terry(np.array([[0, 3, 3], [1, 0, 2], [0, 0, 0]], dtype=float), prior=0.0)
    assert np.all(np.isfinite(bradley_terry(np.array([[0, 3, 3], [0, 0, 2], [0, 0, 0]], dtype=float))))


def test_verdicts() -> None:
    strong = Standing.of("A", [Game(3, 0, 1.0), Game(2, 0, 1.0), Game(4, 1, 1.0), Game(2, 1, 1.0), Game(1, 0, 1.0),
                               Game(2, 0, 1.0)])
    text = verdict("A", "B", strong)
    assert text.startswith("A beats B: win rate 1.00 [0.61, 1.00], goal difference +2.0 [")
    assert text.endswith("over 6 matches")
    weak = Standing.of("B", [Game(0, 3, 0.0), Game(0, 2, 0.0), Game(1, 4, 0.0), Game(1, 2, 0.0), Game(0, 1, 0.0),
                             Game(0, 2, 0.0)])
    assert verdict("B", "A", weak).startswith("A beats B: win rate 1.00 [0.61, 1.00], goal difference +2.0 [")
    even = Standing.of("A", [Game(1, 0, 1.0), Game(0, 1, 0.0), Game(1, 1, 0.5)])
    assert "no significant difference" in verdict("A", "B", even)
    single = Standing.of("A", [Game(5, 0, 1.0)])  # one match: no interval, no verdict
    assert "no significant difference" in verdict("A", "B", single)


# ---- a hand-made round robin ------------------------------------------------------------------

STRENGTH = {"alpha": 2, "beta": 1, "gamma": 0}


def round_robin_records(settings: TournamentSettings) -> list[dict]:
    """Goals by strength (alpha 2, beta 1, gamma 0), one more for the away team in game 2 of a pair; match 5 failed."""
    records = []
    for task in settings.tasks():
        statistics = {side: dict.fromkeys(TEAM_KEYS, 1) for side in ("home", "away")}
        record = {"match": task.index, "pair": task.pair, "game": task.game, "seed": task.seed,
                  "home_policy": task.home, "away_policy": task.away, "home_entrant": task.entrant("home"),
                  "away_entrant": task.entrant("away"), "status": "ok", "error": None, "attempts": 1,
                  "home_goals": STRENGTH[task.home], "away_goals": STRENGTH[task.away] + (task.game == 2),
                  "home_shootout": None, "away_shootout": None, "sim_seconds": 10.0, "wall_seconds": 1.0,
                  "statistics": statistics}
        difference = record["home_goals"] - record["away_goals"]
        record["winner_side"] = "home" if difference > 0 else ("away" if difference < 0 else None)
        if task.index == 5:
            record.update(status="failed", error="the worker process died (exit code 3), again when run alone",
                          attempts=2, home_goals=None, away_goals=None, winner_side=None, statistics=None)
        records.append(record)
    return records


def test_schedule_balances_home_and_seeds_do_not_depend_on_anything_else() -> None:
    settings = TournamentSettings(("alpha", "beta", "gamma"), matches=4, seed=9)
    tasks = settings.tasks()
    assert [(t.home, t.away) for t in tasks[:4]] == [("alpha", "beta"), ("beta", "alpha")] * 2
    assert [t.index for t in tasks] == list(range(12)) and len({t.seed for t in tasks}) == 12
    assert TournamentSettings(("alpha", "beta", "gamma"), matches=4, seed=9).tasks() == tasks
    assert TournamentSettings(("alpha", "beta", "gamma"), matches=4, seed=10).tasks()[0].seed != tasks[0].seed
    self_play = TournamentSettings(("stand", "stand"), matches=2)
    assert self_play.entrants() == ("stand (home)", "stand (away)")
    assert [t.entrant("home") for t in self_play.tasks()] == ["stand (home)"] * 2


@pytest.mark.parametrize("kwargs, words", [
    ({"policies": ("scripted",)}, ["1 policy given", "'scripted'"]),
    ({"policies": ("a", "b", "a")}, ["a named twice"]),
    ({"matches": 0}, ["--matches 0"]),
    ({"half_seconds": -1.0}, ["--half-seconds -1"]),
    ({"players": 5}, ["--players 5"]),
    ({"pauses": (1.0, -1.0, 0.0)}, ["--pauses"]),
])
def test_bad_settings_name_the_flag_and_the_value(kwargs: dict, words: list[str]) -> None:
    arguments = {"policies": ("scripted", "stand"), **kwargs}
    with pytest.raises(TournamentError) as refused:
        TournamentSettings(**arguments)
    for word in words:
        assert word in str(refused.value)


def test_ratings_and_report_of_a_round_robin(tmp_path: Path) -> None:
    settings = TournamentSettings(("alpha", "beta", "gamma"), matches=4, seed=9)
    records = round_robin_records(settings)
    report = build_report(settings, records, wall_seconds=1.0)
    order = [r.name for r in report.ratings]
    assert order == ["alpha", "beta", "gamma"]
    for rating in report.ratings:
        assert rating.ci95[0] <= rating.rating <= rating.ci95[1]
    assert ratings(records, settings.entrants(), seed=9) == list(report.ratings)  # seeded bootstrap
    standings = {s.name: s for s in report.standings}
    assert standings["alpha"].matches == 7  # match 5 (gamma v alpha) failed
    assert len(report.head_to_head) == 3 and report.failed[0]["match"] == 5

    write_report(tmp_path, report)
    for name in ("results.csv", "summary.json", "table.md", "standings.png", "ratings.png"):
        assert (tmp_path / name).stat().st_size > 0
    with (tmp_path / "results.csv").open(encoding="utf-8") as handle:
        rows = list(csv.DictReader(handle))
    assert tuple(rows[0]) == RESULT_COLUMNS and len(rows) == 12
    required = ("match", "seed", "home_policy", "away_policy", "home_goals", "away_goals", "home_shootout",
                "away_shootout", "winner", "home_possession", "away_shots_on_target", "home_faults")
    assert all(column in RESULT_COLUMNS for column in required)
    assert rows[1]["winner"] == "alpha" and rows[2]["winner"] == "" and rows[0]["home_shootout"] == ""
    assert rows[5]["status"] == "failed" and "exit code 3" in rows[5]["error"] and rows[5]["home_goals"] == ""
    summary = json.loads((tmp_path / "summary.json").read_text(encoding="utf-8"))
    assert summary["matches"] == {"planned": 12, "played": 11, "failed": 1}
    assert set(summary["ratings"]) == {"alpha", "beta", "gamma"}
    assert summary["verdicts"][0].startswith("alpha beats beta") or "no significant" in summary["verdicts"][0]
    table = table_markdown(report)
    assert "## Ratings" in table and "## Head to head" in table and "draws / 2" in table
    assert "match 5 (gamma v alpha)" in table
    assert "## Game flow" in table and "| alpha v beta | 4 | 4 | 8 | 8 | n/a | n/a | n/a | n/a |" in table
    assert summary["head_to_head"][0]["game_flow"]["matches_with_goals"] == 4


def flow_record(home: str, away: str, goals: tuple[int, int], own_goals: tuple[int, int] = (0, 0),
                waits: list[float] | None = None, status: str = "ok") -> dict:
    statistics = {side: {**dict.fromkeys(TEAM_KEYS, 0), "goals": g, "own_goals": o}
                  for side, g, o in zip(("home", "away"), goals, own_goals)}
    if waits is not None:
        statistics["restart_waits_s"] = waits
    return {"home_entrant": home, "away_entrant": away, "status": status,
            "statistics": statistics if status == "ok" else None}


def test_game_flow_pools_a_pair_s_goals_and_restart_waits() -> None:
    records = [
        flow_record("a", "b", (0, 0), waits=[2.0, 12.5, 4.0]),
        flow_record("b", "a", (2, 1), own_goals=(0, 1), waits=[3.0, 10.0]),  # 10 s is not over 10 s
        flow_record("a", "c", (5, 0), waits=[30.0]),  # another pair
        flow_record("b", "a", (9, 9), status="failed"),  # counts for nothing
        flow_record("a", "b", (0, 1)),  # an older record without the waits: its goals only
    ]
    flow = game_flow(records, "a", "b")
    assert (flow.matches, flow.matches_with_goals, flow.goals, flow.own_goals) == (3, 2, 4, 1)
    assert (flow.restarts, flow.restarts_slow, flow.restart_max_s) == (5, 1, 12.5)
    assert flow.restart_median_s == pytest.approx(4.0)
    untimed = game_flow(records[-1:], "a", "b")
    assert untimed.restarts is None and untimed.restart_median_s is None and untimed.matches_with_goals == 1


def test_winner_names() -> None:
    base = {"status": "ok", "home_policy": "scripted", "away_policy": "stand"}
    assert winner_name({**base, "winner_side": "away"}) == "stand"
    assert winner_name({**base, "winner_side": None}) == ""
    assert winner_name({**base, "away_policy": "scripted", "winner_side": "home"}) == "home"
