"""The team agent: it survives bad radio, no camera and black images, and never kicks toward its own goal."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from agents.modelling.ball_model import BallEstimate
from agents.policies import make_policy
from agents.behavior.skills import LONE_SILENCE_S
from agents.radio import Role, TeamMessage
from agents.team.agent import TeamAgent
from agents.team.params import TeamParams
from match.free_play import FreePlay
from match.game import MatchConfig
from match.protocol import (
    CameraChoice,
    Displacement,
    GameState,
    GoalColor,
    Motion,
    Pose2D,
    SecondaryState,
    make_action,
    observation_space,
    throw_in_spot,
)
from match.runner import run_match
from tests.team_scene import expected_restart as _expected_restart
from tests.team_scene import note_own_touch as _note_own_touch
from tests.team_scene import output as _output
from tests.team_scene import side_tap as _side_tap
from tests.team_scene import strike as _strike
from tests.team_scene import world as _world
from tests.user_policies import RadioFuzzer
from world.camera_model import CameraPosition
from world.field import FIELD

P = TeamParams.default()


def _observation(seed: int, **changes) -> dict:
    space = observation_space()
    space.seed(seed)
    obs = space.sample()
    obs["fallen"] = 0
    obs["motion"] = len(Motion) - 1  # idle
    obs["game"]["state"] = int(GameState.PLAYING)
    obs["game"]["player"] = 1
    obs.update(changes)
    return obs


@pytest.mark.parametrize("name, method", [("team", "particle"), ("team-thesis", "thesis"),
                                          ("team-odometry", "odometry"), ("team-hybrid", "hybrid")])
def test_variants_by_name(name: str, method: str) -> None:
    agent = make_policy(name)
    assert isinstance(agent, TeamAgent) and agent.method == method
    assert make_policy("team-blind").avoid_obstacles is False


def test_random_observations_black_images_and_no_camera_never_break_it() -> None:
    agent = TeamAgent()
    agent.reset("home_1", 3)
    black = np.zeros((120, 160, 3), np.uint8)
    for seed in range(30):
        changes = {}
        if seed % 3 == 1:
            changes = {"image": black, "camera": int(CameraChoice.TOP)}
        elif seed % 3 == 2:
            changes = {"camera": int(CameraChoice.OFF)}
        action = agent.act(_observation(seed, **changes))
        assert set(action) >= {"motion", "head", "camera"}
        assert all(math.isfinite(v) for v in agent.pose_estimate())


@pytest.mark.parametrize("head_yaw, forgets", [(0.0, True), (1.5, False)])
def test_a_believed_ball_that_frames_in_clear_view_do_not_show_is_forgotten(head_yaw: float, forgets: bool) -> None:
    agent = TeamAgent()
    agent.reset("home_1", 3)
    black = np.zeros((120, 160, 3), np.uint8)
    obs = _observation(0, image=black, camera=int(CameraChoice.TOP), head=(head_yaw, 0.49),
                       sonar=np.full(4, 2.5, np.float32), gyro=np.zeros(3, np.float32))
    agent.act(obs)
    for _ in range(25):  # a ball lying 0.9 m ahead, seen for a second
        agent.world.ball.predict(0.04, Displacement(0.0, 0.0, 0.0))
        agent.world.ball.measure(0.9, 0.0)
    for _ in range(12):  # six frames, none with the ball
        agent.act(obs)
    assert agent.world.ball.known is not forgets
    assert agent.world.perception.absence.forgotten == int(forgets)


@pytest.mark.render
def test_bad_radio_from_a_teammate_is_ignored_and_counted() -> None:
    starts = (("home_1", Pose2D(-1.0, 0.0, 0.0)), ("home_2", Pose2D(-1.0, 1.0, 0.0)))
    config = MatchConfig(free_play=FreePlay(starts), initial_camera=CameraChoice.OFF)
    agent, fuzzer = TeamAgent(), RadioFuzzer()
    summary = run_match(config, {"home_1": agent, "home_2": fuzzer}, seed=1, progress=False, max_steps=60)
    assert summary.faults["total"] == 0
    ignored = agent.world.listener.decode_stats.ignored
    assert agent.world.listener.decode_stats.decoded == 0 and sum(ignored.values()) >= 10
    assert {"unknown version", "wrong length"} <= set(ignored)


@pytest.mark.parametrize("defended, theta", [("blue", math.pi), ("yellow", 0.0)])
def test_never_kicks_toward_its_own_goal(defended: str, theta: float) -> None:
    agent = TeamAgent()
    agent.reset("home_2", 0)
    attack = 1.0 if defended == "blue" else -1.0
    pose = Pose2D(-1.0 * attack, 0.0, theta)  # in its own half, facing its own goal
    ball = BallEstimate(0.15, 0.04, 0.0, 0.0, 0.02, 0.0)  # right in front of a foot
    motion, _, _ = _strike(agent, pose, ball, None, attack, (0.0, 0.0))
    assert not motion.is_kick
    facing = Pose2D(pose.x, pose.y, math.remainder(theta + math.pi, math.tau))
    motion, _, _ = _strike(agent, facing, ball, None, attack, (0.0, 0.0))
    assert motion.is_kick


def test_no_kick_out_over_the_side_line() -> None:
    agent = TeamAgent()
    agent.reset("home_2", 0)
    ball = BallEstimate(0.15, 0.04, 0.0, 0.0, 0.02, 0.0)
    near_line = Pose2D(0.0, 1.8, 0.03)  # the goal is 33 degrees to the right; this heading leaves the field
    motion, _, _ = _strike(agent, near_line, ball, None, 1.0, (0.0, 0.0))
    assert not motion.is_kick
    inward = Pose2D(0.0, 1.8, -0.55)  # toward the goal's centre
    motion, _, _ = _strike(agent, inward, ball, None, 1.0, (0.0, 0.0))
    assert motion.is_kick


@pytest.mark.parametrize("x, theta, kicks", [
    (1.0, 0.0, True),  # 2 m out, straight at the goal
    (1.0, 0.45, False),  # 2 m out, the kick's line passes 0.9 m left of the centre: beside the post
    (-2.0, 0.45, True),  # 5 m out: moving the ball on within 35 degrees is enough
    (-2.0, 0.7, False),
])
def test_in_shooting_range_it_kicks_only_between_the_posts(x: float, theta: float, kicks: bool) -> None:
    agent = TeamAgent()
    agent.reset("home_2", 0)
    ball = BallEstimate(0.15, 0.04, 0.0, 0.0, 0.02, 0.0)
    motion, _, _ = _strike(agent, Pose2D(x, 0.0, theta), ball, None, 1.0, (0.0, 0.0))
    assert motion.is_kick is kicks


def test_it_shoots_past_a_goalkeeper_it_saw_not_at_it() -> None:
    from agents.behavior.tactics.shot_window import shot_window
    from agents.vision.robots import RobotKind, RobotPercept
    from world.teams import TeamColor

    def strike(theta: float, keeper_seen: bool = True) -> Motion:
        """At (1, 0) facing ``theta``, the ball at its left foot, the goalkeeper seen at (2.85, 0)."""
        agent = TeamAgent()
        agent.reset("home_2", 0)
        if keeper_seen:
            agent.world.obstacles.see([RobotPercept(-theta, 1.85, TeamColor.RED, RobotKind.OPPONENT, (0, 0, 1, 1),
                                              (0.0, 0.0), 1)])
        ball = BallEstimate(0.15, 0.04, 0.0, 0.0, 0.02, 0.0)
        return _strike(agent, Pose2D(1.0, 0.0, theta), ball, None, 1.0, (0.0, 0.0))[0]

    assert strike(0.0, keeper_seen=False).is_kick
    assert not strike(0.0).is_kick  # straight at the goalkeeper
    window = shot_window((1.15, 0.04), FIELD.half_length, [(2.85, 0.0)])
    assert abs(window.direction_rad) > math.radians(5.0)
    assert strike(window.direction_rad).is_kick  # past it


def test_lining_up_a_shot_it_looks_ahead_with_the_top_camera_every_few_frames() -> None:
    from agents.team.agent import CAMERA_EVERY_STEPS

    agent = TeamAgent()
    agent.reset("home_2", 0)
    ball = BallEstimate(0.15, 0.04, 0.0, 0.0, 0.02, 0.0)
    cameras = []
    for step in range(CAMERA_EVERY_STEPS * P.head.shot_top_frame_every * 2):
        agent.world.step = step
        agent.behavior.head.camera = CameraPosition.BOTTOM
        _strike(agent, Pose2D(1.0, 0.0, 0.6), ball, None, 1.0, (0.0, 0.0))  # in range, not yet aligned
        assert agent.behavior.striker.lining_up
        if step % CAMERA_EVERY_STEPS == 0:
            cameras.append(agent._frame_camera(_output(agent, agent.behavior.striker.lining_up)))
    assert cameras.count(CameraPosition.TOP) == 2 and cameras.count(CameraPosition.BOTTOM) == 4
    assert agent._frame_camera(_output(agent, False)) is CameraPosition.BOTTOM  # no longer lining up: the head's


def test_the_penalty_kicker_looks_at_the_goal_while_the_kick_is_set() -> None:
    agent = TeamAgent()
    agent.reset("home_1", 0)
    obs = _observation(3, image=np.zeros((120, 160, 3), np.uint8), gyro=np.zeros(3, np.float32))
    obs["game"].update(state=int(GameState.SET), secondary=1, kickoff=0, defended_goal=0, seconds_since_drop_in=1e9)
    actions = [agent.act(obs) for _ in range(4)]
    assert agent.world.locator.pose == pytest.approx(Pose2D(FIELD.penalty_mark_x - 0.22, 0.0, 0.0))  # behind the ball
    stand = make_action(Motion.STAND)["motion"]
    assert all(a["motion"] == stand and abs(float(a["head"][0])) < 0.05 for a in actions)  # the goal straight ahead
    assert [a["camera"] for a in actions if a["camera"] != int(CameraChoice.OFF)] == [int(CameraChoice.TOP)] * 2


def _keeper_observation(step: int, teammate_talks: bool) -> dict:
    """A PLAYING observation of ``home_0`` with a black image, and, every fifth step when
    ``teammate_talks``, player 1's team message."""
    obs = _observation(0, image=np.zeros_like(observation_space()["image"].sample()))
    obs["game"]["player"] = 0
    obs["game"]["secondary"] = int(SecondaryState.NORMAL)
    radio = obs["radio"]
    radio["count"] = 0
    if teammate_talks and step % 5 == 0:
        data = TeamMessage(1, step, (-1.0, 0.0, 0.0), ball_xy=(0.0, 0.0), time_to_ball_s=5.0).encode()
        radio["count"], radio["sender"][0], radio["length"][0] = 1, 1, len(data)
        radio["data"][0, : len(data)] = np.frombuffer(data, dtype=np.uint8)
    return obs


