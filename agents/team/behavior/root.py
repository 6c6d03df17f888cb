"""The behaviour's root: the game state, then the role.

Lying or standing up, the robot recovers (the stand-up for the side it lies on, once it lies still;
lying on a flank the reading is unsure, so when a stand-up tried in this fall left it down, the other
one). Else the head plays (:mod:`.head`) and: in READY it walks to its kick-off pose (a lone goalkeeper
to the first field player's); in INITIAL, SET and FINISHED it stands (a penalty kicker looks at the
goal, then the ball); in PLAYING a kick under way plays on, else the role chosen (:mod:`.roles`) plays.
"""

from __future__ import annotations

import enum
import math
from collections.abc import Sequence

from agents.behavior import skills
from agents.behavior.tactics.roles import FIELD_ROLES
from agents.radio import Intention, Role
from agents.team.behavior.framework import Option
from agents.team.behavior.head import HeadControl
from agents.team.behavior.requests import BehaviorOutput, HeadRequest, MotionRequest
from agents.team.behavior.roles import defender, goalkeeper, striker, supporter  # noqa: F401 (they register)
from agents.team.behavior.roles.assignment import assign, lone, shootout_role
from agents.team.behavior.roles.registry import REGISTRY, RolePlayer, Situation
from agents.team.behavior.striker.play import Striker
from agents.team.modelling.representations import WorldModel
from agents.team.params import TeamParams
from match.protocol import GameState, Motion, kickoff_pose


class Kick(enum.Enum):
    NONE = "none"
    KICKED = "kicked"  # entered again each step a kick plays: the ball rolls off ahead for kick.follow_kick_s


class Behavior:
    """The root option. ``role``, ``intention`` and ``time_to_ball_s`` hold from step to step until changed."""

    def __init__(self, params: TeamParams, field_roles: Sequence[str] = FIELD_ROLES):
        self.params = params
        self.field_roles = tuple(field_roles)
        self.head = HeadControl(params)
        self.striker = Striker(params)
        self.roles: dict[str, RolePlayer] = {name: spec.make(self) for name, spec in REGISTRY.items()}
        self.kick = Option(Kick.NONE)
        self.role = Role.NONE
        self.intention = Intention.NONE
        self.time_to_ball_s = math.inf

    def following_kick(self, now_s: float) -> bool:
        return self.kick.is_in(Kick.KICKED) and self.kick.for_s(now_s) < self.params.kick.follow_kick_s

    def decide(self, world: WorldModel) -> BehaviorOutput:
        self.striker.lining_up = False
        motion, head = self._decide(world)
        if motion.intention is not None:
            self.intention = motion.intention
        return BehaviorOutput(motion, head, self.striker.lining_up, self.role, self.intention, self.time_to_ball_s)

    def _decide(self, world: WorldModel) -> tuple[MotionRequest, HeadRequest]:
        posture, game = world.posture, world.game
        if posture.busy:
            return self._recover(world), self.head.request(0.0, 0.0)
        head = self.head.control(world, self.following_kick(world.now_s))
        if game.state is GameState.READY:
            place = 1 if lone(world) else world.player  # a lone goalkeeper takes the first field player's place
            start = kickoff_pose(place, game.own_kickoff, game.defended)
            return MotionRequest.of(skills.walk_to(world.robot.pose_field, start), Intention.POSITION), head
        if game.state is not GameState.PLAYING:
            if game.state is GameState.SET and game.shootout and game.own_kickoff:
                head = self.head.penalty_look(world)
            return MotionRequest(Motion.STAND, skills.STILL, Intention.NONE), head
        if posture.kicking:
            self.kick.enter(Kick.KICKED, world.now_s)
            return MotionRequest(posture.motion, skills.STILL), head
        return self._play(world), head

    def _recover(self, world: WorldModel) -> MotionRequest:
        posture = world.posture
        if posture.standing_up:
            return MotionRequest(posture.motion, skills.STILL, Intention.RECOVER)
        if math.hypot(*posture.gyro_radps) > self.params.posture.settled_gyro_radps:  # still tumbling
            return MotionRequest(Motion.STAND, skills.STILL, Intention.RECOVER)
        if posture.stand_up_tried:
            tried = posture.last_stand_up
            other = Motion.STAND_UP_FROM_FRONT if tried is Motion.STAND_UP_FROM_BACK else Motion.STAND_UP_FROM_BACK
            return MotionRequest(other, skills.STILL, Intention.RECOVER)
        return MotionRequest(skills.stand_up_for(posture.accelerometer_x_mps2), skills.STILL, Intention.RECOVER)

    def _play(self, world: WorldModel) -> MotionRequest:
        """PLAYING: the role, chosen by the spot a ball going out comes back on, else by the ball."""
        restart = play_xy = None
        if world.game.shootout:
            self.role = shootout_role(world)
        else:
            restart, ball = world.play.restart_field, world.team_ball.field
            play_xy = restart if restart is not None else (None if ball is None else (ball.x, ball.y))
            self.role, self.time_to_ball_s = assign(world, play_xy, self.role, self.field_roles)
        if self.role == Role.NONE:
            return MotionRequest(Motion.STAND, skills.STILL, Intention.NONE)
        situation = Situation(play_xy, restart, self.following_kick(world.now_s), self.head.searching_near_feet)
        return self.roles[self.role].play(world, situation)


