"""Scenes for the team agent's tests: a snapshot from an agent's own state, and its striker's play in it."""

from __future__ import annotations

from agents.behavior.tactics.aim import Aim
from agents.modelling.ball_model import BallEstimate
from agents.radio import Intention
from agents.team.agent import TeamAgent
from agents.team.behavior.requests import BehaviorOutput, MotionRequest
from agents.team.behavior.striker.context import StrikeContext
from agents.team.modelling.representations import TeamState, WorldModel
from agents.team.modelling.snapshot import snapshot
from match.protocol import GoalColor, Motion, Pose2D
from world.field import FIELD


def world(agent: TeamAgent, pose: Pose2D, ball_rel: BallEstimate | None, ball_field: BallEstimate | None = None,
          attack: float = 1.0, restart: tuple[float, float] | None = None) -> WorldModel:
    """The snapshot of ``agent`` at ``pose`` with these balls: its clock, its last throw-in, its sightings of
    its own goal, the obstacles and teammates it believes in."""
    now = agent.now_s
    return snapshot(pose, ball_torso=ball_rel, team_ball=ball_field, attack=attack, step=agent.world.step,
                    player=agent.player, drop_in_at_s=agent.world.game.drop_in_at_s,
                    own_goal_ahead_s=agent.world.perception.own_goal_ahead_s,
                    obstacles=agent.world.obstacles.obstacles(), restart=restart,
                    teammates=agent.world.listener.model.teammates(now),
                    silent_for_s=agent.world.listener.model.silent_for_s(now))


def strike(agent: TeamAgent, pose: Pose2D, ball_rel: BallEstimate | None, ball_field: BallEstimate | None,
           attack: float, head: tuple[float, float] = (0.0, 0.0), restart: tuple[float, float] | None = None
           ) -> tuple[Motion, tuple[float, float, float], tuple[float, float]]:
    """The striker's motion and walk in that scene (its intention kept as the agent's)."""
    scene = world(agent, pose, ball_rel, ball_field, attack, restart)
    behavior = agent.behavior
    request = behavior.striker.play(scene, behavior.following_kick(scene.now_s), behavior.head.searching_near_feet,
                                    restart)
    if request.intention is not None:
        behavior.intention = request.intention
    return request.motion, request.walk, head


def expected_restart(agent: TeamAgent, ball: BallEstimate, defended: GoalColor) -> tuple[float, float] | None:
    return agent.world.restart.expected_restart(ball, agent.world.team_ball.ball_in_s, defended, agent.now_s)


def note_own_touch(agent: TeamAgent) -> None:
    """The play status' own-touch memory after this step (the agent's last intention, its teammates)."""
    scene = world(agent, Pose2D(0.0, 0.0, 0.0), None)
    agent.world.restart.update(None, agent.world.team_ball.ball_in_s, scene.game,
                               TeamState(scene.team.teammates, 0.0), agent.behavior.intention, agent.now_s)


def side_tap(agent: TeamAgent, pose: Pose2D, ball_rel: BallEstimate, ball_xy: tuple[float, float],
             attack: float) -> tuple[float, float, float] | None:
    """The side tap's walk for a due throw-in first touch, or None."""
    scene = world(agent, pose, ball_rel, None, attack)
    aim = Aim(FIELD.half_length * attack, 0.0, False)
    context = StrikeContext(scene, pose, ball_rel, ball_xy, attack, aim.x, aim, aim, None, False, True, False, 0.0)
    request = agent.behavior.striker.side_tap.walk(context)
    return None if request is None else request.walk


def output(agent: TeamAgent, lining_up: bool) -> BehaviorOutput:
    """A step's requests with the head's camera, lining up a kick or not."""
    return BehaviorOutput(MotionRequest(Motion.STAND), agent.behavior.head.request(0.0, 0.0), lining_up,
                          agent.behavior.role, Intention.NONE, agent.behavior.time_to_ball_s)
