"""The team agent (policy ``team``) survives what a match does to it: a fall in the middle of a
kick, a kidnapping (the robot carried elsewhere while it plays) and the half-time swap of sides.

Each test plays a short simulation step by step, so an exception in the agent fails it. The
ground truth (world poses, the ball) is read only for the assertions, never handed to the agent.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import pybullet as pb
import pytest

from agents.observation import Observation
from agents.policies import make_policy
from agents.team.agent import TeamAgent
from match.free_play import FreePlay
from match.game import Match, MatchConfig
from match.protocol import GameState, GoalColor, Motion, Policy, Pose2D, Side, kickoff_pose, parse_action
from match.referee import RefereeConfig
from world.camera_profiles import DEFAULT_CAMERA_PROFILE
from world.config import WorldConfig

STEP_S = 0.04
ROBOT = "home_1"

# Kidnapping: how long the agent may take to be within LOST_M of the truth again, and for how
# long it must then stay there. Measured with the agent of this commit: see the test's docstring.
LOST_M = 0.5
RELOCALIZE_S = 8.0
HOLD_S = 1.0


def _error_m(estimate: tuple[float, float, float] | None, truth: Pose2D) -> float:
    return math.inf if estimate is None else math.hypot(estimate[0] - truth.x, estimate[1] - truth.y)


def _heading_error_rad(estimate: tuple[float, float, float], truth: Pose2D) -> float:
    return abs(math.remainder(estimate[2] - truth.theta, math.tau))


class Game:
    """A match played step by step by ``policies`` (agent id -> policy), reset with ``seed``."""

    def __init__(self, config: MatchConfig, policies: Mapping[str, Policy], seed: int) -> None:
        self.match = Match(config)
        self.policies = policies
        for agent, policy in policies.items():
            policy.reset(agent, seed)
        self.observations = self.match.reset(seed)
        self.actions: dict = {}

    @property
    def world(self):
        return self.match.world

    def observation(self, agent: str = ROBOT) -> Observation:
        return Observation.of(self.observations[agent])

    def decide(self) -> None:
        """Every policy acts on its observation (an exception fails the test)."""
        self.actions = {a: parse_action(a, p.act(self.observations[a])) for a, p in self.policies.items()}

    def play(self) -> None:
        self.observations = self.match.step(self.actions).observations

    def close(self) -> None:
        self.match.close()


def _free_play(start: Pose2D, seed: int, ball_xy: tuple[float, float] | None = None,
               camera_profile: str = DEFAULT_CAMERA_PROFILE) -> tuple[Game, TeamAgent]:
    agent = TeamAgent()
    free_play = FreePlay(((ROBOT, start),)) if ball_xy is None else FreePlay(((ROBOT, start),), ball_xy=ball_xy)
    config = MatchConfig(free_play=free_play, world=WorldConfig(camera_profile=camera_profile))
    return Game(config, {ROBOT: agent}, seed), agent


# --------------------------------------------------------------------------- a fall mid-kick


@pytest.mark.render
@pytest.mark.parametrize("push, within_s", [
    pytest.param("backwards", 8.0, id="pushed backwards"),
    pytest.param("forwards", 8.0, id="pushed forwards"),
    pytest.param("world +y", 12.0, id="pushed sideways, rolls onto its side"),
])
def test_knocked_over_mid_kick_it_stands_up_and_walks_again(push: str, within_s: float) -> None:
    """Pushed over while its observation says it is kicking, it gets up (4.5 s) and walks again.

    Measured: about 5 s from the push to walking again, pushed backwards or forwards; 9.3 s when it
    rolls onto its side, where the accelerometer does not tell front from back: the first
    stand-up leaves it down, and it tries the other one.
    """
    game, agent = _free_play(Pose2D(1.0, 0.0, 0.0), seed=0, ball_xy=(1.25, -0.05))
    try:
        pushed_s = None
        fell = walked = False
        while game.world.time_s < 20.0 or (pushed_s is not None and game.world.time_s - pushed_s <= within_s):
            obs = game.observation()
            game.decide()
            now = game.world.time_s
            if pushed_s is None and obs.motion is not None and obs.motion.is_kick and obs.motion_elapsed_s > 0.1:
                _shove(game, push)
                pushed_s = now
            if pushed_s is not None:
                fell = fell or game.world.robot_truth(ROBOT).fallen
                upright = not obs.fallen and not (obs.motion is not None and obs.motion.is_stand_up)
                if fell and upright and game.actions[ROBOT].motion is Motion.WALK:
                    walked = True
                    break
                if now - pushed_s > within_s:
                    break
            assert all(math.isfinite(v) for v in agent.pose_estimate())
            game.play()
        assert pushed_s is not None, "the agent never kicked: nothing to knock over"
        assert fell, "the push did not knock it over"
        assert walked, f"not walking again {within_s} s after the push (fallen: {game.world.robot_truth(ROBOT).fallen})"
        truth = game.world.robot_truth(ROBOT)
        assert not truth.fallen and truth.tilt_rad < math.radians(10.0)
    finally:
        game.close()


def _shove(game: Game, push: str) -> None:
    """A shove of 1.8 m/s at the torso, as a robot running into it would give."""
    heading = game.world.robot_pose(ROBOT).theta
    direction = {"backwards": heading + math.pi, "forwards": heading, "world +y": math.pi / 2}[push]
    velocity = (1.8 * math.cos(direction), 1.8 * math.sin(direction), 0.0)
    pb.resetBaseVelocity(game.world.body_id(ROBOT), velocity, (0.0, 0.0, 0.0), physicsClientId=game.world.client)


# --------------------------------------------------------------------------- kidnapping


FREE_PLAY_START = Pose2D(-1.0, 0.0, 0.0)  # home_1's kick-off pose by the game-control data of free play


@pytest.mark.render
@pytest.mark.parametrize(("carried_to", "seed"), [
    pytest.param(None, 1, id="to its mirror image through the centre spot"),
    pytest.param(Pose2D(1.5, -1.2, 2.0), 3, id="across the field"),
])
def test_kidnapped_while_playing_it_finds_itself_again(carried_to: Pose2D | None, seed: int) -> None:
    """Carried elsewhere during PLAYING (no fall, nothing told), its estimate is back within 0.5 m of
    the truth, and stays there for a second, within 8 s.

    It starts where it believes it starts (its kick-off pose), plays 4 s (it knows where it is:
    within 0.3 m), then is carried to its mirror image (-x, -y, theta + 180 degrees: the field
    looks the same but for the goal colours) or across the field.

    Played with the ``clean`` camera, so that what is checked is how the agent recovers, not how a
    blurred frame measures a post. Measured (12 kidnappings, seeds 0-3, to the mirror image, to
    (1.5, -1.2, 115 deg) and to (0.5, -1.0, 115 deg)): back within 0.5 m for good after 2.4 s,
    0.8-0.9 s and 1.2-1.4 s. Under the default ``robotstadium`` camera: 2.6-8.1 s, 4.9-12.7 s and
    1.2-1.3 s, and three of the four robots were 0.27-0.30 m off before they were carried (seed 1:
    a post measured 0.35 m too far in a frame blurred by a 1.5 rad/s head turn, believed with the
    other post and the goal centre).
    A far fix is believed when six fixes in a row agree on it; the first rejected one makes the
    robot doubt its pose and glance at a goal.
    """
    game, agent = _free_play(FREE_PLAY_START, seed, camera_profile="clean")
    try:
        while game.world.time_s < 4.0:
            game.decide()
            game.play()
        game.decide()
        truth = game.world.robot_pose(ROBOT)
        assert _error_m(agent.pose_estimate(), truth) < 0.3  # it knew where it was
        target = Pose2D(-truth.x, -truth.y, truth.theta + math.pi) if carried_to is None else carried_to
        game.world.place_robot(ROBOT, target)  # the kidnapping, after it decided
        game.play()
        kidnapped_s, held_since, error = game.world.time_s, None, math.inf
        while game.world.time_s - kidnapped_s <= RELOCALIZE_S + HOLD_S:
            game.decide()
            error = _error_m(agent.pose_estimate(), game.world.robot_pose(ROBOT))
            if error < LOST_M:
                held_since = game.world.time_s if held_since is None else held_since
                if game.world.time_s - held_since >= HOLD_S - 1e-9:
                    break
            else:
                held_since = None
            game.play()
        assert held_since is not None and game.world.time_s - held_since >= HOLD_S - 1e-9, (
            f"not back within {LOST_M} m for {HOLD_S} s in {RELOCALIZE_S} s: error {error:.2f} m at the end")
        assert held_since - kidnapped_s <= RELOCALIZE_S
    finally:
        game.close()


# --------------------------------------------------------------------------- the second half


@pytest.mark.render
def test_after_half_time_it_plays_in_the_new_frame_toward_the_other_goal() -> None:
    """The referee swaps sides at half-time: the agent's estimate follows (within 0.5 m and 20 degrees
    of the truth at the second kick-off), it stays at its new kick-off pose through READY, and its
    kick goes toward the goal it now attacks (the blue one for the home team)."""
    quick = RefereeConfig(half_seconds=10.0, initial_seconds=0.5, ready_seconds=4.0, set_seconds=0.5, shootout=False)
    config = MatchConfig(home_players=2, away_players=1, referee=quick)
    agent = TeamAgent()
    policies = {"home_0": make_policy("stand"), ROBOT: agent, "away_0": make_policy("stand")}
    game = Game(config, policies, seed=0)
    referee = game.match.referee
    try:
        kickoff_checked = False
        kicks: dict[int, list[tuple[float, Pose2D, float]]] = {1: [], 2: []}  # half -> (time, true pose, ball x)
        ball_after: dict[int, float] = {}  # half -> ball x 2 s after its first kick
        while not game.match.finished:
            obs = game.observation()
            game.decide()
            now, truth, estimate = game.world.time_s, game.world.robot_pose(ROBOT), agent.pose_estimate()
            if referee.half == 2:
                assert referee.defended_goal(Side.HOME) is GoalColor.YELLOW
                start = kickoff_pose(1, referee.kickoff is Side.HOME, GoalColor.YELLOW)
                ready_after_half_time = referee.state is GameState.READY and not kickoff_checked  # not after a goal
                if ready_after_half_time and obs.game.defended_goal is GoalColor.YELLOW:
                    assert math.hypot(truth.x - start.x, truth.y - start.y) < 0.3, f"left its kick-off pose: {truth}"
                    assert _error_m(estimate, start) < LOST_M
                if referee.state is GameState.PLAYING and not kickoff_checked:
                    kickoff_checked = True
                    assert _error_m(estimate, truth) < LOST_M and _heading_error_rad(estimate, truth) < math.radians(20)
            starts_kick = game.actions[ROBOT].motion.is_kick and not (obs.motion is not None and obs.motion.is_kick)
            if starts_kick and referee.state is GameState.PLAYING:
                kicks[referee.half].append((now, truth, game.world.ball().x))
            for half, made in kicks.items():
                if made and half not in ball_after and now >= made[0][0] + 2.0:
                    ball_after[half] = game.world.ball().x
            game.play()
        assert kickoff_checked
        assert kicks[1] and kicks[2], f"a kick in each half expected: {kicks}"
        (_, first_pose, _), (_, second_pose, ball_x) = kicks[1][0], kicks[2][0]
        assert math.cos(first_pose.theta) > 0.5  # toward the yellow goal (+x) in the first half ...
        assert math.cos(second_pose.theta) < -0.5  # ... toward the blue goal (-x) in the second
        assert ball_after[2] < ball_x - 0.1, f"the ball went from x = {ball_x:.2f} to {ball_after[2]:.2f} m"
        assert game.match.score["away"] == 0  # the away goalkeeper stands: an away goal would be an own goal
    finally:
        game.close()
