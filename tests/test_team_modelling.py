"""The team agent's models: the ball filter, the self-locator's odometry, the team ball, and roles."""

from __future__ import annotations

import math

import pytest

from agents.behavior.tactics.roles import Candidate, assign_role, role_position, time_to_ball
from agents.modelling.ball_absence import MISS_WINDOW_S, MISSES_TO_FORGET, BallAbsence, in_clear_view, in_view
from agents.modelling.ball_model import ROLL_DECAY_S, BallEstimate, BallModel
from agents.modelling.obstacle_model import Obstacle, ObstacleKind
from agents.localization.estimate import EstimateSource, PoseEstimate
from agents.modelling.self_locator import DOUBT_SIGMA_M, JUMP_CONFIRMATIONS, SelfLocator
from agents.modelling.team_model import MESSAGE_TIMEOUT_S, TeamModel
from agents.radio import Role, TeamMessage
from agents.team.modelling.odometry import arc as _arc
from agents.vision.percepts import LandmarkPercept
from match.protocol import Displacement, Pose2D
from world.camera_model import CameraPosition
from world.field import FIELD, LandmarkId, LandmarkKind

STILL = Displacement(0.0, 0.0, 0.0)


def test_ball_model_follows_a_rolling_ball_and_estimates_its_speed() -> None:
    model = BallModel()
    for k in range(60):
        model.predict(0.04, STILL)
        t = (k + 1) * 0.04
        model.measure(1.0 + ROLL_DECAY_S * (1.0 - math.exp(-t / ROLL_DECAY_S)), 0.0)
    ball = model.relative()
    speed = math.exp(-60 * 0.04 / ROLL_DECAY_S)
    assert ball.vx == pytest.approx(speed, abs=0.1) and abs(ball.vy) < 0.05 and ball.age_s == 0.0


def test_ball_model_moves_the_ball_into_the_robots_new_frame() -> None:
    model = BallModel()
    model.predict(0.04, STILL)
    model.measure(1.0, 0.0)
    model.predict(0.04, Displacement(0.2, 0.0, math.pi / 2))  # walked 0.2 m, then faces left
    ball = model.relative()
    assert (ball.x, ball.y) == pytest.approx((0.0, -0.8), abs=0.01)
    field = model.in_field((0.2, 0.0, math.pi / 2), 0.1, 0.0)
    assert (field.x, field.y) == pytest.approx((1.0, 0.0), abs=0.01) and field.sigma_m > ball.sigma_m


def test_ball_model_restarts_after_the_ball_jumped() -> None:
    model = BallModel()
    for _ in range(5):
        model.predict(0.04, STILL)
        model.measure(1.0, 0.0)
    model.predict(0.04, STILL)
    model.measure(2.5, 1.0)  # one wild sighting is not enough
    assert model.relative().distance_m == pytest.approx(1.0, abs=0.05)
    model.predict(0.04, STILL)
    model.measure(2.5, 1.0)
    assert model.relative().distance_m == pytest.approx(2.5, abs=0.01)


LOOKING_DOWN_RAD = 0.49  # head pitch at which the top camera centres a ball 0.9 m ahead


