"""The team agent's parts: the option framework, the providers fed recorded inputs, the role registry."""

from __future__ import annotations

import dataclasses
import enum
import math

import numpy as np
import pytest

from agents.behavior.tactics.roles import FIELD_ROLES
from agents.modelling.ball_model import BallEstimate, BallModel
from agents.modelling.self_locator import SelfLocator
from agents.modelling.team_model import TeamModel
from agents.observation import Observation
from agents.radio import Intention, Role, TeamMessage
from agents.team.agent import TeamAgent
from agents.team.behavior.framework import Option, deck
from agents.team.behavior.roles.assignment import assign, lone
from agents.team.behavior.roles.registry import REGISTRY, RoleSpec, register
from agents.team.behavior.root import Behavior
from agents.team.modelling.game import GameProvider
from agents.team.modelling.modeller import WorldModeller
from agents.team.modelling.representations import TeamState
from agents.team.modelling.restart import RestartProvider
from agents.team.modelling.snapshot import snapshot
from agents.team.modelling.team_ball import TeamBallProvider
from agents.team.params import TeamParams
from agents.vision.pipeline import VisionPipeline
from match.protocol import (
    CameraChoice,
    DropIn,
    GameState,
    GoalColor,
    KickOff,
    Motion,
    Pose2D,
    observation_space,
    throw_in_spot,
)

P = TeamParams.default()


class _Light(enum.Enum):
    OFF = "off"
    ON = "on"


def test_an_option_keeps_the_time_of_its_state_unless_entered_again() -> None:
    option = Option(_Light.OFF)
    assert option.is_in(_Light.OFF) and option.for_s(5.0) == math.inf
    option.goto(_Light.ON, 1.0)
    option.goto(_Light.ON, 2.0)  # staying: the time holds
    assert option.since_s == 1.0 and option.for_s(3.0) == 2.0
    option.enter(_Light.ON, 2.5)  # entered again: the time restarts
    assert option.since_s == 2.5
    option.reset()
    assert option.is_in(_Light.OFF) and option.since_s == -math.inf


def test_a_deck_plays_the_first_card_that_takes_the_situation_and_asks_no_later_one() -> None:
    asked = []

    class Card:
        def __init__(self, name: str, takes: bool):
            self.name, self.takes = name, takes

        def play(self, context: int) -> str | None:
            asked.append(self.name)
            return f"{self.name}:{context}" if self.takes else None

    assert deck([Card("a", False), Card("b", True), Card("c", True)], 7) == "b:7"
    assert asked == ["a", "b"]
    assert deck([Card("a", False)], 1) is None


def _observations(count: int, seed: int = 0) -> list[Observation]:
    """Recorded inputs: PLAYING observations of home_1 (random sensors, black frames, no radio)."""
    space = observation_space()
    space.seed(seed)
    recorded = []
    for k in range(count):
        obs = space.sample()
        obs.update(fallen=0, motion=len(Motion) - 1, image=np.zeros((120, 160, 3), np.uint8),
                   camera=int(CameraChoice.TOP))
        obs["game"].update(state=int(GameState.PLAYING), player=1, secondary=0, seconds_since_drop_in=1e5 + k)
        obs["radio"]["count"] = 0
        recorded.append(Observation.of(obs))
    return recorded


def test_the_modeller_gives_the_same_snapshots_for_the_same_recorded_inputs() -> None:
    recorded = _observations(30)
    runs = []
    for _ in range(2):
        modeller = WorldModeller(1, "particle", 0, VisionPipeline("exact"), P)
        worlds = []
        for k, obs in enumerate(recorded):
            if k % 2:
                modeller.see(obs)
            worlds.append(modeller.update(obs, (0.1, 0.0, 0.2), Intention.NONE))
        runs.append(worlds)
    assert runs[0] == runs[1]
    world = runs[0][-1]
    assert world.step == 30 and world.now_s == pytest.approx(1.2)
    assert world.robot.pose_field is not None and world.game.state is GameState.PLAYING
    with pytest.raises(dataclasses.FrozenInstanceError):
        world.step = 3  # type: ignore[misc]


def test_the_game_provider_puts_a_thrown_in_ball_where_the_rule_says_from_where_it_left() -> None:
    """A team ball believed crossing the side line at x = 1.1 m and rolling on: at the put-back the spot
    comes from where it left (the own team put it out: 1 m back toward the own goal)."""
    locator, ball = SelfLocator("odometry", 0), BallModel()
    team = TeamModel(1)
    team_ball = TeamBallProvider(team, P)
    game = GameProvider(1, locator, ball, team_ball)
    obs = _observations(1)[0]
    base = dataclasses.replace(obs.game, defended_goal=GoalColor.BLUE, drop_in_team=DropIn.NONE,
                               seconds_since_drop_in=1e5)
    situation = game.update(dataclasses.replace(obs, game=base), 0.04, -math.inf)
    for k, (x, y) in enumerate([(1.0, 1.9), (1.1, 2.2), (2.0, 3.0)]):
        own = snapshot(Pose2D(0.0, 0.0, 0.0)).ball
        own = dataclasses.replace(own, field=BallEstimate(x, y, 0.0, 0.0, 0.05, 0.0))
        team_ball.update(own, situation, 0.08 + 0.04 * k)
    put_back = dataclasses.replace(base, drop_in_team=DropIn.OWN_TEAM, seconds_since_drop_in=0.0)
    situation = game.update(dataclasses.replace(obs, game=put_back), 0.2, -math.inf)
    left = situation.drop_in_spot_field
    assert situation.drop_in_at_s == 0.2 and left is not None
    assert left == pytest.approx(throw_in_spot(1.1, 2.0, False, GoalColor.BLUE), abs=0.05)
    assert team_ball.left_at is None  # put back: no longer out