@pytest.mark.parametrize("teammate_talks, role_at_the_end", [(False, Role.STRIKER), (True, Role.GOALKEEPER)])
def test_a_goalkeeper_that_hears_no_teammate_plays_the_field(teammate_talks: bool, role_at_the_end: Role) -> None:
    agent = TeamAgent()
    agent.reset("home_0", 0)
    roles = []
    for step in range(int(LONE_SILENCE_S / 0.04) + 25):
        agent.act(_keeper_observation(step, teammate_talks))
        roles.append(agent.behavior.role)
    assert roles[int(LONE_SILENCE_S / 0.04) - 10] is Role.GOALKEEPER  # silent, but not for long yet
    assert roles[-1] is role_at_the_end


@pytest.mark.render
def test_a_team_of_one_goes_for_the_ball(tmp_path) -> None:
    """A lone team agent is its team's player 0; it plays the ball, not only its goal (before, in a
    1 v 1 match neither robot ever touched the ball, and here it walked back to its goal)."""
    starts = (("home_0", Pose2D(-1.0, 0.0, 0.0)),)
    config = MatchConfig(free_play=FreePlay(starts, ball_xy=(-0.2, 0.0)), initial_camera=CameraChoice.OFF)
    run_match(config, {"home_0": TeamAgent()}, seed=3, out_dir=tmp_path, progress=False, max_steps=500)
    ball = np.load(tmp_path / "match_log.npz")["ball"]
    assert ball[-1, 0] > 1.0, ball[-1]  # kicked toward the goal it attacks (it went in, at 3.4 m)


@pytest.mark.render
def test_its_estimates_are_in_the_match_log(tmp_path) -> None:
    starts = (("home_1", Pose2D(-1.0, 0.0, 0.0)),)
    config = MatchConfig(free_play=FreePlay(starts))
    run_match(config, {"home_1": TeamAgent()}, seed=2, out_dir=tmp_path, progress=False, max_steps=50)
    log = np.load(tmp_path / "match_log.npz")
    assert log["estimates"].shape == (51, 1, 3)
    assert np.isfinite(log["estimates"][1:]).all()  # from the first action on


def _actions_played(privileged: bool, steps: int = 150) -> list[str]:
    from match import parallel_env
    from match.referee import RefereeConfig

    quick = RefereeConfig(half_seconds=30.0, initial_seconds=0.2, ready_seconds=0.4, set_seconds=0.2, shootout=False)
    env = parallel_env(home_players=2, away_players=1, privileged=privileged, config=MatchConfig(referee=quick))
    try:
        observations, infos = env.reset(seed=7)
        assert bool(infos["home_0"]) is privileged  # the ground truth is there only when asked for
        agents = {a: TeamAgent() for a in env.possible_agents}
        for agent_id, agent in agents.items():
            agent.reset(agent_id, 11)
        played = []
        for _ in range(steps):
            actions = {a: agents[a].act(observations[a]) for a in env.agents}
            played.append(repr(sorted((a, repr(sorted(action.items()))) for a, action in actions.items())))
            observations, _, _, _, _ = env.step(actions)
        return played
    finally:
        env.close()


@pytest.mark.render
def test_the_same_match_with_and_without_privileged_infos_gives_the_same_actions() -> None:
    """Honesty: the agents decide from their observations only, so the ground truth in infos changes nothing."""
    assert _actions_played(privileged=True) == _actions_played(privileged=False)


@pytest.mark.render
def test_it_takes_penalties_in_the_shootout(tmp_path) -> None:
    """A 1-second half with no goals goes to the shoot-out: the team agent, placed on the penalty
    mark, knows where it is and scores against a goalkeeper that stands."""
    from scenarios.matches.play import Lineup, run_lineup_match

    summary = run_lineup_match(
        tmp_path, Lineup("team", "stand"), home=1, away=1, half_seconds=1.0, seed=2, progress=False,
        referee={"shootout_kicks": 2, "sudden_death": False, "ready_seconds": 1.0, "shootout_attempt_seconds": 15.0},
    )
    kicks = [e for e in map(json.loads, (tmp_path / "events.jsonl").read_text().splitlines())
             if e["kind"] == "shootout_kick"]
    home_kicks = [k for k in kicks if k["team"] == "home"]
    assert home_kicks and all(k["reason"] != "time" for k in home_kicks), kicks  # it always got its kick away
    assert summary.shootout is not None and summary.shootout["home"] >= 1, kicks


