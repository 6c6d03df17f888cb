"""The world modeller: the providers in their order, once per step, into a :class:`WorldModel`.

Order (each provider reads only the representations before it): odometry and posture (the models
moved by the last walk), the team (radio in), the game situation (and the resets it calls for: after
them the self-locator always holds a pose), the robot pose and the obstacles; while the robot
stands, the own ball and the team ball; in PLAYING, while no kick plays, the play status (a ball
going out, a kick-off played). Perception (:class:`~agents.team.modelling.perception.Perception`)
feeds the same models when a frame is seen, between steps.
"""

from __future__ import annotations

from agents.behavior import skills
from agents.modelling.ball_model import BallModel as BallFilter
from agents.modelling.obstacle_model import ObstacleModel
from agents.modelling.self_locator import SelfLocator
from agents.observation import Observation
from agents.radio import Intention
from agents.team.modelling.ball import own_ball
from agents.team.modelling.game import GameProvider
from agents.team.modelling.odometry import OdometryProvider
from agents.team.modelling.perception import Perception
from agents.team.modelling.representations import Obstacles, RobotPose, WorldModel
from agents.team.modelling.restart import RestartProvider
from agents.team.modelling.team import TeamListener
from agents.team.modelling.team_ball import TeamBallProvider
from agents.team.params import TeamParams
from agents.vision.pipeline import VisionPipeline
from match.protocol import GameState

DT_S = skills.CONTROL_STEP_S


class WorldModeller:
    """The models of one robot and the providers that read them out, step by step."""

    def __init__(self, player: int, method: str, seed: int, pipeline: VisionPipeline, params: TeamParams):
        self.player, self.params = player, params
        self.locator = SelfLocator(method, seed)
        self.ball = BallFilter()
        self.obstacles = ObstacleModel()
        self.perception = Perception(pipeline, self.locator, self.ball, self.obstacles, params)
        self.odometry = OdometryProvider(self.locator, self.ball, self.obstacles, params)
        self.listener = TeamListener(player)
        self.team_ball = TeamBallProvider(self.listener.model, params)
        self.game = GameProvider(player, self.locator, self.ball, self.team_ball)
        self.restart = RestartProvider(params)
        self.step = 0

    @property
    def now_s(self) -> float:
        return self.step * DT_S

    def see(self, obs: Observation) -> None:
        """A camera frame of the last step (its clock)."""
        self.perception.see(obs, self.step, self.now_s)

    def update(self, obs: Observation, last_walk: tuple[float, float, float], last_intention: Intention
               ) -> WorldModel:
        """The next step's snapshot; ``last_walk`` and ``last_intention``: what the behaviour asked last step."""
        self.step += 1
        now = self.now_s
        odometry, posture = self.odometry.update(obs, last_walk)
        team = self.listener.update(obs, now)
        game = self.game.update(obs, now, self.perception.own_goal_ahead_s)
        pose = self.locator.pose
        robot = RobotPose(pose, self.locator.sigma_m, self.locator.sigma_rad)
        obstacles = Obstacles(self.obstacles.obstacles(), pose)
        ball = team_ball = play = None
        if not posture.busy:
            ball = own_ball(self.ball, robot, self.params)
            team_ball = self.team_ball.update(ball, game, now, team)
            if game.state is GameState.PLAYING and not posture.kicking:
                play = self.restart.update(team_ball.field, self.team_ball.ball_in_s, game, team, last_intention, now)
        return WorldModel(self.player, self.step, now, robot, posture, odometry, game, team, obstacles, ball,
                          team_ball, play)