def test_a_ball_is_in_clear_view_only_near_in_the_image_and_unhidden() -> None:
    ahead = BallEstimate(0.9, 0.0, 0.0, 0.0, 0.05, 0.5)
    assert in_clear_view(ahead, 0.0, LOOKING_DOWN_RAD, CameraPosition.TOP, ())
    assert not in_clear_view(ahead, 0.6, LOOKING_DOWN_RAD, CameraPosition.TOP, ())  # the head looks left of it
    assert not in_clear_view(ahead, 0.0, 0.0, CameraPosition.TOP, ())  # it is below the image
    assert not in_clear_view(BallEstimate(-0.9, 0.0, 0.0, 0.0, 0.05, 0.5), 0.0, LOOKING_DOWN_RAD,
                             CameraPosition.TOP, ())  # behind the robot
    unsure = BallEstimate(0.9, 0.0, 0.0, 0.0, 0.4, 0.5)
    assert not in_clear_view(unsure, 0.0, LOOKING_DOWN_RAD, CameraPosition.TOP, ())  # too unsure for a miss to count
    assert in_view(unsure, 0.0, LOOKING_DOWN_RAD, CameraPosition.TOP, ())  # ... but worth a look there
    hidden_by = Obstacle(0.5, 0.03, ObstacleKind.OPPONENT, 0.0)
    assert not in_view(unsure, 0.0, LOOKING_DOWN_RAD, CameraPosition.TOP, (hidden_by,))
    far = BallEstimate(3.0, 0.0, 0.0, 0.0, 0.05, 0.5)
    assert not in_clear_view(far, 0.0, 0.1, CameraPosition.TOP, ())
    in_front = Obstacle(0.5, 0.03, ObstacleKind.OPPONENT, 0.0)
    assert not in_clear_view(ahead, 0.0, LOOKING_DOWN_RAD, CameraPosition.TOP, (in_front,))
    beside = Obstacle(0.5, 0.4, ObstacleKind.OPPONENT, 0.0)
    assert in_clear_view(ahead, 0.0, LOOKING_DOWN_RAD, CameraPosition.TOP, (beside,))
    at_the_feet = BallEstimate(0.18, 0.0, 0.0, 0.0, 0.05, 0.5)
    assert in_clear_view(at_the_feet, 0.0, 0.5, CameraPosition.BOTTOM, ())
    by_the_legs = BallEstimate(0.14, 0.14, 0.0, 0.0, 0.05, 0.5)  # 45 degrees left: a leg may hide it
    assert not in_clear_view(by_the_legs, math.pi / 4, 0.5, CameraPosition.BOTTOM, ())


def test_a_ball_missed_in_clear_view_is_forgotten_after_a_few_frames() -> None:
    absence = BallAbsence()
    frames = [absence.frame(0.08 * k, seen=False, expected=k % 2 == 0) for k in range(2 * MISSES_TO_FORGET)]
    assert frames.index(True) == 2 * MISSES_TO_FORGET - 2  # frames that could not show it do not clear the count
    assert absence.forgotten == 1
    absence = BallAbsence()
    for k in range(3 * MISSES_TO_FORGET):  # a sighting among the misses clears them
        assert not absence.frame(0.08 * k, seen=k % MISSES_TO_FORGET == 0, expected=True)
    absence = BallAbsence()
    spread = MISS_WINDOW_S * 1.01  # misses farther apart than the window never add up
    assert not any(absence.frame(spread * k, seen=False, expected=True) for k in range(3 * MISSES_TO_FORGET))


def test_walk_arcs_compose_to_the_same_displacement() -> None:
    locator = SelfLocator("odometry", 0)
    locator.reset(Pose2D(0.0, 0.0, 0.0))
    for _ in range(100):  # 4 s at 0.1 m/s while turning 0.4 rad/s
        locator.move(_arc(0.1, 0.0, 0.4, 0.04))
    pose = locator.pose
    radius = 0.1 / 0.4
    assert pose.theta == pytest.approx(1.6, abs=1e-6)
    assert (pose.x, pose.y) == pytest.approx((radius * math.sin(1.6), radius * (1 - math.cos(1.6))), abs=1e-6)
    assert locator.sigma_m > 0.05


def test_team_ball_prefers_the_fresher_and_surer_estimate() -> None:
    team = TeamModel(own_player=1)
    own = BallEstimate(1.0, 0.0, 0.0, 0.0, 0.5, 1.5)
    team.hear(TeamMessage(2, 1, (0.0, 0.0, 0.0), ball_xy=(2.0, 1.0), ball_sigma_m=0.1, ball_age_s=0.1), now_s=10.0)
    ball, player = team.team_ball(own, now_s=10.2)
    assert player == 2 and (ball.x, ball.y) == pytest.approx((2.0, 1.0)) and ball.age_s == pytest.approx(0.3)
    sure_own = BallEstimate(1.0, 0.0, 0.0, 0.0, 0.05, 0.0)
    assert team.team_ball(sure_own, now_s=10.2)[1] == 1
    assert team.team_ball(None, now_s=10.0 + MESSAGE_TIMEOUT_S + 0.1) is None  # the teammate fell silent
    team.hear(TeamMessage(1, 1, None, ball_xy=(0.0, 0.0)), now_s=10.0)  # its own echo is not a teammate
    assert [m.message.player for m in team.teammates(10.0)] == [2]