def test_the_striker_goes_behind_the_ball_and_round_it_on_its_own_side() -> None:
    from agents.behavior.skills import BEHIND_BALL_M, PASS_BALL_SIDE_M, behind_ball

    ball, goal = (1.0, 0.0), (3.0, 0.0)
    assert behind_ball(Pose2D(0.0, 0.1, 0.0), ball, goal) is None  # already coming from behind
    behind = behind_ball(Pose2D(0.5, -1.0, 1.57), ball, goal)  # 63 degrees off: go behind first
    assert (behind.x, behind.y, behind.theta) == pytest.approx((1.0 - BEHIND_BALL_M, 0.0, 0.0))
    level = behind_ball(Pose2D(1.0, -1.0, 1.57), ball, goal)  # level with the ball: past it on its side first
    assert (level.x, level.y) == pytest.approx((1.0 - BEHIND_BALL_M, -PASS_BALL_SIDE_M))
    assert behind_ball(level, ball, goal) == behind  # from there, straight to the spot behind the ball
    beyond = behind_ball(Pose2D(2.0, 0.3, math.pi), ball, goal)  # on the far side, a little left
    assert beyond.y == pytest.approx(PASS_BALL_SIDE_M) and beyond.x < ball[0]  # passes on its own (left) side
    assert behind_ball(Pose2D(2.0, 0.3, math.pi), (3.3, 0.0), goal) is None  # a ball out of the field


def _radio(*packets: tuple[int, bytes]) -> dict:
    """An inbox holding ``packets`` (sender player, data)."""
    from match.protocol import INBOX_CAPACITY, MAX_PACKET_BYTES

    sender, length = np.zeros(INBOX_CAPACITY, np.int8), np.zeros(INBOX_CAPACITY, np.int16)
    data = np.zeros((INBOX_CAPACITY, MAX_PACKET_BYTES), np.uint8)
    for i, (player, packet) in enumerate(packets):
        sender[i], length[i] = player, len(packet)
        data[i, : len(packet)] = np.frombuffer(packet, np.uint8)
    return {"count": len(packets), "sender": sender, "length": length, "data": data, "dropped": 0}


def test_after_a_throw_in_it_looks_for_the_ball_where_the_rule_put_it() -> None:
    """A teammate saw the ball leave over the side line at x = 1 m; the game-control data then says
    the own team put it out and the referee put it back: by the rule it lies on the throw-in line
    1 m back toward the own (blue, -x) goal, and the old sighting no longer counts."""
    from match.protocol import DropIn, throw_in_spot

    agent = TeamAgent()
    agent.reset("home_1", 3)
    quiet = {"camera": int(CameraChoice.OFF), "image": np.zeros((120, 160, 3), np.uint8), "gyro": np.zeros(3)}

    def step(sequence: int, drop_in_team: DropIn, since_s: float, packets=()) -> dict:
        obs = _observation(sequence, radio=_radio(*packets), **quiet)
        obs["game"].update(defended_goal=0, drop_in_team=int(drop_in_team), seconds_since_drop_in=np.float32(since_s))
        agent.act(obs)
        return agent.report()

    out = TeamMessage(player=2, sequence=1, pose=(0.5, 1.5, 0.0), ball_xy=(1.0, 2.3), ball_sigma_m=0.1, ball_age_s=0.5)
    report = step(0, DropIn.NONE, 1e5, [(2, out.encode())])
    assert report.team_ball_xy == pytest.approx((1.0, 2.3), abs=0.05)
    report = step(1, DropIn.OWN_TEAM, 0.3)
    assert report.team_ball_xy == pytest.approx(throw_in_spot(1.0, 2.3, False, GoalColor.BLUE), abs=0.05)
    assert report.team_ball_xy == pytest.approx((0.0, 1.6), abs=0.05)


def test_after_a_throw_in_the_spot_comes_from_where_the_ball_left_not_where_it_rolled_on_to() -> None:
    """A teammate saw the ball leave over the side line at x = 1.1 m and roll on beyond it to (2.5, 3.5);
    the own team put it out: the rule's spot is 1 m back from where it left, toward the own (blue, -x) goal,
    not from where it was last seen."""
    from match.protocol import DropIn

    agent = TeamAgent()
    agent.reset("home_1", 3)
    quiet = {"camera": int(CameraChoice.OFF), "image": np.zeros((120, 160, 3), np.uint8), "gyro": np.zeros(3)}

    def step(sequence: int, drop_in_team: DropIn, since_s: float, ball_xy=None) -> dict:
        packets = []
        if ball_xy is not None:
            seen = TeamMessage(player=2, sequence=sequence + 1, pose=(0.5, 1.5, 0.0), ball_xy=ball_xy,
                               ball_sigma_m=0.1, ball_age_s=0.5)
            packets = [(2, seen.encode())]
        obs = _observation(sequence, radio=_radio(*packets), **quiet)
        obs["game"].update(defended_goal=0, drop_in_team=int(drop_in_team), seconds_since_drop_in=np.float32(since_s))
        agent.act(obs)
        return agent.report()

    for k, ball_xy in enumerate([(1.0, 1.9), (1.1, 2.2), (1.8, 2.9), (2.5, 3.5)]):
        step(k, DropIn.NONE, 1e5, ball_xy)
    report = step(4, DropIn.OWN_TEAM, 0.3)
    assert report.team_ball_xy == pytest.approx((0.1, 1.6), abs=0.05)  # from (1.1, 2.0), not (2.5, 3.5)


def test_the_striker_level_with_the_ball_walks_on_behind_it() -> None:
    """A striker level with the ball and off to its side (found standing there for 70 s, dithering
    between two targets) walks on round it, and from its way round to the spot behind the ball."""
    from agents.behavior import skills

    ball, goal = (0.0, -1.6), (-3.0, 0.0)
    for pose in (Pose2D(0.33, -1.21, math.radians(149.0)), skills.behind_ball(Pose2D(0.33, -1.21, 2.6), ball, goal)):
        agent = TeamAgent()
        agent.reset("home_3", 0)
        rel = BallEstimate(*_to_robot(pose, ball), 0.0, 0.0, 0.05, 0.0)
        motion, walk, _ = _strike(agent, pose, rel, None, -1.0, (0.0, 0.0))
        assert motion is Motion.WALK and any(walk), pose
    assert skills.behind_ball(skills.behind_ball(Pose2D(0.33, -1.21, 2.6), ball, goal), ball, goal) == (
        skills.behind_point(ball, goal))


def test_a_near_ball_with_the_aim_behind_is_orbited_without_stepping_in_first() -> None:
    """Just beyond kicking distance with the goal behind it, the striker orbits the ball at once:
    walking in first and orbiting once there made it alternate between the two every step, which
    halved its turn (found near the side line, 6 s for half a turn)."""
    from agents.behavior import skills

    for distance in (skills.KICK_DISTANCE_M + 0.01, skills.ORBIT_WITHIN_M - 0.01):
        ball = BallEstimate(distance, 0.02, 0.0, 0.0, 0.05, 0.0)
        for error in (math.radians(120.0), -math.radians(120.0)):
            motion, (vx, vy, omega) = skills.chase(ball, error, foot_first=True)
            assert motion is Motion.WALK and math.copysign(1.0, omega) == math.copysign(1.0, error), (distance, error)
            assert vy * omega < 0.0  # side-steps round the ball, facing it
    far = BallEstimate(skills.ORBIT_WITHIN_M + 0.05, 0.0, 0.0, 0.0, 0.05, 0.0)
    assert skills.chase(far, math.radians(120.0))[1] == skills.approach(far)  # farther: walk in first


def _to_robot(pose: Pose2D, xy: tuple[float, float]) -> tuple[float, float]:
    dx, dy = xy[0] - pose.x, xy[1] - pose.y
    c, s = math.cos(pose.theta), math.sin(pose.theta)
    return c * dx + s * dy, -s * dx + c * dy


