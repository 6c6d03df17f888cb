"""Agent reports in the match log: the AgentReport type, the reader that contains failing reports,
and a short match where a team agent's reports are logged and broken reports do not stop play."""

from __future__ import annotations

import logging
import math

import numpy as np
import pytest

from agents.behavior.policies.scripted import ScriptedPlayer
from agents.team.agent import TeamAgent
from agents.team.report import landmarks_seen
from agents.vision.percepts import LandmarkPercept
from match.errors import InvalidReportError
from match.game import MatchConfig
from match.protocol import AgentReport, AgentReporter, Motion, Pose2D, make_action
from match.protocol.policy import check_pose
from match.referee import RefereeConfig
from match.reports import ReportReader
from match.runner import run_match
from scenarios.replay.record import load_match
from world.field import FIELD, LandmarkId, LandmarkKind

SHORT = RefereeConfig(half_seconds=2.0, initial_seconds=0.2, ready_seconds=0.4, set_seconds=0.2, shootout=False)
STEPS = 60  # 2.4 s: INITIAL, READY, SET and some PLAYING


# ---- the report type -------------------------------------------------------------------------


def test_a_report_is_normalized() -> None:
    report = AgentReport(ball_xy=np.array([1, 2.5]), team_ball_xy=[0, 0], role="striker",
                         landmarks_seen=[np.int64(3), 0, 3])
    assert report.ball_xy == (1.0, 2.5) and report.team_ball_xy == (0.0, 0.0)
    assert report.landmarks_seen == frozenset({0, 3}) and isinstance(report, AgentReport)
    assert AgentReport.check(None) is None and AgentReport.check(report) == report
    assert check_pose((1, 2, 0.5)) == (1.0, 2.0, 0.5) and check_pose(None) is None


@pytest.mark.parametrize("fields", [
    {"ball_xy": (1.0,)}, {"ball_xy": ("1", "2")}, {"ball_xy": (math.nan, 0.0)}, {"team_ball_xy": "xy"},
    {"ball_xy": (1e9, 0.0)}, {"ball_xy": 3.0}, {"role": ""}, {"role": 7}, {"role": "x" * 100},
    {"landmarks_seen": [17]}, {"landmarks_seen": [-1]}, {"landmarks_seen": ["0"]}, {"landmarks_seen": [True]},
    {"landmarks_seen": 5},
])
def test_garbage_in_a_report_is_refused(fields: dict) -> None:
    with pytest.raises(InvalidReportError):
        AgentReport(**fields)


@pytest.mark.parametrize("value", [{"ball_xy": (0, 0)}, "report", 3])
def test_a_report_of_another_type_is_refused(value: object) -> None:
    with pytest.raises(InvalidReportError, match="expected an AgentReport"):
        AgentReport.check(value)


@pytest.mark.parametrize("value", [(1.0, 2.0), ("a", "b", "c"), (0.0, math.inf, 0.0), "abc", np.zeros((3, 1, 2))])
def test_garbage_pose_estimates_are_refused(value: object) -> None:
    with pytest.raises(InvalidReportError):
        check_pose(value)


# ---- the reader --------------------------------------------------------------------------


class Plain:
    def reset(self, agent_id: str, seed: int) -> None:
        pass

    def act(self, observation: dict) -> dict:
        return make_action(Motion.STAND)


class Raises(Plain):
    def report(self) -> AgentReport | None:
        raise RuntimeError("report bug")

    def pose_estimate(self):
        return ("x", "y", "z")


class Garbage(Plain):
    def report(self):
        return {"ball_xy": (0.0, 0.0)}


class Reports(Plain):
    def report(self) -> AgentReport:
        return AgentReport(ball_xy=(0.5, -0.5), role="striker", landmarks_seen={6})


