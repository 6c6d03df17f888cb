"""Perception: a camera frame into the self-locator, the ball model and the obstacle model.

A frame is seen after the action of its step went out (:meth:`Perception.see`, from the agent's
``think``): one step (40 ms) of perception latency. Its landmarks update the self-locator, its ball
(the orange blob, its size checked against its distance) the ball model, a believed ball in clear
view that it misses the ball's absence (:mod:`agents.modelling.ball_absence`), the robots it shows
(by their waistbands) the obstacle model; a goal of the own colour near straight ahead is noted
(no kick goes off while it was seen lately).
"""

from __future__ import annotations

from agents.modelling.ball_absence import BallAbsence, in_clear_view
from agents.modelling.ball_model import BallEstimate, BallModel
from agents.modelling.obstacle_model import ObstacleModel
from agents.modelling.self_locator import SelfLocator
from agents.observation import Observation
from agents.team.params import TeamParams
from agents.team.report import landmarks_seen
from agents.vision.ball import ball_in_mask, plausible
from agents.vision.colors import ColorClass
from agents.vision.frame import CameraFrame
from agents.vision.percepts import LandmarkPercept
from agents.vision.pipeline import VisionPipeline
from agents.vision.robots import find_robots
from match.protocol import Pose2D


class Perception:
    """Sees frames into the models it is given; remembers the last frame's landmarks for reports."""

    def __init__(self, pipeline: VisionPipeline, locator: SelfLocator, ball: BallModel, obstacles: ObstacleModel,
                 params: TeamParams):
        self.pipeline, self.locator, self.ball, self.obstacles = pipeline, locator, ball, obstacles
        self.params = params
        self.absence = BallAbsence()
        self.own_goal_ahead_s = float("-inf")  # when a frame last showed the own goal near straight ahead
        # the last frame: its step, its percepts and the pose they were seen from; the landmark indices
        # are matched only when a report asks for them (evaluation, not play)
        self._seen: tuple[int, tuple[LandmarkPercept, ...], Pose2D | None] = (-1, (), None)
        self._seen_landmarks: tuple[int, frozenset[int]] = (-1, frozenset())

    def see(self, obs: Observation, step: int, now_s: float) -> None:
        """The frame of ``obs``, taken at ``step`` (``now_s`` on the own clock)."""
        frame = CameraFrame.from_observation(obs)
        result = self.pipeline.process(frame)
        self._seen = (step, result.percepts, self.locator.pose)
        self.locator.update(result.percepts)
        own_goal = obs.game.defended_goal
        for percept in result.percepts:
            if percept.goal is own_goal and abs(percept.bearing_rad) < self.params.kick.own_goal_ahead_rad:
                self.own_goal_ahead_s = now_s
        mask = result.segmented == int(ColorClass.ORANGE)
        ball = ball_in_mask(mask, frame.head_yaw_rad, frame.head_pitch_rad, frame.camera)
        seen = ball is not None and plausible(ball)
        if seen:
            self.ball.measure(ball.distance_m, ball.bearing_rad)
        believed = None if seen or obs.fallen else self._recent_ball()
        expected = believed is not None and in_clear_view(
            believed, frame.head_yaw_rad, frame.head_pitch_rad, frame.camera, self.obstacles.obstacles())
        if self.absence.frame(now_s, seen, expected):
            self.ball.reset()
        self.obstacles.see(find_robots(result.segmented, frame.head_yaw_rad, frame.head_pitch_rad, frame.camera,
                                       obs.game.team_color))

    def _recent_ball(self) -> BallEstimate | None:
        rel = self.ball.relative()
        return rel if rel is not None and rel.age_s <= self.params.ball.lost_s else None

    def landmarks_of_last_frame(self, step: int, within_steps: int) -> frozenset[int]:
        """The landmarks of the last frame if it is at most ``within_steps`` old at ``step`` (matched once
        per frame)."""
        seen_step, percepts, pose = self._seen
        if pose is None or not 0 <= step - seen_step <= within_steps:
            return frozenset()
        if self._seen_landmarks[0] != seen_step:
            self._seen_landmarks = (seen_step, landmarks_seen(percepts, pose))
        return self._seen_landmarks[1]