@pytest.mark.parametrize("attack", [1.0, -1.0])
def test_a_ball_in_front_of_its_own_goal_is_cleared_out_to_its_side(attack: float) -> None:
    from agents.behavior.tactics.aim import BEHIND_MIN_DEPTH_M, kick_aim
    from agents.behavior.skills import behind_point

    own_line = -attack * FIELD.half_length
    for depth in (0.05, 0.2, 0.4, 0.7):
        for y in (-1.2, -0.5, 0.0, 0.3, 1.0):
            ball = (own_line + attack * depth, y)
            aim = kick_aim(ball, attack, robot_y=-0.4)
            assert aim.clearing
            direction = (aim.x - ball[0], aim.y - ball[1])
            assert attack * direction[0] > 0.0  # never back toward its own line ...
            assert abs(direction[1]) > 0.0 and (y == 0.0 or direction[1] * y > 0.0)  # ... out to the ball's side
            if y == 0.0:
                assert direction[1] > 0.0  # the robot stands right of a centred ball: cleared to the left
            if depth >= 0.4:  # room behind the ball: the spot to kick it from lies in front of the line
                spot = behind_point(ball, aim.xy)
                assert attack * (spot.x - own_line) >= BEHIND_MIN_DEPTH_M - 1e-9
    assert not kick_aim((own_line + attack * 0.9, 0.0), attack, 0.0).clearing  # out of the goal mouth
    assert not kick_aim((own_line + attack * 0.3, 1.6), attack, 0.0).clearing  # beside it
    assert kick_aim((0.0, 0.5), attack, 0.0) == kick_aim((0.0, -0.5), attack, 0.0)  # elsewhere: at the goal


def test_a_clearing_goes_along_its_aim_never_toward_its_own_goal_and_is_pushed_near_the_line() -> None:
    from agents.behavior.skills import PUSH_MPS

    agent = TeamAgent()
    agent.reset("home_1", 0)
    ball = BallEstimate(0.15, 0.04, 0.0, 0.0, 0.02, 0.0)  # right in front of a foot
    facing_own_goal = Pose2D(-2.65, 0.2, math.pi * 0.9)
    motion, walk, _ = _strike(agent, facing_own_goal, ball, None, 1.0, (0.0, 0.0))
    assert not motion.is_kick and walk[0] < PUSH_MPS  # it goes round the ball
    toward_aim = Pose2D(-2.85, 0.2, math.radians(40.0))  # out to the left, away from the goal mouth
    motion, walk, _ = _strike(agent, toward_aim, ball, None, 1.0, (0.0, 0.0))
    assert motion is Motion.WALK and walk[0] == pytest.approx(PUSH_MPS)  # no kick there: a kick may go astray
    farther_out = Pose2D(-2.65, 0.2, math.radians(40.0))
    motion, _, _ = _strike(agent, farther_out, ball, None, 1.0, (0.0, 0.0))
    assert motion.is_kick
    in_the_field = Pose2D(-1.0, 0.2, 0.0)
    motion, _, _ = _strike(agent, in_the_field, ball, None, 1.0, (0.0, 0.0))
    assert motion.is_kick


@pytest.mark.parametrize("attack", [1.0, -1.0])
def test_a_ball_on_their_goal_line_is_pushed_in_past_the_post_or_back_out_in_front_of_the_goal(attack: float) -> None:
    """Found in a match: the ball on the goal line just inside a post, the striker 0.3 m from it
    facing the goal 12 degrees off its axis; aiming at the goal's centre (along the line) it
    circled the ball into an opponent standing at the post and stood there for 150 s. Now it
    walks the ball in from where it stands, and a ball beside the goal is pushed back out in
    front of it from beyond the end line."""
    from agents.behavior.tactics.aim import POST_CLEARANCE_M, kick_aim
    from agents.behavior.skills import PUSH_MPS, behind_point

    goal_x = attack * FIELD.half_length
    ball = (goal_x - attack * 0.06, -0.65)  # where it lay, in the frame where the robot attacks -x
    aim = kick_aim(ball, attack, robot_y=-0.8)
    assert aim.push and not aim.clearing and attack * (aim.x - goal_x) > 0.0 and aim.y == 0.0  # inside the goal
    theta = 2.93 if attack < 0 else math.pi - 2.93  # 12 degrees off the line's normal, toward the goal's axis
    c, s = math.cos(theta), math.sin(theta)
    at_foot = (0.14, 0.05)  # the ball before its left foot, within kicking distance
    pose = Pose2D(ball[0] - c * at_foot[0] + s * at_foot[1], ball[1] - s * at_foot[0] - c * at_foot[1], theta)
    agent = TeamAgent()
    agent.reset("away_1", 0)
    motion, walk, _ = _strike(agent, pose, BallEstimate(*_to_robot(pose, ball), 0.0, 0.0, 0.02, 0.0), None, attack,
                                    (0.0, 0.0))
    assert motion is Motion.WALK and walk[0] == pytest.approx(PUSH_MPS)  # walks it in ...
    y_at_line = ball[1] + math.tan(theta) * (goal_x - ball[0])
    assert abs(y_at_line) < FIELD.goal_post_y - POST_CLEARANCE_M  # ... past the post
    far = Pose2D(attack * 1.0, 0.0, theta)
    motion, walk, _ = _strike(agent, far, BallEstimate(*_to_robot(far, ball), 0.0, 0.0, 0.02, 0.0), None, attack,
                                    (0.0, 0.0))
    assert motion is Motion.WALK and any(walk)  # from afar it goes to the ball

    beside = (goal_x - attack * 0.05, -0.9)
    aim = kick_aim(beside, attack, robot_y=-1.2)
    assert aim.push and aim.clearing and abs(aim.x) < abs(goal_x) and aim.y == 0.0  # back out, toward the goal's axis
    spot = behind_point(beside, aim.xy)
    assert attack * (spot.x - goal_x) > 0.0  # the spot to push it from lies beyond the end line ...
    assert abs(spot.y) > FIELD.goal_post_y + FIELD.goal_post_diameter  # ... clear of the goal
    pose = Pose2D(beside[0] - math.cos(spot.theta) * 0.14 + math.sin(spot.theta) * 0.05,
                  beside[1] - math.sin(spot.theta) * 0.14 - math.cos(spot.theta) * 0.05, spot.theta)
    agent.world.perception.own_goal_ahead_s = agent.now_s  # its own goal, 6 m away, straight ahead: no danger to a push
    motion, walk, _ = _strike(agent, pose, BallEstimate(*_to_robot(pose, beside), 0.0, 0.0, 0.02, 0.0), None, attack,
                                    (0.0, 0.0))
    assert motion is Motion.WALK and walk[0] == pytest.approx(PUSH_MPS)


@pytest.mark.parametrize("attack", [1.0, -1.0])
@pytest.mark.parametrize("line_y", [1.6, -1.6])
@pytest.mark.parametrize("half", ["own", "theirs"])
def test_a_throw_in_first_touch_goes_neither_out_nor_back_in_its_own_half(attack: float, line_y: float,
                                                                         half: str) -> None:
    """Whichever way a robot would play a ball on the throw-in line, the first touch's aim turns at
    least 10 degrees off the near side line into the field, and in its own half never back toward
    its own goal; a way within those bounds is kept, one outside goes to the nearer bound."""
    from agents.behavior.tactics.aim import RESTART_BACK_RAD, RESTART_INTO_FIELD_RAD, RESTART_OFF_LINE_RAD, restart_aim

    ball = (attack * (-0.5 if half == "own" else 0.5), line_y)
    side = math.copysign(1.0, line_y)
    most = RESTART_INTO_FIELD_RAD if half == "own" else RESTART_BACK_RAD
    for heading in np.radians(np.arange(0.0, 360.0, 15.0)):
        aim = restart_aim(ball, heading, attack)
        forward, toward_line = attack * (aim.x - ball[0]), side * (aim.y - ball[1])
        way = math.atan2(toward_line, forward)
        assert -most - 1e-9 <= way <= -RESTART_OFF_LINE_RAD + 1e-9, math.degrees(heading)
        wanted = math.atan2(side * math.sin(heading), attack * math.cos(heading))
        if -most <= wanted <= -RESTART_OFF_LINE_RAD:
            assert way == pytest.approx(wanted)
        else:
            bounds = (-RESTART_OFF_LINE_RAD, -most)
            nearer = min(bounds, key=lambda bound: abs(math.remainder(wanted - bound, math.tau)))
            assert way == pytest.approx(nearer), math.degrees(heading)


