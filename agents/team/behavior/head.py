"""The head: track the ball, glance at a goal when the pose is uncertain, else search.

States (:class:`Look`): a near ball unseen for a moment is looked at where it is believed, until a
frame finds it or forgets it, if a frame would show it there (not behind a robot or the robot); a far
belief is often stale and hidden (a ball kicked away behind robots). After a kick, it looks ahead
where the ball rolled. Without its own ball it looks where the team believes it for part of every
search cycle; else it searches: a quick look near the feet, then wide sweeps (the bottom camera on
every other one). With an uncertain pose (``head.uncertain_m``) it glances at the nearer goal's centre
(its posts are the surest landmarks) every ``head.glance_every_s`` for ``head.glance_s``.
"""

from __future__ import annotations

import enum
import math

from agents.behavior import skills
from agents.modelling.ball_absence import in_view
from agents.modelling.ball_model import BallEstimate
from agents.team.behavior.framework import Option
from agents.team.behavior.geometry import relative
from agents.team.behavior.requests import HeadRequest
from agents.team.modelling.representations import WorldModel
from agents.team.params import TeamParams
from match.protocol import PENALTY_KICKER_BEHIND_BALL_M, Pose2D
from world.camera_model import CameraPosition
from world.field import FIELD


class Look(enum.Enum):
    GLANCE = "glance"
    TRACK = "track"
    FOLLOW_KICK = "follow kick"
    LOOK_NEAR = "look near"
    LOOK_TEAM_BALL = "look at the team ball"
    SEARCH = "search"


class Glance(enum.Enum):
    NONE = "none"
    GLANCING = "glancing"  # since it began: it lasts head.glance_s, the next one comes head.glance_every_s after


class HeadControl:
    """The head option; ``camera``: the camera it chose (kept from step to step: a hysteresis by distance)."""

    def __init__(self, params: TeamParams):
        self.params = params
        self.look = Option(Look.TRACK)
        self.glance = Option(Glance.NONE)
        self.camera = CameraPosition.TOP
        self.sweep = skills.HeadSweep()
        self.near_sweep = skills.HeadSweep(amplitude_rad=skills.NEAR_SWEEP_AMPLITUDE_RAD)

    @property
    def searching_near_feet(self) -> bool:
        """The search's first look, near the feet, is not done."""
        return not self.near_sweep.swept

    def request(self, yaw_rad: float, pitch_rad: float) -> HeadRequest:
        return HeadRequest(yaw_rad, pitch_rad, self.camera)

    def control(self, world: WorldModel, following_kick: bool) -> HeadRequest:
        """This step's head (``following_kick``: a kick of its own went off lately)."""
        p, now, pose = self.params.head, world.now_s, world.robot.pose_field
        ball_rel, ball_field = world.ball.recent, world.team_ball.field
        was_searching = self.look.is_in(Look.SEARCH)
        if world.robot.sigma_m > p.uncertain_m and now >= self.glance.since_s + p.glance_every_s:
            self.glance.enter(Glance.GLANCING, now)
        if self.glance.is_in(Glance.GLANCING) and now < self.glance.since_s + p.glance_s:
            return self._goto(Look.GLANCE, now, *self._glance(pose))
        if ball_rel is not None and ball_rel.age_s <= p.track_ball_s:
            return self._goto(Look.TRACK, now, *self.look_at(ball_rel))
        if following_kick:  # the ball rolled off ahead
            self.camera = CameraPosition.TOP
            return self._goto(Look.FOLLOW_KICK, now, 0.0, skills.SCAN_PITCH_RAD)
        if ball_rel is not None and ball_rel.distance_m < p.look_at_near_ball_m:  # not seen lately, but near
            yaw, pitch = self.look_at(ball_rel)
            if in_view(ball_rel, yaw, pitch, self.camera, world.obstacles.torso):
                return self._goto(Look.LOOK_NEAR, now, yaw, pitch)
        if ball_rel is None and ball_field is not None and now % p.search_cycle_s < p.look_for_team_ball_s:
            return self._goto(Look.LOOK_TEAM_BALL, now, *self.look_at(relative(pose, ball_field)))
        return self._goto(Look.SEARCH, now, *self._search(was_searching))

    def _goto(self, look: Look, now_s: float, yaw_rad: float, pitch_rad: float) -> HeadRequest:
        self.look.goto(look, now_s)
        return self.request(yaw_rad, pitch_rad)

    def _search(self, was_searching: bool) -> tuple[float, float]:
        """A quick look near the feet (a new search), then wide sweeps on from where it ended."""
        if not was_searching:
            self.near_sweep.restart(0.0, 1.0)
        if not self.near_sweep.swept:
            self.camera = CameraPosition.BOTTOM
            yaw = self.near_sweep.advance(skills.NEAR_SWEEP_RATE_RADPS)
            if self.near_sweep.swept:
                self.sweep.restart(yaw, self.near_sweep.direction)
            return yaw, skills.NEAR_SCAN_PITCH_RAD
        yaw = self.sweep.advance(skills.SEARCH_SCAN_RATE_RADPS)
        if self.sweep.reversals % 2 == 1:
            self.camera = CameraPosition.BOTTOM
            return yaw, skills.MID_SCAN_PITCH_RAD
        self.camera = CameraPosition.TOP
        return yaw, skills.SCAN_PITCH_RAD

    def look_at(self, ball: BallEstimate) -> tuple[float, float]:
        """Head angles that centre a ball (torso frame), with the camera that sees it at its distance."""
        if ball.distance_m < skills.BOTTOM_CAMERA_BELOW_M:
            self.camera = CameraPosition.BOTTOM
        elif ball.distance_m > skills.TOP_CAMERA_BEYOND_M:
            self.camera = CameraPosition.TOP
        return skills.look_at(ball, self.camera)

    def penalty_look(self, world: WorldModel) -> HeadRequest:
        """A penalty kicker's head while the kick is set: first at the goal straight ahead (top camera), where
        it sees the goalkeeper (:mod:`agents.behavior.tactics.shot_window`), then at the ball before its feet."""
        if world.now_s - world.game.state_since_s < self.params.head.penalty_look_s:
            self.camera = CameraPosition.TOP
            return self.request(0.0, skills.SCAN_PITCH_RAD)
        return self.request(*self.look_at(BallEstimate(PENALTY_KICKER_BEHIND_BALL_M, 0.0, 0.0, 0.0, 0.0, 0.0)))

    def _glance(self, pose: Pose2D) -> tuple[float, float]:
        """Look at the nearer goal's centre with the top camera."""
        self.camera = CameraPosition.TOP
        best = None
        for goal_x in (-FIELD.half_length, FIELD.half_length):
            bearing = math.remainder(math.atan2(-pose.y, goal_x - pose.x) - pose.theta, math.tau)
            if best is None or abs(bearing) < abs(best):
                best = bearing
        return best, skills.SCAN_PITCH_RAD
