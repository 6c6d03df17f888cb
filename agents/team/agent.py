"""The team agent: a player that sees, localizes while it plays, and plays with its teammates.

A composition of three stages, each step (40 ms), from the observation only:

1. **Perception** (:meth:`TeamAgent.think`) of the last step's camera frame, if the step before it had
   the camera on and nothing saw it yet: one step of perception latency
   (:mod:`agents.team.modelling.perception`).
2. **Modelling** (:class:`~agents.team.modelling.modeller.WorldModeller`): odometry and posture, the
   radio in, the game situation, the pose, the obstacles, the own ball, the team ball and the play
   status, each by its provider, into one :class:`~agents.team.modelling.representations.WorldModel`.
3. **Behaviour** (:class:`~agents.team.behavior.root.Behavior`): reads that snapshot only and requests
   a motion, the head and camera, and the radio's role and intention.

The composition then steers a walk around the obstacles (not the striker's near its ball), escapes a
lock with another robot (:mod:`agents.behavior.tactics.unjam`), and sends the radio message every
:data:`RADIO_EVERY_STEPS` steps and a camera frame every :data:`CAMERA_EVERY_STEPS`. The tunable numbers
are :mod:`agents.team.params`'s (``params``). Variants: the localization method (``method``) and
``avoid_obstacles`` (False: the "blind" player of the thesis' scenario 3).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

from agents.behavior import skills
from agents.behavior.skills import paths
from agents.behavior.tactics.unjam import Unjammer
from agents.modelling.ball_model import to_field
from agents.observation import Observation
from agents.radio import Role, TeamMessage
from agents.team.behavior.requests import BehaviorOutput
from agents.team.behavior.root import Behavior
from agents.team.modelling.modeller import WorldModeller
from agents.team.modelling.representations import WorldModel
from agents.team.params import TeamParams
from agents.vision.pipeline import VisionPipeline
from match.protocol import AgentId, AgentReport, CameraChoice, Motion, make_action
from world.camera_model import CameraPosition

DT_S = skills.CONTROL_STEP_S
DEFAULT_METHOD = "particle"
CAMERA_EVERY_STEPS = 2
RADIO_EVERY_STEPS = 5  # one packet per 0.2 s: the radio's budget


class TeamAgent:
    """The ``team`` policy (:class:`match.protocol.policy.Policy` and ``PoseReporter``)."""

    def __init__(self, method: str = DEFAULT_METHOD, avoid_obstacles: bool = True, camera_model: str = "exact",
                 params: TeamParams | None = None):
        self.method = method
        self.avoid_obstacles = avoid_obstacles
        self.params = TeamParams.default() if params is None else params
        self.pipeline = VisionPipeline(camera_model)
        self.reset("home_1", 0)

    def reset(self, agent_id: str, seed: int) -> None:
        self.agent_id = agent_id
        self.player = AgentId.parse(agent_id).player
        self.world = WorldModeller(self.player, self.method, seed, self.pipeline, self.params)
        self.behavior = self.make_behavior()
        self.unjam = Unjammer(DT_S)
        self.sequence = 0
        self.last: BehaviorOutput | None = None
        self._walk = skills.STILL
        self._unseen: Observation | None = None  # the last act's frame, not seen yet (think)

    def make_behavior(self) -> Behavior:
        """The behaviour this agent plays (a subclass may choose another, or other roles)."""
        return Behavior(self.params)

    @property
    def step(self) -> int:
        return self.world.step

    @property
    def now_s(self) -> float:
        return self.world.now_s

    def pose_estimate(self) -> tuple[float, float, float] | None:
        pose = self.world.locator.pose
        return None if pose is None else (pose.x, pose.y, pose.theta)

    def act(self, observation: Observation | Mapping[str, Any]) -> dict:
        obs = Observation.of(observation)
        self.think()  # the last step's frame, unless a controller process had it seen already
        world = self.world.update(obs, self._walk, self.behavior.intention)
        busy = world.posture.busy
        # kept for think(): a copy of the image, since a caller may reuse its buffer for the next step
        self._unseen = dataclasses.replace(obs, image=obs.image.copy()) if obs.image is not None and not busy else None
        out = self.last = self.behavior.decide(world)
        motion, walk = out.motion.motion, self._steer(world, out)
        self._walk = walk if motion is Motion.WALK else skills.STILL
        radio = self._message(world, out).encode() if self.step % RADIO_EVERY_STEPS == 0 else b""
        camera = CameraChoice.of(self._frame_camera(out)) if self.step % CAMERA_EVERY_STEPS == 0 else CameraChoice.OFF
        return make_action(motion, walk=walk, head=skills.clip_head(out.head.yaw_rad, out.head.pitch_rad),
                           camera=camera, radio=radio)

    def think(self) -> None:
        """See the camera frame of the last :meth:`act` (:class:`~match.protocol.policy.Thinker`): the
        models take it in after the step's action went out, so a step's action reacts to the frames
        before it, one step (40 ms) of perception latency, as on a robot whose vision runs beside its
        motion control. A controller process calls this while the simulator plays the next step;
        otherwise the next :meth:`act` does, first: the same actions either way."""
        frame, self._unseen = self._unseen, None
        if frame is not None:
            self.world.see(frame)

    def _steer(self, world: WorldModel, out: BehaviorOutput) -> tuple[float, float, float]:
        """The walk around the obstacles (not the striker's near its ball, which goes for it whoever stands
        there), and out of a lock with another robot (a turn that does not turn)."""
        walk = out.motion.walk
        odometry = world.odometry
        if odometry.upright:
            self.unjam.observe(odometry.commanded_turn_radps, odometry.measured_turn_radps)
        else:
            self.unjam.reset()
        if out.motion.motion is not Motion.WALK:
            return walk
        ball = world.ball.recent if world.ball is not None else None
        contesting = (out.role == Role.STRIKER and ball is not None
                      and ball.distance_m < self.params.kick.contest_ball_m)
        if self.avoid_obstacles and not contesting:
            walk = paths.steer_around(walk, world.obstacles.torso)
        escape = self.unjam.escape(world.posture.sonar_m)
        return walk if escape is None else escape

    def _frame_camera(self, out: BehaviorOutput) -> CameraPosition:
        """The camera of this step's frame: the head's, but while the striker lines up a kick with the ball
        at its feet, every ``head.shot_top_frame_every``-th frame the top one, which sees the robots in
        front of it (the shot window's blockers, those a kick must pass) and the goal's posts."""
        if out.lining_up and (self.step // CAMERA_EVERY_STEPS) % self.params.head.shot_top_frame_every == 0:
            return CameraPosition.TOP
        return out.head.camera

    def _message(self, world: WorldModel, out: BehaviorOutput) -> TeamMessage:
        """This step's report; lying or standing up, teammates neither count it for the ball (its role and
        time to the ball are those of before the fall) nor take its sightings."""
        robot = world.robot
        pose, ball = robot.pose_field, None
        torso = world.ball.torso if world.ball is not None else self.world.ball.relative()
        if torso is not None:
            ball = to_field(torso, (pose.x, pose.y, pose.theta), robot.sigma_m, robot.sigma_rad)
        self.sequence += 1
        return TeamMessage(
            player=self.player, sequence=self.sequence, pose=(pose.x, pose.y, pose.theta),
            pose_sigma_m=robot.sigma_m, pose_sigma_rad=robot.sigma_rad,
            ball_xy=None if ball is None else (ball.x, ball.y),
            ball_velocity=(0.0, 0.0) if ball is None else (ball.vx, ball.vy),
            ball_sigma_m=0.0 if ball is None else ball.sigma_m, ball_age_s=0.0 if ball is None else ball.age_s,
            fallen=world.posture.busy, role=out.role, intention=out.intention, time_to_ball_s=out.time_to_ball_s)

    def report(self) -> AgentReport | None:
        """What it believes beside its pose, for the match log (``match.protocol.AgentReporter``): its own
        ball and the team ball (field frame) as its last decision used them, its role, and the landmarks
        of its last camera frame if that frame is at most one camera period old. None before it has a pose."""
        if self.world.locator.pose is None:
            return None
        own, team = self.world.team_ball.believed
        role = self.behavior.role
        return AgentReport(ball_xy=own, team_ball_xy=team, role=None if role == Role.NONE else role,
                           landmarks_seen=self.world.perception.landmarks_of_last_frame(self.step, CAMERA_EVERY_STEPS))