@pytest.mark.parametrize("attack", [1.0, -1.0])
def test_a_throw_in_first_touch_keeps_the_edge_it_turned_to(attack: float) -> None:
    """A robot facing away from the middle of the allowed cone is about as near to both of its edges:
    turning toward one must not make the other the aim (a robot 0.5 m from a throw-in's ball once
    turned back and forth for 7 s). With the last aim held, the edge stays whichever way it faces
    outside the cone; without it, the tie flips the aim."""
    from agents.behavior.tactics.aim import restart_aim

    ball = (-attack * 2.0, 1.6)  # in the own half, by the own goal: the cone runs from 10 to 90 degrees into the field
    tie = math.atan2(math.sin(math.radians(130.0)), attack * math.cos(math.radians(130.0)))  # the cone's far middle

    def direction(aim) -> float:
        return math.atan2(aim.y - ball[1], aim.x - ball[0])

    left, right = restart_aim(ball, tie + 0.05, attack), restart_aim(ball, tie - 0.05, attack)
    assert abs(math.remainder(direction(left) - direction(right), math.tau)) > math.radians(60.0)
    for first in (left, right):
        held = direction(first)
        for offset in np.radians(np.arange(-60.0, 61.0, 5.0)):
            aim = restart_aim(ball, tie + offset, attack, held)
            assert aim.xy == pytest.approx(first.xy), math.degrees(offset)


def test_a_fresh_throw_in_is_touched_the_quick_way_never_toward_its_own_goal_in_its_own_half() -> None:
    """Just after a throw-in, a striker at the ball facing along the side line toward the opponent half
    (the goal far off to the side) plays it at once, and a second later plays on as in open play
    (pushing on drifted the ball out); facing the line, or its own goal in its own half, it turns
    round the ball first; in the opponent half it may push it back along the line; ten seconds
    later the same striker at the same ball plays as in open play."""
    from agents.team.agent import DT_S

    ball_xy = (0.5, 1.6)
    ball = BallEstimate(0.15, 0.04, 0.0, 0.0, 0.02, 0.0)  # right in front of a foot
    along = Pose2D(ball_xy[0] - 0.15, ball_xy[1] - 0.04, 0.0)  # facing along the line, toward +x (attacked)

    def after_throw_in(seconds: float) -> TeamAgent:
        agent = TeamAgent()
        agent.reset("home_2", 0)
        agent.world.step = 1000
        agent.world.game.drop_in_at_s = agent.now_s - seconds
        return agent

    def strike(agent: TeamAgent, pose: Pose2D) -> tuple[Motion, tuple[float, float, float]]:
        motion, walk, _ = _strike(agent, pose, ball, None, 1.0, (0.0, 0.0))
        return motion, walk

    agent = after_throw_in(1.0)
    motion, walk = strike(agent, along)
    assert motion.is_kick or (motion is Motion.WALK and walk[0] > 0.0 and walk[2] == 0.0)  # played forward at once
    agent.world.step += round(P.throw_in.quick_push_s / DT_S) - 1
    assert strike(agent, along) == (motion, walk)  # still its first touch
    agent.world.step += 1
    motion, walk = strike(agent, along)
    assert not motion.is_kick and walk[2] != 0.0  # then open play: it turns round the ball to face the goal
    motion, walk = strike(after_throw_in(P.throw_in.quick_touch_s + 1.0), along)
    assert not motion.is_kick and walk[2] != 0.0  # open play
    motion, walk = strike(after_throw_in(1.0), Pose2D(along.x, along.y, math.radians(100.0)))
    assert not motion.is_kick and walk[2] != 0.0  # facing the side line: round the ball, never through it
    own_half = Pose2D(-along.x, along.y, math.pi)  # facing its own goal, in its own half
    agent = after_throw_in(1.0)
    motion, walk, _ = _strike(agent, own_half, ball, None, 1.0, (0.0, 0.0))
    assert not motion.is_kick and walk[2] != 0.0  # round the ball
    agent = after_throw_in(1.0)  # in the opponent half a push back along the line (10 degrees into the field)
    motion, walk = strike(agent, Pose2D(along.x, along.y, math.pi + math.radians(10.0)))
    assert motion is Motion.WALK and walk[0] > 0.0 and walk[2] == 0.0


def test_a_striker_beside_a_throw_in_s_ball_steps_to_it_without_turning_to_it() -> None:
    """The ball put on the throw-in line 0.3 m to the left of a striker that faces along the line into
    the field: it steps back and left to put the ball before its left foot, facing the way it faces
    (once it turned to the ball and orbited back, 6 s), then touches it."""
    from agents.behavior import skills

    ball_xy = (0.5, 1.6)
    pose = Pose2D(0.48, 1.3, math.radians(-20.0))  # facing forward (attack +x), 20 degrees into the field
    agent = TeamAgent()
    agent.reset("home_2", 0)
    agent.world.step = 1000
    agent.world.game.drop_in_at_s = agent.now_s - 1.0
    ball = BallEstimate(*_to_robot(pose, ball_xy), 0.0, 0.0, 0.02, 0.0)
    assert ball.bearing_rad > math.radians(60.0)
    motion, (vx, vy, omega), _ = _strike(agent, pose, ball, None, 1.0, (0.0, 0.0))
    assert motion is Motion.WALK and vx < 0.0 and vy > 0.0 and omega == pytest.approx(0.0)
    at_foot = Pose2D(ball_xy[0] - 0.14 * math.cos(pose.theta) + 0.05 * math.sin(pose.theta),
                     ball_xy[1] - 0.14 * math.sin(pose.theta) - 0.05 * math.cos(pose.theta), pose.theta)
    ball = BallEstimate(*_to_robot(at_foot, ball_xy), 0.0, 0.0, 0.02, 0.0)
    assert skills.at_kick_spot(ball)
    motion, walk, _ = _strike(agent, at_foot, ball, None, 1.0, (0.0, 0.0))
    assert motion.is_kick or (motion is Motion.WALK and walk == pytest.approx(skills.push(ball)))


def test_a_throw_in_s_ball_is_walked_round_to_the_spot_behind_it_not_orbited() -> None:
    """0.36 m from a throw-in's ball in its own half, on its field side toward the opponent goal, coming
    at it obliquely and facing away from the line (no tap along the line): for the first touch the
    striker walks round the ball to the spot behind it (orbiting it from 0.45 m on was slower in the
    throw-in drill); ten seconds later, in open play, it orbits the ball as before."""
    from agents.behavior import skills
    from agents.behavior.tactics.aim import restart_aim

    ball_xy, attack = (-0.5, 1.6), 1.0
    pose = Pose2D(-0.2, 1.4, math.radians(150.0))
    ball = BallEstimate(*_to_robot(pose, ball_xy), 0.0, 0.0, 0.02, 0.0)

    def strike(seconds_since_drop_in: float) -> tuple[float, float, float]:
        agent = TeamAgent()
        agent.reset("home_2", 0)
        agent.world.step = 1000
        agent.world.game.drop_in_at_s = agent.now_s - seconds_since_drop_in
        motion, walk, _ = _strike(agent, pose, ball, None, attack, (0.0, 0.0))
        assert motion is Motion.WALK
        return walk

    aim = restart_aim(ball_xy, pose.theta, attack)
    waypoint = skills.behind_ball(pose, ball_xy, aim.xy, P.throw_in.quick_go_behind_beyond_m)
    assert waypoint is not None and skills.behind_ball(pose, ball_xy, aim.xy) is None
    assert strike(1.0) == skills.walk_to(pose, waypoint)[1]
    assert strike(P.throw_in.quick_touch_s + 1.0) != skills.walk_to(pose, waypoint)[1]