def test_the_restart_provider_guesses_who_touched_a_ball_going_out() -> None:
    rolling = BallEstimate(0.5, 1.5, 0.0, 1.0, 0.05, 0.0)  # crosses the side line at x = 0.5
    game = snapshot(Pose2D(0.0, 0.0, 0.0), attack=1.0, step=100).game
    nobody, mine = RestartProvider(P), RestartProvider(P)
    line_y = 2.0 - 0.4
    assert nobody.update(rolling, 4.0, game, TeamState((), 0.0), Intention.NONE, 4.0).restart_field == (
        pytest.approx((1.5, line_y)))  # the other team's: 1 m toward their goal
    assert mine.update(rolling, 4.0, game, TeamState((), 0.0), Intention.KICK, 4.0).restart_field == (
        pytest.approx((-0.5, line_y)))
    late = mine.update(rolling, 0.0, game, TeamState((), 0.0), Intention.NONE, 4.0)
    assert late.restart_field is None  # believed out longer than the referee waits: in play


def test_the_kick_off_is_played_once_per_state() -> None:
    provider = RestartProvider(P)
    game = snapshot(Pose2D(0.0, 0.0, 0.0), state_since_s=1.0).game
    far = BallEstimate(P.kickoff.played_m + 0.1, 0.0, 0.0, 0.0, 0.05, 0.0)
    assert provider.update(None, 2.0, game, TeamState((), 0.0), Intention.NONE, 2.0).kickoff_played_s == math.inf
    assert provider.update(far, 2.1, game, TeamState((), 0.0), Intention.NONE, 2.1).kickoff_played_s == 2.1
    assert provider.update(far, 2.2, game, TeamState((), 0.0), Intention.NONE, 2.2).kickoff_played_s == 2.1
    again = dataclasses.replace(game, state_since_s=5.0)
    assert provider.update(None, 5.1, again, TeamState((), 0.0), Intention.NONE, 5.1).kickoff_played_s == math.inf


def test_roles_are_a_registry_and_a_new_field_role_plays_without_editing_the_agent() -> None:
    assert {Role.GOALKEEPER, Role.STRIKER, Role.DEFENDER, Role.SUPPORTER} <= set(REGISTRY)
    with pytest.raises(ValueError, match="registered already"):
        register(RoleSpec(Role.DEFENDER, REGISTRY[Role.SUPPORTER].make))

    class Statue:
        def __init__(self, kit) -> None:
            self.kit = kit

        def play(self, world, situation):
            from agents.team.behavior.requests import MotionRequest

            return MotionRequest(Motion.STAND, intention=Intention.POSITION)

    spec = register(RoleSpec("statue", Statue, "stands"))
    try:
        behavior = Behavior(P, field_roles=("statue",))
        mates = TeamModel(2)
        mates.hear(TeamMessage(1, 1, (0.0, 0.0, 0.0), time_to_ball_s=1.0), 0.0)
        world = snapshot(Pose2D(-1.0, 0.0, 0.0), team_ball=BallEstimate(0.0, 0.0, 0.0, 0.0, 0.1, 0.0), player=2,
                         teammates=mates.teammates(0.0))
        assert assign(world, (0.0, 0.0), Role.NONE, ("statue",))[0] == "statue"
        assert behavior.decide(world).motion.intention is Intention.POSITION and behavior.role == "statue"
    finally:
        del REGISTRY[spec.name]
    assert FIELD_ROLES == (Role.DEFENDER, Role.SUPPORTER)


def test_the_behaviour_decides_from_a_snapshot_alone() -> None:
    """A striker 0.15 m behind the ball, facing the open goal: it kicks; the same in SET: it stands."""
    ball = BallEstimate(0.15, 0.04, 0.0, 0.0, 0.02, 0.0)
    behavior = Behavior(P)
    out = behavior.decide(snapshot(Pose2D(1.0, 0.0, 0.0), ball_torso=ball, player=1))
    assert out.motion.motion.is_kick and out.role == Role.STRIKER and out.intention is Intention.KICK
    out = Behavior(P).decide(snapshot(Pose2D(1.0, 0.0, 0.0), ball_torso=ball, state=GameState.SET,
                                      kickoff=KickOff.OPPONENT))
    assert out.motion.motion is Motion.STAND and out.intention is Intention.NONE


def test_a_team_agent_plays_another_parameter_set() -> None:
    slow = TeamAgent(params=P.replace(kick={"follow_kick_mps": 0.05}))
    assert slow.behavior.params.kick.follow_kick_mps == 0.05 and slow.world.params is slow.params


def test_the_team_and_scripted_policies_share_the_lone_goalkeeper_rule() -> None:
    from agents.behavior import skills
    from agents.behavior.policies import scripted

    assert skills.plays_alone(0, skills.LONE_SILENCE_S) and not skills.plays_alone(0, skills.LONE_SILENCE_S - 0.04)
    assert not skills.plays_alone(1, 60.0)  # field players play the field anyway
    assert scripted.LONE_SILENCE_STEPS * skills.CONTROL_STEP_S == skills.LONE_SILENCE_S
    world = snapshot(Pose2D(-2.8, 0.0, 0.0), player=0, silent_for_s=skills.LONE_SILENCE_S)
    assert lone(world) and not lone(dataclasses.replace(world, player=1))