def test_roles_one_striker_with_hysteresis_and_the_rest_by_number() -> None:
    assert assign_role(Candidate(0, 1.0), [], Role.NONE) is Role.GOALKEEPER
    others = [Candidate(0, 0.5), Candidate(2, 5.0), Candidate(3, 9.0)]
    assert assign_role(Candidate(1, 6.0), others, Role.NONE) is Role.DEFENDER
    assert assign_role(Candidate(3, 9.0), [Candidate(1, 6.0), Candidate(2, 5.0)], Role.NONE) is Role.SUPPORTER
    assert assign_role(Candidate(2, 5.0), [Candidate(1, 6.0)], Role.NONE) is Role.STRIKER
    # The striker keeps its role against a robot only a little faster.
    assert assign_role(Candidate(1, 6.0), [Candidate(2, 5.0)], Role.STRIKER) is Role.STRIKER
    assert assign_role(Candidate(1, 6.0), [Candidate(2, 4.0)], Role.STRIKER) is Role.DEFENDER
    assert assign_role(Candidate(1, math.inf), [], Role.NONE) is Role.STRIKER  # alone: always the striker


def test_roles_a_lone_goalkeeper_plays_the_field() -> None:
    """A goalkeeper that hears no teammate is a team of one: it is the striker, which only keeping the
    goal would never be; a field player alone is the striker anyway."""
    assert assign_role(Candidate(0, 1.0), [], Role.NONE, lone=True) is Role.STRIKER
    assert assign_role(Candidate(0, 1.0), [], Role.GOALKEEPER) is Role.GOALKEEPER
    assert assign_role(Candidate(1, 1.0), [], Role.NONE, lone=True) is Role.STRIKER


def test_team_model_silence_counts_from_the_last_teammate_heard() -> None:
    team = TeamModel(own_player=0)
    assert team.silent_for_s(3.0) == pytest.approx(3.0)  # none heard yet: since the own clock began
    team.hear(TeamMessage(2, 1, None), now_s=5.0)
    team.hear(TeamMessage(1, 1, None), now_s=6.0)
    assert team.silent_for_s(7.5) == pytest.approx(1.5)
    team.hear(TeamMessage(0, 1, None), now_s=7.0)  # its own echo is no teammate
    assert team.silent_for_s(7.5) == pytest.approx(1.5)


def test_roles_two_strikers_agree_on_one() -> None:
    """The hysteresis counts for every robot that says it is the striker, so each robot's view agrees."""
    # A robot a little faster than the striker does not take the role the striker keeps.
    assert assign_role(Candidate(2, 5.0), [Candidate(1, 6.0, striker=True)], Role.NONE) is Role.DEFENDER
    # Two robots that both took the role: the faster keeps it, the other yields, from either side.
    assert assign_role(Candidate(1, 6.0), [Candidate(2, 5.5, striker=True)], Role.STRIKER) is Role.DEFENDER
    assert assign_role(Candidate(2, 5.5), [Candidate(1, 6.0, striker=True)], Role.STRIKER) is Role.STRIKER


def test_time_to_ball_counts_the_turn() -> None:
    facing = time_to_ball(Pose2D(0.0, 0.0, 0.0), (1.0, 0.0))
    away = time_to_ball(Pose2D(0.0, 0.0, math.pi), (1.0, 0.0))
    assert away > facing and time_to_ball(Pose2D(0.0, 0.0, 0.0), (1.0, 0.0), fallen=True) > facing


@pytest.mark.parametrize("attack", [1.0, -1.0])
def test_role_positions_stay_on_the_own_side_of_the_ball(attack: float) -> None:
    ball = (0.5 * attack, 0.8 * attack)
    keeper = role_position(Role.GOALKEEPER, ball, attack)
    defender = role_position(Role.DEFENDER, ball, attack)
    supporter = role_position(Role.SUPPORTER, ball, attack)
    assert keeper.x * attack == pytest.approx(-2.85) and abs(keeper.y) <= 0.55
    assert defender.x * attack < ball[0] * attack and supporter.x * attack < ball[0] * attack
    for pose in (keeper, defender, supporter):
        assert abs(pose.x) <= 3.0 and abs(pose.y) <= 2.0


class _FixedLocalizer:
    """A localizer stand-in whose every fix is ``fix`` (and which counts its resets)."""

    name = "fixed"

    def __init__(self, fix: Pose2D) -> None:
        self.fix, self.pose, self.resets, self.widened = fix, None, 0, 0

    def reset(self, pose: Pose2D) -> None:
        self.pose, self.resets = pose, self.resets + 1

    def move(self, displacement: Displacement) -> None:
        pass

    def widen(self, sigma_m: float, sigma_rad: float) -> None:
        self.widened += 1

    def localize(self, percepts):
        return PoseEstimate(self.fix.x, self.fix.y, self.fix.theta, "fixed", EstimateSource.LANDMARKS)