def test_a_striker_on_the_opponent_side_of_a_throw_in_s_ball_plays_it_back_along_the_line() -> None:
    """The ball put on the throw-in line in the opponent half, the striker 0.85 m from it on the side
    of the opponent goal: it comes at the ball from where it stands and plays it back along the line
    (it once walked round the ball and orbited it for 13 s); in its own half it goes round the ball."""
    from agents.behavior.tactics.aim import restart_aim
    from agents.behavior.skills import behind_ball, behind_point

    ball, robot, attack = (-2.0, -1.6), Pose2D(-2.6, -1.0, math.radians(-45.0)), -1.0
    aim = restart_aim(ball, math.atan2(ball[1] - robot.y, ball[0] - robot.x), attack)
    assert attack * (aim.x - ball[0]) < 0.0 and aim.y > ball[1]  # back along the line, into the field
    assert behind_ball(robot, ball, aim.xy) == behind_point(ball, aim.xy)  # straight to the spot behind it
    assert math.hypot(behind_point(ball, aim.xy).x - robot.x, behind_point(ball, aim.xy).y - robot.y) < 0.75
    own_half, coming = (2.0, -1.6), (0.6, -0.6)  # the same way, in its own half: never back there
    aim = restart_aim(own_half, math.atan2(coming[1], coming[0]), attack)
    assert attack * (aim.x - own_half[0]) > -1e-9


def test_a_striker_late_to_a_throw_in_walks_on_through_the_ball_along_the_touch_aim() -> None:
    """Coming at a throw-in's ball along the first touch's aim, 0.25 m from it: five seconds after the
    throw-in the striker walks on through the ball at full speed; a second after it, it slows down and
    side-steps the ball to a foot for a kick, as in open play. Facing the side line instead, it never
    pushes the ball out: it steps to the ball's side, for a tap along the line."""
    from agents.behavior.skills import PUSH_MPS

    ball_xy, way = (0.5, 1.6), math.radians(-30.0)  # 30 degrees into the field from the side line at +y
    pose = Pose2D(ball_xy[0] - 0.25 * math.cos(way), ball_xy[1] - 0.25 * math.sin(way), way)

    def strike(after_s: float, robot: Pose2D) -> tuple[Motion, tuple[float, float, float]]:
        agent = TeamAgent()
        agent.reset("home_2", 0)
        agent.world.step = 1000
        agent.world.game.drop_in_at_s = agent.now_s - after_s
        ball = BallEstimate(*_to_robot(robot, ball_xy), 0.0, 0.0, 0.02, 0.0)
        motion, walk, _ = _strike(agent, robot, ball, None, 1.0, (0.0, 0.0))
        return motion, walk

    motion, walk = strike(P.throw_in.late_touch_after_s + 0.5, pose)
    assert motion is Motion.WALK and walk == pytest.approx((PUSH_MPS, 0.0, 0.0), abs=1e-6)
    motion, walk = strike(1.0, pose)
    assert motion is Motion.WALK and walk[0] < PUSH_MPS and walk[1] != 0.0
    toward_line = Pose2D(ball_xy[0], ball_xy[1] - 0.25, math.pi / 2)
    motion, walk = strike(P.throw_in.late_touch_after_s + 0.5, toward_line)
    assert motion is Motion.WALK and walk[0] < 0.1 and abs(walk[1]) > 0.05  # beside the ball (a tap), not through it


def test_a_ball_believed_just_out_for_longer_than_the_referee_waits_is_played() -> None:
    """A ball resting on the side line, believed 0.12 m beyond it: the striker waits on the throw-in
    line for the referee at first, but once the ball was believed out for longer than the referee
    takes to put it back, it plays it as a ball just inside (both teams' strikers once waited 70 s)."""
    from agents.behavior import skills
    from agents.team.agent import DT_S
    from agents.team.behavior.set_plays.ball_out import wait_pose

    pose = Pose2D(-0.32, -1.63, -0.16)
    believed, inside = (-0.04, -2.12), (-0.04, -2.0 + 0.05)

    def strike(ball_xy: tuple[float, float], out_for_s: float) -> tuple:
        agent = TeamAgent()
        agent.reset("away_2", 0)
        agent.world.step = 1000
        agent.world.team_ball.ball_in_s = agent.now_s - out_for_s
        restart = _expected_restart(agent, BallEstimate(*ball_xy, 0.0, 0.0, 0.05, 0.0), GoalColor.YELLOW)
        ball = BallEstimate(*_to_robot(pose, ball_xy), 0.0, 0.0, 0.05, 0.0)
        return _strike(agent, pose, ball, None, -1.0, (0.0, 0.0), restart)

    waiting = strike(believed, P.ball_out.out_wait_s - DT_S)
    # nobody of its team kicked: the other team put it out, and the referee puts it 1 m toward their goal
    spot = throw_in_spot(believed[0], believed[1], False, GoalColor.BLUE)
    assert waiting[:2] == skills.walk_to(pose, wait_pose(spot, -1.0, P.ball_out.throw_in_wait_back_m))
    playing = strike(believed, P.ball_out.out_wait_s + DT_S)
    assert playing == strike(inside, 0.0) and playing != waiting


def test_a_ball_going_out_is_waited_for_behind_the_spot_of_the_team_guessed_to_have_touched_it() -> None:
    """A ball rolling over the side line: the robot waits behind the rule's spot, 1 m toward the goal
    of the team it guesses touched the ball last: its own if it or a teammate (a fresh message) meant
    to kick it within OWN_TOUCH_MEMORY_S, else the other team's."""
    from agents.behavior import skills
    from agents.modelling.ball_out import OWN_TOUCH_MEMORY_S
    from agents.team.behavior.geometry import relative as _relative
    from agents.team.behavior.set_plays.ball_out import wait_pose
    from agents.radio import Intention

    rolling = BallEstimate(0.5, 1.5, 0.0, 1.0, 0.05, 0.0)  # rests 2 m on, the path crosses the line at x = 0.5
    pose = Pose2D(0.2, 0.8, 0.0)

    def restart(setup) -> tuple[float, float] | None:
        agent = TeamAgent()
        agent.reset("home_2", 0)
        agent.world.step = 1000
        agent.world.team_ball.ball_in_s = agent.now_s  # believed in the field until now
        setup(agent)
        _note_own_touch(agent)
        return _expected_restart(agent, rolling, GoalColor.BLUE)  # home defends blue: attacks +x

    def kicked(agent: TeamAgent) -> None:
        agent.behavior.intention = Intention.KICK

    def teammate_kicked(agent: TeamAgent) -> None:
        agent.world.listener.model.hear(TeamMessage(player=3, sequence=1, pose=(0.4, 1.4, 1.5),
                                                    intention=Intention.KICK,
                                    role=Role.STRIKER), agent.now_s)

    def kicked_long_ago(agent: TeamAgent) -> None:
        agent.world.restart.note_own_touch(agent.now_s - OWN_TOUCH_MEMORY_S - 0.1)

    line_y = FIELD.half_width - 0.4
    assert restart(kicked) == pytest.approx((-0.5, line_y))  # its own touch: 1 m toward its own goal
    assert restart(teammate_kicked) == pytest.approx((-0.5, line_y))
    assert restart(kicked_long_ago) == pytest.approx((1.5, line_y))  # the other team's
    assert restart(lambda agent: None) == pytest.approx((1.5, line_y))
    slow = BallEstimate(0.5, 1.5, 0.0, 0.2, 0.05, 0.0)  # rests inside: played, not waited for
    agent = TeamAgent()
    agent.reset("home_2", 0)
    assert _expected_restart(agent, slow, GoalColor.BLUE) is None
    assert _expected_restart(agent, rolling, GoalColor.BLUE) is not None
    agent.world.step = 1000  # the ball believed out (or no ball) since the start: the referee would have put it back
    assert _expected_restart(agent, rolling, GoalColor.BLUE) is None

    spot = restart(lambda agent: None)
    motion, walk, _ = _strike(agent, pose, _relative(pose, rolling), rolling, 1.0, (0.0, 0.0), spot)
    assert (motion, walk) == skills.walk_to(pose, wait_pose(spot, 1.0, P.ball_out.throw_in_wait_back_m))
    behind = wait_pose(spot, 1.0, P.ball_out.throw_in_wait_back_m)
    assert behind == Pose2D(1.2, line_y, 0.0)  # behind it, facing the opponent goal