def test_the_reader_contains_failing_reports_and_warns_once_per_robot(caplog: pytest.LogCaptureFixture) -> None:
    reader = ReportReader({"home_0": Raises(), "home_1": Garbage(), "away_0": Reports(), "away_1": Plain()})
    assert isinstance(Reports(), AgentReporter) and not isinstance(Plain(), AgentReporter)
    with caplog.at_level(logging.WARNING, logger="match.reports"):
        for _ in range(3):
            reports = reader.reports()
            estimates = reader.estimates()
    assert reports == {"home_0": None, "home_1": None, "away_0": Reports().report(), "away_1": None}
    assert estimates == {"home_0": None, "home_1": None, "away_0": None, "away_1": None}
    warnings = [r.getMessage() for r in caplog.records]
    assert len(warnings) == 3  # home_0 report, home_0 pose_estimate, home_1 report: once each
    assert reader.failures == {("home_0", "report"): 3, ("home_0", "pose_estimate"): 3, ("home_1", "report"): 3}


# ---- landmarks of a frame --------------------------------------------------------------------


def test_landmarks_seen_are_matched_to_the_nearest_possible_landmark() -> None:
    pose = Pose2D(-1.0, 0.5, 0.0)
    corner = FIELD.landmark(LandmarkId.GOAL_AREA_CORNER_YELLOW_LEFT)  # (2.4, 1.1): an ambiguous L corner
    dx, dy = corner.x - pose.x, corner.y - pose.y
    percepts = [
        LandmarkPercept(LandmarkKind.L_CORNER, (80.0, 60.0), math.atan2(dy, dx), math.hypot(dx, dy) * 1.05, "exact"),
        LandmarkPercept(LandmarkKind.CENTER_CIRCLE, (80.0, 90.0), math.atan2(-0.5, 1.0), 1.1, "exact"),
    ]
    index = {lm.id: i for i, lm in enumerate(FIELD.landmarks)}
    assert landmarks_seen(percepts, pose) == {index[corner.id], index[LandmarkId.CENTER_CIRCLE]}
    assert landmarks_seen([], pose) == frozenset()


# ---- in a match --------------------------------------------------------------------------


@pytest.fixture(scope="module")
def reported_match(tmp_path_factory: pytest.TempPathFactory):
    out = tmp_path_factory.mktemp("reports")
    config = MatchConfig(home_players=2, away_players=2, referee=SHORT)
    policies = {"home_0": TeamAgent(), "home_1": Raises(), "away_0": ScriptedPlayer(), "away_1": Garbage()}
    summary = run_match(config, policies, seed=1, out_dir=out, progress=False, max_steps=STEPS)
    return summary, out


@pytest.mark.render
def test_a_team_agents_reports_are_logged_and_others_are_nan(reported_match) -> None:
    summary, out = reported_match
    assert summary.steps == STEPS and summary.faults["total"] == 0  # broken reports are no faults of play
    log = np.load(out / "match_log.npz")
    agents = [str(a) for a in log["agents"]]
    team = agents.index("home_0")
    assert log["ball_estimates"].shape == (STEPS + 1, 4, 2) and log["roles"].shape == (STEPS + 1, 4)
    seen = log["landmarks_seen"][1:, team]
    assert np.isfinite(seen).all() and (seen > 0).any() and (seen < 2 ** len(FIELD.landmarks)).all()
    assert np.isfinite(log["team_ball"][:, team]).any()
    assert [str(n) for n in log["role_names"]] == ["goalkeeper"]  # player 0, once PLAYING
    assert np.isfinite(log["roles"][:, team]).any()
    for other in ("home_1", "away_0", "away_1"):  # raises, scripted (no reports), garbage
        i = agents.index(other)
        for key in ("ball_estimates", "team_ball", "roles", "landmarks_seen", "estimates"):
            assert np.isnan(log[key][:, i]).all(), (other, key)
    # the actions that led to each row: none to the first, every robot's (a stand at least) to the others
    names = [str(n) for n in log["motion_names"]]
    assert log["motions"].shape == (STEPS + 1, 4) and log["walks"].shape == (STEPS + 1, 4, 3)
    assert (log["motions"][0] == -1).all() and (log["motions"][1:] >= 0).all()
    assert names[log["motions"][-1, team]] in ("stand", "walk", "kick_left", "kick_right")
    walking = log["motions"][1:, team] == names.index("walk")
    assert walking.any() and np.abs(log["walks"][1:, team][walking]).max() > 0.0
    record = load_match(out)  # the replay page reads them
    assert set(record.extras) >= {"ball_estimate", "team_ball", "role", "landmarks"}
    assert record.labels["role"] == ("goalkeeper",)