LINE_CORNER = LandmarkPercept(LandmarkKind.L_CORNER, (80.0, 90.0), 0.1, 1.5, "exact")
TRACKED = Pose2D(-1.0, 0.5, 0.0)
MIRRORED = Pose2D(1.0, -0.5, math.pi)  # the field's point reflection of TRACKED: only the goals' colours differ


def seen_from(pose: Pose2D, landmark: LandmarkId) -> LandmarkPercept:
    """The exact percept of ``landmark`` from ``pose`` (a post's side left unknown, as from afar)."""
    mark = next(m for m in FIELD.landmarks if m.id is landmark)
    bearing = math.atan2(mark.y - pose.y, mark.x - pose.x) - pose.theta
    return LandmarkPercept(mark.kind, (80.0, 60.0), math.remainder(bearing, math.tau),
                           math.hypot(mark.x - pose.x, mark.y - pose.y), "exact",
                           goal=mark.goal if mark.kind in (LandmarkKind.GOAL_POST, LandmarkKind.GOAL_CENTER) else None)


def test_a_far_fix_counts_only_when_its_frame_contradicts_the_tracked_pose() -> None:
    locator = SelfLocator("odometry", 0)
    locator.localizer = stand_in = _FixedLocalizer(MIRRORED)
    locator.reset(TRACKED)
    corner = seen_from(MIRRORED, LandmarkId.GOAL_AREA_CORNER_BLUE_LEFT)  # the tracked pose sees one there too
    for _ in range(JUMP_CONFIRMATIONS + 3):  # lines alone repeat over the field: never evidence
        assert locator.update((corner,)) is None
        assert locator.pose == TRACKED
    assert stand_in.resets == 1  # the localizer is left to itself: if it keeps finding the far pose, it wins
    assert locator.sigma_m >= DOUBT_SIGMA_M  # meanwhile the robot doubts, and looks for landmarks
    post = seen_from(MIRRORED, LandmarkId.BLUE_GOAL_LEFT_POST)  # where the tracked pose has the yellow goal
    for _ in range(JUMP_CONFIRMATIONS - 1):
        assert locator.update((corner, post)) is None
    assert locator.update((post,)) is not None and locator.pose == MIRRORED
    assert locator.rejected_fixes == JUMP_CONFIRMATIONS + 3 + JUMP_CONFIRMATIONS - 1


def test_agreeing_far_fixes_need_a_goal() -> None:
    locator = SelfLocator("odometry", 0)
    far = Pose2D(-1.0, -1.5, 0.0)  # 2 m to the side: the same lines in view
    locator.localizer = _FixedLocalizer(far)
    locator.reset(TRACKED)
    corner = seen_from(far, LandmarkId.GOAL_AREA_CORNER_YELLOW_RIGHT)
    circle = seen_from(far, LandmarkId.CENTER_CIRCLE)
    for _ in range(JUMP_CONFIRMATIONS + 3):  # evidence, but from lines alone
        assert locator.update((corner, circle)) is None and locator.pose == TRACKED
    post = seen_from(far, LandmarkId.YELLOW_GOAL_RIGHT_POST)
    assert locator.update((corner, circle, post)) is not None and locator.pose == far


def test_after_a_fall_a_fix_may_turn_the_heading_at_once() -> None:
    locator = SelfLocator("odometry", 0)
    turned = Pose2D(-1.1, 0.5, math.radians(80.0))
    locator.localizer = stand_in = _FixedLocalizer(turned)
    locator.reset(Pose2D(-1.0, 0.5, 0.0))
    locator.fell(0.2, math.radians(60.0))
    assert stand_in.widened == 1
    assert locator.update((LINE_CORNER,)) is not None and locator.pose == turned


def test_the_closed_form_spread_is_the_largest_eigenvalue() -> None:
    import numpy as np

    from agents.modelling.spread import largest_eigenvalue

    rng = np.random.default_rng(0)
    for _ in range(200):
        m = rng.normal(size=(2, 2))
        m = m @ m.T
        assert largest_eigenvalue(m[0, 0], m[0, 1], m[1, 1]) == pytest.approx(float(np.linalg.eigvalsh(m).max()))
    assert largest_eigenvalue(0.0, 0.0, 0.0) == 0.0