def test_the_striker_of_a_ball_going_out_is_the_robot_nearest_the_spot_it_comes_back_on() -> None:
    """Roles go by the time to the spot: a robot near the spot takes the striker's role from a teammate
    near where the ball crosses the line, which would have kept it by the time to the ball."""
    from agents.behavior.tactics.roles import time_to_ball
    from agents.team.behavior.roles.assignment import assign

    rolling = BallEstimate(0.5, 1.5, 0.0, 1.0, 0.05, 0.0)
    near_crossing = Pose2D(0.5, 1.3, 1.5)

    def role(ball_xy: tuple[float, float]) -> Role:
        agent = TeamAgent()
        agent.reset("home_2", 0)
        agent.world.step = 1000
        crossing = (near_crossing.x, near_crossing.y, near_crossing.theta)
        agent.world.listener.model.hear(TeamMessage(player=3, sequence=1, pose=crossing,
                                    role=Role.STRIKER, time_to_ball_s=time_to_ball(near_crossing, ball_xy)),
                        agent.now_s)
        return assign(_world(agent, Pose2D(spot[0] - 0.3, spot[1], 0.0), None), ball_xy, agent.behavior.role)[0]

    foreseeing = TeamAgent()
    foreseeing.reset("home_2", 0)
    spot = _expected_restart(foreseeing, rolling, GoalColor.BLUE)  # nobody of its team kicked: 1 m toward theirs
    assert spot == pytest.approx((1.5, FIELD.half_width - 0.4))
    assert role(spot) is Role.STRIKER
    assert role((rolling.x, rolling.y)) is not Role.STRIKER


def test_a_robot_standing_up_tells_its_teammates_it_is_down_so_its_old_role_does_not_hold_the_ball() -> None:
    """Standing up, a striker's role and time to the ball are those of before its fall: its messages say it
    is down, as while it lay, so that a teammate does not leave the ball to it."""
    from agents.observation import MOTIONS
    from agents.radio import decode

    agent = TeamAgent()
    agent.reset("home_1", 0)
    agent.behavior.role, agent.behavior.time_to_ball_s = Role.STRIKER, 0.5
    packets = {}
    for motion in (Motion.STAND_UP_FROM_BACK, Motion.WALK):
        obs = _observation(3, motion=MOTIONS.index(motion), image=np.zeros((120, 160, 3), np.uint8))
        for _ in range(5):  # a packet every fifth step
            radio = agent.act(obs)["radio"]
        packets[motion] = decode(bytes(radio))
    assert packets[Motion.STAND_UP_FROM_BACK].fallen
    assert not packets[Motion.WALK].fallen


class _KickOffWatch:
    """Watches a refereed match from its kick-off (ground truth, evaluation only): how far the away
    (defending) team's players 2 and 3 have gone from where PLAYING found them, at the home team's
    first touch and :data:`AFTER_S` into PLAYING."""

    AFTER_S = 8.0

    def __init__(self) -> None:
        self.start: dict[str, Pose2D] = {}
        self.start_s = 0.0
        self.at_touch: dict[str, float] | None = None
        self.at_end: dict[str, float] = {}
        self.touch_s: float | None = None

    def _moved(self, match) -> dict[str, float]:
        return {robot: math.hypot(match.world.robot_pose(robot).x - pose.x, match.world.robot_pose(robot).y - pose.y)
                for robot, pose in self.start.items()}

    def decided(self, match, actions) -> None:
        if match.state is not GameState.PLAYING:
            return
        if not self.start:
            self.start = {robot: match.world.robot_pose(robot) for robot in ("away_2", "away_3")}
            self.start_s = match.world.time_s
        if self.at_touch is None and any(e.kind.value == "touch" for e in match.events):
            self.at_touch, self.touch_s = self._moved(match), match.world.time_s - self.start_s
        self.at_end = self._moved(match)

    def done(self, match) -> bool:
        return bool(self.start) and match.world.time_s - self.start_s >= self.AFTER_S


def test_at_the_other_team_s_kick_off_its_defender_and_supporter_hold_their_places_until_the_ball_is_played() -> None:
    """Walking up from their kick-off places at once, the defending team's defender and supporter crossed
    the lane of the kick past their striker a second later, and their legs turned the ball into their
    own goal: they now stand until the ball is played and a little after, then play on."""
    from match.referee import RefereeConfig

    config = MatchConfig(referee=RefereeConfig(initial_seconds=0.2, ready_seconds=0.4, set_seconds=0.2))
    watch = _KickOffWatch()
    run_match(config, {str(a): make_policy("team") for a in config.agents}, seed=3, progress=False, observer=watch)
    assert watch.at_touch is not None and watch.touch_s > 0.5, "the home striker kicks off after a moment"
    assert max(watch.at_touch.values()) < 0.02, watch.at_touch
    assert max(watch.at_end.values()) > 0.2, watch.at_end


@pytest.mark.parametrize("attack", [1.0, -1.0])
def test_a_striker_coming_at_a_throw_in_s_ball_from_the_field_taps_it_along_the_line(attack: float) -> None:
    """A striker that comes at a throw-in's ball from the field, about square to the side line, does not
    walk round it: it walks to the spot where it faces the line with the ball beside a foot, and side-steps
    into the ball, tapping it along the line, toward the opponent goal in its own half."""
    from agents.behavior import skills

    ball_xy = (-1.0 * attack, 1.6)  # in the robot's own half
    tap_to = attack  # along the line toward the opponent goal

    def strike(pose: Pose2D, ball_rel: tuple[float, float]) -> tuple[TeamAgent, tuple[float, float, float]]:
        agent = TeamAgent()
        agent.reset("home_2", 0)
        agent.world.step = 1000
        agent.world.game.drop_in_at_s = agent.now_s - 2.0
        motion, walk, _ = _strike(agent, pose, BallEstimate(*ball_rel, 0.0, 0.0, 0.02, 0.0), None, attack, (0.0, 0.0))
        assert motion is Motion.WALK
        return agent, walk

    far = Pose2D(ball_xy[0] - 0.2 * attack, 0.8, math.radians(90.0))
    _, walk = strike(far, _to_robot(far, ball_xy))
    spot = Pose2D(ball_xy[0] - tap_to * P.side_tap.side_m, ball_xy[1] - P.side_tap.forward_m, math.radians(90.0))
    assert walk == skills.walk_to(far, spot)[1]  # to the tap's spot, not round the ball

    facing_the_line = Pose2D(ball_xy[0] - tap_to * P.side_tap.side_m, ball_xy[1] - P.side_tap.forward_m,
                             math.radians(90.0))
    beside = _to_robot(facing_the_line, ball_xy)  # the ball ahead and to the side the tap goes
    assert beside == pytest.approx((P.side_tap.forward_m, -tap_to * P.side_tap.side_m))
    agent, walk = strike(facing_the_line, beside)
    assert walk[0] == pytest.approx(0.0, abs=0.02) and walk[1] == pytest.approx(-tap_to * skills.WALK_HIGH[1])
    c, s = math.cos(facing_the_line.theta), math.sin(facing_the_line.theta)
    field_step = (c * walk[0] - s * walk[1], s * walk[0] + c * walk[1])
    assert field_step[0] * attack > 0.0 and abs(field_step[1]) < 0.02  # along the line, toward the opponent goal


@pytest.mark.parametrize("pose, ball_xy", [(Pose2D(-1.5, 1.6, 0.0), (-1.1, 1.6)),
                                           (Pose2D(-1.7, 0.8, math.radians(135.0)), (-2.0, 1.6))])
def test_no_side_tap_along_the_line_or_from_past_a_ball_near_the_own_goal_line(
        pose: Pose2D, ball_xy: tuple[float, float]) -> None:
    """Beside the ball on the throw-in line, facing along it, the striker steps to the ball as before;
    on the field side but past the ball toward the opponent goal, in its own half with the ball nearer
    its own goal line than :data:`BACK_TAP_CLEAR_M` (here a corner's spot, 1 m from it), it does not tap
    (its place for the tap toward the opponent goal is on the ball's far side: a robot at a corner's spot
    once walked round the ball to it for 14 s)."""
    agent = TeamAgent()
    agent.reset("home_2", 0)
    agent.world.step = 1000
    agent.world.game.drop_in_at_s = agent.now_s - 2.0
    ball = BallEstimate(*_to_robot(pose, ball_xy), 0.0, 0.0, 0.02, 0.0)
    assert _side_tap(agent, pose, ball, ball_xy, 1.0) is None


