"""The user-side example examples/my_team.py: a role added by a file of one's own, played as a policy."""

from __future__ import annotations

import math

from agents.behavior import skills
from agents.modelling.ball_model import BallEstimate
from agents.modelling.obstacle_model import Obstacle, ObstacleKind
from agents.modelling.team_model import TeamModel
from agents.policies import make_policy
from agents.radio import ROLE_CODES, Intention, Role, TeamMessage, decode
from agents.team.behavior.requests import MotionRequest
from agents.team.modelling.snapshot import snapshot
from match.protocol import Pose2D


def test_the_example_team_is_a_policy_whose_third_field_player_marks_the_nearest_opponent() -> None:
    from examples.my_team import MARK_M, MARKER, Team

    agent = make_policy("examples.my_team:Team")
    assert isinstance(agent, Team) and ROLE_CODES[MARKER] == 16
    assert decode(TeamMessage(3, 1, None, role=MARKER).encode()).role == MARKER
    mates = TeamModel(3)
    for player, time_s in ((1, 2.0), (2, 1.0)):  # player 2 is faster: the striker; player 1 defends
        mates.hear(TeamMessage(player, 1, (0.0, 0.0, 0.0), time_to_ball_s=time_s), 0.0)
    opponent = Obstacle(1.0, 0.0, ObstacleKind.OPPONENT, 0.0)  # 1 m ahead of the robot at (0, 1): at (1, 1)
    world = snapshot(Pose2D(0.0, 1.0, 0.0), team_ball=BallEstimate(2.0, 0.0, 0.0, 0.0, 0.1, 0.0), player=3,
                     teammates=mates.teammates(0.0), obstacles=(opponent,))
    out = agent.behavior.decide(world)
    assert out.role == MARKER and out.motion.walk[0] > 0.0  # on toward the spot goal-side of it
    plain = make_policy("team").behavior.decide(world)
    assert plain.role == Role.SUPPORTER
    reach = math.hypot(4.0, 1.0)  # to its own goal's centre at (-3, 0)
    x, y = 1.0 - MARK_M * 4.0 / reach, 1.0 - MARK_M * 1.0 / reach
    target = Pose2D(x, y, math.atan2(1.0 - y, 1.0 - x))
    assert out.motion == MotionRequest.of(skills.walk_to(world.robot.pose_field, target), Intention.POSITION)