def test_past_a_ball_far_from_its_own_goal_line_the_striker_taps_it_back_along_the_line() -> None:
    """On the field side of a throw-in's ball in its own half, past it toward the opponent goal, with the
    ball 1.9 m from its own goal line, the striker taps it back along the line from where it stands (a
    robot 1 m from such a ball once walked round it and touched it after 10 s)."""
    from agents.behavior import skills

    agent = TeamAgent()
    agent.reset("home_2", 0)
    agent.world.step = 1000
    agent.world.game.drop_in_at_s = agent.now_s - 2.0
    pose, ball_xy, attack = Pose2D(-0.8, 0.8, math.radians(135.0)), (-1.1, 1.6), 1.0
    assert FIELD.half_length + attack * ball_xy[0] >= P.side_tap.back_tap_clear_m
    ball = BallEstimate(*_to_robot(pose, ball_xy), 0.0, 0.0, 0.02, 0.0)
    walk = _side_tap(agent, pose, ball, ball_xy, attack)
    assert agent.behavior.striker.side_tap.along == -attack  # back toward its own goal, away from the robot
    spot = Pose2D(ball_xy[0] + P.side_tap.side_m, ball_xy[1] - P.side_tap.forward_m, math.pi / 2)
    assert walk == skills.walk_to(pose, spot)[1]  # to the tap's place on its own side of the ball


def test_a_side_tap_keeps_the_way_it_was_chosen_when_the_position_estimate_jumps() -> None:
    """The tap's way along the line is chosen once, with the tap: a jump of the position estimate that
    carries the believed ball over the centre line does not turn it round (a striker once side-stepped
    0.4 m past the ball, to the far side of its tap, while the other team came and touched first)."""
    from agents.behavior import skills

    agent = TeamAgent()
    agent.reset("home_2", 0)
    agent.world.step = 1000
    agent.world.game.drop_in_at_s = agent.now_s - 2.0
    pose = Pose2D(0.35, -1.2, math.radians(-100.0))
    ball_xy = (-0.1, -1.6)  # in the robot's own half, 0.6 m away
    ball = BallEstimate(*_to_robot(pose, ball_xy), 0.0, 0.0, 0.02, 0.0)
    jumped = Pose2D(pose.x + 0.2, pose.y, pose.theta)  # the same sighting puts the ball in the other half
    chosen = _side_tap(agent, jumped, ball, (ball_xy[0] + 0.2, ball_xy[1]), 1.0)
    assert chosen is not None  # in the other half the tap goes away from the robot: toward the own goal
    walk = _side_tap(agent, pose, ball, ball_xy, 1.0)
    spot = Pose2D(ball_xy[0] + P.side_tap.side_m, ball_xy[1] + P.side_tap.forward_m, -math.pi / 2)
    assert walk == skills.walk_to(pose, spot)[1]  # still the spot on the robot's side of the ball


def test_a_throw_in_s_ball_still_where_the_striker_first_saw_it_gets_the_quick_touch_after_ten_seconds() -> None:
    """Ten seconds after a throw-in the first touch is still played the quick way while the ball lies
    where the striker first saw it after the put-back (nobody touched it), up to twenty seconds; a ball
    moved from there is played as in open play."""
    from agents.behavior import skills
    from agents.behavior.tactics.aim import restart_aim
    from agents.team.agent import DT_S

    ball_xy, attack = (-0.5, 1.6), 1.0
    pose = Pose2D(-0.2, 1.4, math.radians(150.0))  # as above: the quick touch walks round to behind the ball
    waypoint = skills.behind_ball(pose, ball_xy, restart_aim(ball_xy, pose.theta, attack).xy,
                                  P.throw_in.quick_go_behind_beyond_m)
    assert waypoint is not None
    quick_walk = skills.walk_to(pose, waypoint)[1]

    def strike(seconds_since_drop_in: float, at_xy: tuple[float, float], saw_it: bool) -> tuple[float, float, float]:
        agent = TeamAgent()
        agent.reset("home_2", 0)
        agent.world.step = 1000
        agent.world.game.drop_in_at_s = agent.now_s - 1.0
        if saw_it:  # a second after the put-back, at the ball's spot
            assert _strike(agent, pose, BallEstimate(*_to_robot(pose, ball_xy), 0.0, 0.0, 0.02, 0.0), None, attack,
                                 (0.0, 0.0))[1] == quick_walk
        agent.world.step += round((seconds_since_drop_in - 1.0) / DT_S)
        ball = BallEstimate(*_to_robot(pose, at_xy), 0.0, 0.0, 0.02, 0.0)
        return _strike(agent, pose, ball, None, attack, (0.0, 0.0))[1]

    assert strike(P.throw_in.quick_touch_s + 1.0, ball_xy, saw_it=True) == quick_walk
    assert strike(P.throw_in.quick_touch_s + 1.0, ball_xy, saw_it=False) != quick_walk  # open play
    moved = (ball_xy[0] + 0.4, ball_xy[1])
    late, later = P.throw_in.quick_touch_s + 1.0, P.throw_in.quick_untouched_s + 1.0
    assert strike(late, moved, saw_it=True) == strike(late, moved, saw_it=False)
    assert strike(later, ball_xy, saw_it=True) == strike(later, ball_xy, saw_it=False)


@pytest.mark.parametrize("ball_xy, age_s, looks", [((0.5, 0.2), 1.0, True), ((0.9, 0.08), 1.2, True),
                                                   ((0.5, 0.2), 2.1, False),
                                                   ((1.5, 0.2), 1.0, False), ((1.5, 0.2), 0.3, True),
                                                   ((-0.42, -0.06), 1.0, False)])
def test_a_near_ball_unseen_for_a_second_is_looked_for_where_it_is_believed_a_far_one_is_searched_for(
        ball_xy: tuple[float, float], age_s: float, looks: bool) -> None:
    """A ball 0.54 m away, last seen a second ago, is looked at where the ball model believes it; a striker
    once swept its head instead, with the ball 0.5 m ahead, and turned away from its throw-in tap. Two seconds
    unseen, the ball is lost: the head searches. A ball believed 1.5 m away and unseen for a second is searched
    for (in the throw-in drill, staring at a ball believed at the kick-off spot behind robots, while it rolled
    away, cost 4-6 s); seen 0.3 s ago, it is tracked. A near ball behind the robot, out of the head's reach, is
    searched for too (a striker's head once stood at its yaw limit for seconds). The ball is the ball model's, as
    unsure as its age makes it: a look that asked for a sure belief (sigma 0.25 m, 0.75 s unseen) once swept past a
    ball 0.9 m ahead for 4.7 s."""
    from agents.modelling.ball_model import BallModel
    from agents.team.agent import DT_S
    from agents.team.behavior.head import Glance

    agent = TeamAgent()
    agent.reset("home_2", 0)
    agent.world.step = 1000
    pose = Pose2D(0.0, 0.0, 0.0)
    agent.behavior.head.glance.enter(Glance.NONE, math.inf)  # its pose is uncertain here: no glance at a goal
    model = BallModel()
    for _ in range(10):  # seen for 0.4 s, then unseen for age_s
        model.measure(math.hypot(*ball_xy), math.atan2(ball_xy[1], ball_xy[0]))
        model.predict(DT_S, Displacement())
    for _ in range(round(age_s / DT_S) - 1):
        model.predict(DT_S, Displacement())
    ball = model.relative()
    assert ball.age_s == pytest.approx(age_s, abs=DT_S) and ball.x == pytest.approx(ball_xy[0], abs=0.01)
    head = agent.behavior.head.control(_world(agent, pose, ball if age_s <= P.ball.lost_s else None), False)
    assert ((head.yaw_rad, head.pitch_rad) == pytest.approx(agent.behavior.head.look_at(ball))) is looks
