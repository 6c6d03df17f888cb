"""The team agent: a player that sees, localizes while it plays, and plays with its teammates.

One step (40 ms) runs, from the observation only:

1. **Perception** of the last step's camera frame, if the step before it had the camera on
   and nothing saw it yet (:meth:`TeamAgent.think`): the landmark pipeline of
   :mod:`agents.vision`, the ball from the same segmented image, its size checked against
   its distance, and other robots by their waistbands; landmarks update the self-locator,
   the ball the ball model, robots the obstacle model. A frame is seen after the action of
   its step went out (in a controller process, while the simulator plays the next step):
   one step of perception latency.
2. **Odometry**: the walk commanded last step moved the robot, and the gyro says how much
   it turned; the self-locator, the ball model and the obstacle model are moved by it
   (:mod:`agents.modelling`), and the sonars' echoes go into the obstacle model.
3. **Radio in**: teammates' messages (:mod:`agents.team.messages`) into the team model;
   anything else is counted and ignored. This step's frame, if any, is kept for step 1.
4. **Game state**: stand in INITIAL, SET and FINISHED (placed at its kick-off pose in
   INITIAL, so the locator is reset there, and in SET when it lay fallen or believes it
   stood where it may not stay: the referee placed it); walk to the kick-off pose in READY;
   stand up after a fall, once it lies still; in a penalty shoot-out, reset at the kicker's
   or goalkeeper's place when the kick is set. After a throw-in (the
   game-control data's drop-in), the balls seen before it are forgotten and the ball is
   believed at the rule's spot (from where it was believed to leave the field and who put it
   out) until someone sees it.
5. **Role** (PLAYING): goalkeeper, striker, supporter or defender (:mod:`agents.behavior.roles`)
   from the team model; the striker goes behind the ball and kicks it toward the opponent
   goal computed from its pose estimate, within 3 m of it into the widest part of the mouth
   no robot it saw covers (:mod:`agents.behavior.shot_window`), farther out past a robot it saw in
   the way (:mod:`agents.behavior.kick_past`) (a ball going out or out: striker and roles
   are chosen by the spot the referee will put it back on, and the striker waits behind it,
   :mod:`agents.modelling.ball_out`;
   a ball in front of its own goal: it clears it out to the side, :mod:`agents.behavior.aim`,
   or, lying at the goal line, holds off, :mod:`agents.behavior.goal_line`;
   a throw-in's ball still on the throw-in line: the quickest first touch that sends it neither
   back toward the own goal nor out);
   the others walk to their role's position; every walk steps around the obstacles but the
   striker's near its ball.
6. **Head**: track the ball (a near one unseen for a moment: look where it is believed, until
   a frame finds it or forgets it), glance at a goal when the pose is uncertain; without its own
   ball, look where the team believes it, else search: a quick look near the feet, then wide
   sweeps; the camera is on every other step (lining up a shot with the ball at its feet,
   every third frame is the top camera's: it sees the goalkeeper).
7. **Radio out**: pose, ball, role and intention every :data:`RADIO_EVERY_STEPS` steps.

Variants: the localization method (``method``) and ``avoid_obstacles`` (False: the
"blind" player of the thesis' scenario 3).
"""

from __future__ import annotations

import dataclasses
import logging
import math
from collections.abc import Mapping
from typing import Any

from agents.behavior import paths, skills
from agents.behavior.aim import POST_CLEARANCE_M, Aim, kick_aim, on_their_goal_line, restart_aim
from agents.behavior.goal_line import at_own_goal_line, hold_off
from agents.behavior.kick_past import kick_past
from agents.behavior.shot_window import ShotWindow, shot_window
from agents.behavior.roles import Candidate, assign_role, role_position, time_to_ball
from agents.behavior.stall import STALL_NEAR_M, StallWatch, push_allowed
from agents.behavior.unjam import Unjammer
from agents.modelling.ball_absence import BallAbsence, in_clear_view, in_view
from agents.modelling.ball_model import BallEstimate, BallModel
from agents.modelling.ball_out import OWN_TOUCH_MEMORY_S, BallOut, expected_spot, leaving_point, out_of_field
from agents.modelling.obstacle_model import ObstacleKind, ObstacleModel
from agents.modelling.self_locator import SelfLocator
from agents.modelling.team_model import TeamModel
from agents.observation import Observation
from agents.team.params import TeamParams
from agents.team.messages import DecodeStats, Intention, Role, TeamMessage, decode
from agents.team.report import landmarks_seen
from agents.vision.ball import ball_in_mask, plausible
from agents.vision.colors import ColorClass
from agents.vision.frame import CameraFrame
from agents.vision.percepts import LandmarkPercept
from agents.vision.pipeline import VisionPipeline
from agents.vision.robots import find_robots
from match.protocol import (
    PENALTY_KICKER_BEHIND_BALL_M,
    THROW_IN_INSET_M,
    AgentId,
    AgentReport,
    CameraChoice,
    Displacement,
    DropIn,
    GameState,
    GoalColor,
    KickOff,
    Motion,
    Pose2D,
    SecondaryState,
    kickoff_pose,
    legal_kickoff_position,
    make_action,
    penalty_pose,
    throw_in_spot,
)
from world.camera_model import CameraPosition
from world.field import FIELD

LOG = logging.getLogger(__name__)

DT_S = skills.CONTROL_STEP_S
DEFAULT_METHOD = "particle"
CAMERA_EVERY_STEPS = 2
RADIO_EVERY_STEPS = 5  # one packet per 0.2 s: the radio's budget


class TeamAgent:
    """The ``team`` policy (:class:`match.protocol.policy.Policy` and ``PoseReporter``)."""

    def __init__(self, method: str = DEFAULT_METHOD, avoid_obstacles: bool = True, camera_model: str = "exact",
                 params: TeamParams | None = None):
        self.method = method
        self.params = TeamParams.default() if params is None else params
        self.avoid_obstacles = avoid_obstacles
        self.pipeline = VisionPipeline(camera_model)
        self.reset("home_1", 0)

    # ---- life cycle ----------------------------------------------------------------------

    def reset(self, agent_id: str, seed: int) -> None:
        self.agent_id = agent_id
        self.player = AgentId.parse(agent_id).player
        self.locator = SelfLocator(self.method, seed)
        self.ball = BallModel()
        self.ball_absence = BallAbsence()
        self.obstacles = ObstacleModel()
        self.unjam = Unjammer(DT_S)
        self.stall = StallWatch()
        self.team = TeamModel(self.player)
        self.role = Role.NONE
        self.intention = Intention.NONE
        self.decode_stats = DecodeStats()
        self.step = 0
        self._unseen: Observation | None = None  # the last act's frame, not seen yet (think)
        self.sequence = 0
        self._walk = skills.STILL
        self._state: GameState | None = None
        self._state_since_s = 0.0  # when the game state last changed (own clock)
        self._defended: GoalColor | None = None
        self._camera = CameraPosition.TOP
        self._sweep = skills.HeadSweep()
        self._near_sweep = skills.HeadSweep(amplitude_rad=skills.NEAR_SWEEP_AMPLITUDE_RAD)
        self._sweeping = False  # the head sweeps for the ball (since the last step that did something else)
        self._glance_until_s = -math.inf
        self._next_glance_s = 0.0
        self._own_goal_ahead_s = -math.inf
        self._was_fallen = False
        self._acceleration_z = 9.81
        self._kicked_s = -math.inf  # when it last kicked (s)
        self._fall_sequence = 0  # the finished-motion count when it last went down
        # the last frame, for report(): its step, its percepts and the pose they were seen from; the
        # landmark indices are matched only when a report asks for them (evaluation, not play)
        self._seen: tuple[int, tuple[LandmarkPercept, ...], Pose2D | None] = (-1, (), None)
        self._seen_landmarks: tuple[int, frozenset[int]] = (-1, frozenset())
        self._believed_balls: tuple[tuple[float, float] | None, tuple[float, float] | None] = (None, None)
        self._time_to_ball_s = math.inf
        self._last_ball_xy: tuple[float, float] | None = None  # the last ball it believed in (field frame)
        self._left_at: BallOut | None = None  # where the believed ball left the field, while it is believed out
        self._drop_in_since_s = math.inf  # the last broadcast's seconds since a throw-in
        self._drop_in_at_s = -math.inf  # when the last throw-in put the ball back (own clock)
        self._drop_in_spot: tuple[float, float] | None = None  # where the rule put it, from the last belief
        self._first_touch_s = -math.inf  # when it began its first touch after the last throw-in (own clock)
        self._restart_aim_rad: float | None = None  # the direction of that first touch's last aim (field frame)
        self._put_back_seen_xy: tuple[float, float] | None = None  # where it first saw that ball (field frame)
        self._shot_direction_rad: float | None = None  # the direction its last shot window aimed at (field frame)
        self._past_direction_rad: float | None = None  # the direction it last aimed at to kick past a robot (field frame)
        self._lining_up_s = -math.inf  # when it last lined up a kick with the ball at its feet (own clock)
        self._ball_in_s = 0.0  # when it last believed the ball in the field (or believed no ball; own clock)
        self._own_touch_s = -math.inf  # when it or a teammate last meant to kick or push the ball (own clock)
        self._kickoff_played_s = math.inf  # when the ball of the last kick-off was first believed played (own clock)
        self._side_tap_s = -math.inf  # when it last side-stepped into a throw-in's ball (own clock)
        self._side_tap_for_s = -math.inf  # the throw-in (its _drop_in_at_s) whose first touch it chose to tap
        self._side_tap_along = 1.0  # the way (field x: +1 or -1) that tap goes, chosen with it

    @property
    def now_s(self) -> float:
        return self.step * DT_S

    def pose_estimate(self) -> tuple[float, float, float] | None:
        pose = self.locator.pose
        return None if pose is None else (pose.x, pose.y, pose.theta)

    # ---- the step ------------------------------------------------------------------------

    def act(self, observation: Observation | Mapping[str, Any]) -> dict:
        obs = Observation.of(observation)
        self.think()  # the last step's frame, unless a controller process had it seen already
        self.step += 1
        self._move(obs)
        self._listen(obs)
        busy = obs.fallen or (obs.motion is not None and obs.motion.is_stand_up)
        # kept for think(): a copy of the image, since a caller may reuse its buffer for the next step
        self._unseen = dataclasses.replace(obs, image=obs.image.copy()) if obs.image is not None and not busy else None
        self._follow_game(obs)
        motion, walk, head = self._decide(obs, busy)
        if motion is Motion.WALK and self.avoid_obstacles and not self._contesting():
            walk = paths.steer_around(walk, self.obstacles.obstacles())
        escape = self.unjam.escape(obs.sonar_m) if motion is Motion.WALK else None
        if escape is not None:  # a turn that does not turn: locked with another robot
            walk = escape
        self._walk = walk if motion is Motion.WALK else skills.STILL
        radio = self._message(busy).encode() if self.step % RADIO_EVERY_STEPS == 0 else b""
        camera = CameraChoice.of(self._frame_camera()) if self.step % CAMERA_EVERY_STEPS == 0 else CameraChoice.OFF
        return make_action(motion, walk=walk, head=skills.clip_head(*head), camera=camera, radio=radio)

    def _frame_camera(self) -> CameraPosition:
        """The camera of this step's frame: the one the head chose, but while the striker lines up a kick with
        the ball at its feet (bottom camera), every ``head.shot_top_frame_every``-th frame the top one, which
        sees the robots in front of it (the shot window's blockers, those a kick must pass) and the goal's posts."""
        frame = self.step // CAMERA_EVERY_STEPS
        if self._lining_up_s == self.now_s and frame % self.params.head.shot_top_frame_every == 0:
            return CameraPosition.TOP
        return self._camera

    def think(self) -> None:
        """See the camera frame of the last :meth:`act` (:class:`~match.protocol.policy.Thinker`):
        the models take it in after the step's action went out, so a step's action reacts to the
        frames before it, one step (40 ms) of perception latency, as on a robot whose vision runs
        beside its motion control. A controller process calls this while the simulator plays the
        next step; otherwise the next :meth:`act` does, first: the same actions either way."""
        frame, self._unseen = self._unseen, None
        if frame is not None:
            self._see(frame)

    # ---- modelling -----------------------------------------------------------------------

    def _move(self, obs: Observation) -> None:
        """The last step's own walk moves the beliefs: the translation as commanded (nominal), the
        turn as the gyro measured it (it also feels pushes and collisions)."""
        walking = obs.motion is Motion.WALK
        vx, vy, _ = self._walk if walking else skills.STILL
        self._acceleration_z += self.params.posture.upright_smoothing * (obs.accelerometer_mps2[2] - self._acceleration_z)
        upright = (not obs.fallen and not (obs.motion is not None and obs.motion.is_stand_up)
                   and self._acceleration_z > self.params.posture.upright_acceleration_mps2)
        omega = obs.gyro_radps[2] if upright else 0.0
        if upright:
            self.unjam.observe(self._walk[2] if walking else 0.0, omega)
        else:
            self.unjam.reset()
        moved = _arc(vx, vy, omega, DT_S)
        self.locator.move(moved)
        self.ball.predict(DT_S, moved)
        self.obstacles.predict(moved, DT_S)
        self.obstacles.hear_sonar(obs.sonar_m)
        if obs.fallen and not self._was_fallen:
            self.locator.fell(self.params.posture.fall_sigma_m, self.params.posture.fall_sigma_rad)
            self._fall_sequence = obs.last_motion_sequence
        self._was_fallen = obs.fallen

    def _listen(self, obs: Observation) -> None:
        for packet in obs.packets:
            message = decode(packet.data, self.decode_stats)
            if message is not None and message.player == packet.sender:
                self.team.hear(message, self.now_s)
            elif message is not None:
                self.decode_stats.ignored["sender mismatch"] += 1

    def _see(self, obs: Observation) -> None:
        frame = CameraFrame.from_observation(obs)
        result = self.pipeline.process(frame)
        self._seen = (self.step, result.percepts, self.locator.pose)
        self.locator.update(result.percepts)
        own_goal = obs.game.defended_goal
        for percept in result.percepts:
            if percept.goal is own_goal and abs(percept.bearing_rad) < self.params.kick.own_goal_ahead_rad:
                self._own_goal_ahead_s = self.now_s
        mask = result.segmented == int(ColorClass.ORANGE)
        ball = ball_in_mask(mask, frame.head_yaw_rad, frame.head_pitch_rad, frame.camera)
        seen = ball is not None and plausible(ball)
        if seen:
            self.ball.measure(ball.distance_m, ball.bearing_rad)
        believed = None if seen or obs.fallen else self._own_ball()
        expected = believed is not None and in_clear_view(
            believed, frame.head_yaw_rad, frame.head_pitch_rad, frame.camera, self.obstacles.obstacles())
        if self.ball_absence.frame(self.now_s, seen, expected):
            self.ball.reset()
        self.obstacles.see(find_robots(result.segmented, frame.head_yaw_rad, frame.head_pitch_rad, frame.camera,
                                       obs.game.team_color))

    def _follow_game(self, obs: Observation) -> None:
        """Resets at the kick-off pose (thesis 5.5) when the referee placed the robot there,
        and at the penalty kicker's or goalkeeper's pose when a shoot-out kick is set; after a
        throw-in, forgets the balls seen before it (:meth:`_throw_in`)."""
        if obs.game.state is not self._state:
            self._state_since_s = self.now_s
            self._kickoff_played_s = math.inf
        since = obs.game.seconds_since_drop_in
        if since < self._drop_in_since_s:  # the count started again: a new throw-in
            self._throw_in(obs, since)
        self._drop_in_since_s = since
        state, defended = obs.game.state, obs.game.defended_goal
        kicking = obs.game.kickoff is KickOff.OWN_TEAM
        if _shootout(obs):
            set_anew = state is GameState.SET and (self._state is not GameState.SET or defended is not self._defended)
            if set_anew or self.locator.pose is None:
                self.locator.reset(penalty_pose(kicking, defended))
                self.ball.reset()
            self._state, self._defended = state, defended
            return
        start = kickoff_pose(self.player, kicking, defended)
        pose = self.locator.pose
        if state is GameState.INITIAL and (self._state is not GameState.INITIAL or defended is not self._defended):
            self.locator.reset(start)
            self.ball.reset()
        elif state is GameState.SET and self._state is not GameState.SET:
            # The referee put it at its kick-off pose if it lay fallen or stood where it may not stay.
            if pose is None or obs.fallen or not legal_kickoff_position(pose.x, pose.y, defended, kicking):
                self.locator.reset(start)
        elif pose is None:
            self.locator.reset(start)
        self._state, self._defended = state, defended

    def _throw_in(self, obs: Observation, since_s: float) -> None:
        """The referee put the ball back ``since_s`` ago: every sighting from before is of a ball that
        is gone, and the rule gives where it is now, from where the ball was believed to leave the field
        (its first belief out, on the line it crossed; else where it was last believed) and from who put
        it out (game-control data). A ball seen rolling on beyond the line, 2 m out by the put-back, once
        gave a spot 1.5 m from the referee's, and the striker walked there."""
        self._drop_in_at_s = self.now_s - since_s
        if self.ball.age_s > since_s:
            self.ball.reset()
        self._drop_in_spot = None
        self._restart_aim_rad = None
        self._put_back_seen_xy = None
        defended = obs.game.defended_goal
        toucher_defends = {DropIn.OWN_TEAM: defended, DropIn.OPPONENT: defended.other}.get(obs.game.drop_in_team)
        if self._left_at is not None:  # where it was believed to leave, not where it rolled on to
            left = self._left_at
            self._drop_in_spot = throw_in_spot(left.x, left.y, left.over_end_line, toucher_defends)
        elif self._last_ball_xy is not None:
            bx, by = self._last_ball_xy
            self._drop_in_spot = throw_in_spot(bx, by, abs(bx) > FIELD.half_length, toucher_defends)
        self._left_at = None

    # ---- behaviour -----------------------------------------------------------------------

    def _decide(self, obs: Observation, busy: bool) -> tuple[Motion, tuple[float, float, float], tuple[float, float]]:
        if obs.motion is not None and obs.motion.is_stand_up:
            self.intention = Intention.RECOVER
            return obs.motion, skills.STILL, (0.0, 0.0)
        if obs.fallen:
            self.intention = Intention.RECOVER
            return self._stand_up(obs), skills.STILL, (0.0, 0.0)
        pose = self.locator.pose
        assert pose is not None  # reset in _follow_game
        ball_rel = self._own_ball()
        ball_field = self._team_ball(pose, ball_rel)
        head = self._head(pose, ball_rel, ball_field)
        state = obs.game.state
        if state is GameState.READY:
            self.intention = Intention.POSITION
            place = 1 if self._lone() else self.player  # a lone goalkeeper takes the first field player's place
            start = kickoff_pose(place, obs.game.kickoff is KickOff.OWN_TEAM, obs.game.defended_goal)
            motion, walk = skills.walk_to(pose, start)
            return motion, walk, head
        if state is not GameState.PLAYING:
            self.intention = Intention.NONE
            if state is GameState.SET and _shootout(obs) and obs.game.kickoff is KickOff.OWN_TEAM:
                head = self._penalty_look()
            return Motion.STAND, skills.STILL, head
        if obs.motion is not None and obs.motion.is_kick:
            self._kicked_s = self.now_s
            return obs.motion, skills.STILL, head
        attack = 1.0 if obs.game.defended_goal is GoalColor.BLUE else -1.0
        self._note_own_touch()
        restart: tuple[float, float] | None = None  # where a ball going out comes back (field frame)
        play_xy: tuple[float, float] | None = None  # what roles are chosen and placed by: that spot, else the ball
        if _shootout(obs):
            self.role = self._shootout_role(obs)
        else:
            restart = self._expected_restart(ball_field, obs.game.defended_goal)
            if restart is not None:
                play_xy = restart
            elif ball_field is not None:
                play_xy = (ball_field.x, ball_field.y)
            self.role = self._assign_role(pose, play_xy, obs)
        holds_lane = self._holds_kickoff_lane(obs, ball_field)
        if self.role is Role.NONE:
            self.intention = Intention.NONE
            return Motion.STAND, skills.STILL, head
        if self.role is Role.STRIKER:
            return self._strike(pose, ball_rel, ball_field, attack, head, restart)
        if self.role is Role.GOALKEEPER and self._keeper_clears(ball_rel, pose, attack):
            return self._strike(pose, ball_rel, ball_field, attack, head)
        self.intention = Intention.POSITION
        if holds_lane:
            return Motion.STAND, skills.STILL, head
        target = role_position(self.role, play_xy, attack)
        motion, walk = skills.walk_to(pose, target)
        return motion, walk, head

    def _holds_kickoff_lane(self, obs: Observation, ball: BallEstimate | None) -> bool:
        """Whether this defender or supporter holds its place at the other team's kick-off: until the ball
        is believed played (``kickoff.played_m`` from the centre spot) and ``kickoff.lane_s`` after,
        within ``kickoff.free_s`` of the kick-off. Walking up from its kick-off place at once, it crossed
        the lane of the kick past the striker, 1.5 m away a second later, and its legs turned the ball
        toward its own goal."""
        if ball is not None and math.hypot(ball.x, ball.y) >= self.params.kickoff.played_m:
            self._kickoff_played_s = min(self._kickoff_played_s, self.now_s)
        if obs.game.kickoff is not KickOff.OPPONENT or self.role not in (Role.DEFENDER, Role.SUPPORTER):
            return False
        return (self.now_s - self._state_since_s < self.params.kickoff.free_s
                and self.now_s - self._kickoff_played_s < self.params.kickoff.lane_s)

    def _own_ball(self) -> BallEstimate | None:
        rel = self.ball.relative()
        return rel if rel is not None and rel.age_s <= self.params.ball.lost_s else None

    def _team_ball(self, pose: Pose2D, ball_rel: BallEstimate | None) -> BallEstimate | None:
        own = None
        if ball_rel is not None:
            own = self.ball.in_field((pose.x, pose.y, pose.theta), self.locator.sigma_m, self.locator.sigma_rad)
        best = self.team.team_ball(own, self.now_s, max_age_s=self.now_s - self._drop_in_at_s)
        team = None if best is None else best[0]
        since_drop_in = self.now_s - self._drop_in_at_s
        if team is None and self._drop_in_spot is not None and since_drop_in < self.params.ball.drop_in_spot_s:
            team = BallEstimate(*self._drop_in_spot, 0.0, 0.0, self.params.ball.drop_in_spot_sigma_m, since_drop_in)
        if team is not None:
            self._last_ball_xy = (team.x, team.y)
            if not out_of_field(self._last_ball_xy):
                self._left_at = None
            elif self._left_at is None:  # its first belief out, on the line it crossed
                self._left_at = leaving_point(team)
        believed = own if own is not None else team
        if believed is None or not out_of_field((believed.x, believed.y)):
            self._ball_in_s = self.now_s
        self._believed_balls = (None if own is None else (own.x, own.y), None if team is None else (team.x, team.y))
        return team

    def _expected_restart(self, ball: BallEstimate | None, defended: GoalColor) -> tuple[float, float] | None:
        """Where the referee will put back the team's ball (field frame), if it is going out or out
        (believed out for less than ``ball_out.out_wait_s``); else None (:mod:`agents.modelling.ball_out`)."""
        if ball is None or self.now_s - self._ball_in_s >= self.params.ball_out.out_wait_s:
            return None
        out = leaving_point(ball)
        if out is None:
            return None
        return expected_spot(out, self.now_s - self._own_touch_s < OWN_TOUCH_MEMORY_S, defended)

    def _note_own_touch(self) -> None:
        """Notes the time when the own team may have touched the ball: this robot meant to kick or push it
        last step, or a teammate's fresh message says it does (the guess of who put a ball out,
        :meth:`_expected_restart`)."""
        if self.intention is Intention.KICK or any(
                m.message.intention is Intention.KICK and m.age_s < self.params.ball_out.teammate_kick_heard_s
                for m in self.team.teammates(self.now_s)):
            self._own_touch_s = self.now_s

    def _assign_role(self, pose: Pose2D, ball_xy: tuple[float, float] | None, obs: Observation) -> Role:
        own_time = math.inf if ball_xy is None else time_to_ball(pose, ball_xy, obs.fallen)
        self._time_to_ball_s = own_time
        others = [Candidate(m.message.player, m.message.time_to_ball_s, m.message.role is Role.STRIKER)
                  for m in self.team.teammates(self.now_s) if not m.message.fallen]
        return assign_role(Candidate(self.player, own_time), others, self.role, lone=self._lone())

    def _lone(self) -> bool:
        """Whether this goalkeeper plays alone: no teammate heard for
        :data:`~agents.behavior.skills.LONE_SILENCE_S` (a team of one, or every teammate silent); it then
        plays the field (:func:`agents.behavior.roles.assign_role`)."""
        return self.player == 0 and self.team.silent_for_s(self.now_s) >= skills.LONE_SILENCE_S

    def _shootout_role(self, obs: Observation) -> Role:
        """In a shoot-out the kicking team's robot on the field strikes, the other team's player 0
        keeps the goal, everyone else (held off the field) stands."""
        if obs.game.kickoff is KickOff.OWN_TEAM:
            return Role.STRIKER
        return Role.GOALKEEPER if self.player == 0 else Role.NONE

    def _keeper_clears(self, ball_rel: BallEstimate | None, pose: Pose2D, attack: float) -> bool:
        """The goalkeeper leaves its line for a ball close to it in its own goal area."""
        if ball_rel is None or ball_rel.distance_m > self.params.keeper.clear_ball_within_m:
            return False
        return pose.x * attack < -FIELD.half_length + self.params.keeper.clear_area_depth_m

    def _strike(self, pose: Pose2D, ball_rel: BallEstimate | None, ball_field: BallEstimate | None, attack: float,
                head: tuple[float, float], restart: tuple[float, float] | None = None
                ) -> tuple[Motion, tuple[float, float, float], tuple[float, float]]:
        """Play the ball; one going out (``restart``: where the referee will put it back, field frame):
        wait behind that spot."""
        if ball_rel is None and ball_field is None:
            self.intention = Intention.SEARCH
            if self._just_kicked():  # follow the kick before turning round to search
                return Motion.WALK, skills.walk_command(self.params.kick.follow_kick_mps, 0.0, 0.0), head
            if not self._near_sweep.swept:  # the head looks near the feet first: stand while it does
                return Motion.STAND, skills.STILL, head
            return Motion.WALK, skills.walk_command(0.0, 0.0, skills.SEARCH_TURN_RADPS), head
        self.intention = Intention.GO_TO_BALL
        if restart is not None:
            motion, walk = skills.walk_to(pose, _throw_in_wait_pose(restart, attack, self.params.ball_out.throw_in_wait_back_m))
            return motion, walk, head
        goal_x = FIELD.half_length * attack
        ball_xy = (ball_field.x, ball_field.y) if ball_rel is None else _in_field(pose, ball_rel)
        if at_own_goal_line(ball_xy, attack):  # no way behind it but through the goal: hold off
            self.intention = Intention.POSITION
            motion, walk = hold_off(pose, ball_xy, attack)
            return motion, walk, head
        if out_of_field(ball_xy):  # not put back: it lies on a line, believed a little beyond it
            ball_xy = _into_field(ball_xy, self.params.ball.in_field_margin_m)
        aim = goal_aim = kick_aim(ball_xy, attack, pose.y)
        shot = None
        goal_line = on_their_goal_line(ball_xy, attack)
        if (not aim.clearing and not goal_line
                and math.hypot(goal_x - ball_xy[0], ball_xy[1]) < self.params.kick.shooting_range_m):
            shot = shot_window(ball_xy, goal_x, self._robots_in_field(pose), self._shot_direction_rad)
            self._shot_direction_rad = shot.direction_rad
            if ball_rel is not None and ball_rel.distance_m < skills.BOTTOM_CAMERA_BELOW_M:
                self._lining_up_s = self.now_s
            aim = goal_aim = Aim(*shot.aim_xy, False)
        elif not aim.clearing and not goal_line and ball_rel is not None and ball_rel.distance_m < self.params.kick.kick_past_near_m:
            shot = kick_past(ball_xy, goal_x, self._robots_in_field(pose), self._past_direction_rad)
            self._past_direction_rad = None if shot is None else shot.direction_rad
            if ball_rel.distance_m < skills.BOTTOM_CAMERA_BELOW_M:
                self._lining_up_s = self.now_s
            if shot is not None:
                aim = goal_aim = Aim(*shot.aim_xy, False)
        if ball_rel is not None and self._put_back_seen_xy is None and self.now_s - self._drop_in_at_s < self.params.throw_in.quick_touch_s:
            self._put_back_seen_xy = ball_xy
        quick = self._quick_touch(ball_xy)
        near = ball_rel is not None and ball_rel.distance_m < self.params.throw_in.quick_step_within_m
        if quick:
            way = pose.theta if near else math.atan2(ball_xy[1] - pose.y, ball_xy[0] - pose.x)
            aim = restart_aim(ball_xy, way, attack, self._restart_aim_rad)
            self._restart_aim_rad = math.atan2(aim.y - ball_xy[1], aim.x - ball_xy[0])
        if ball_rel is None:  # the team's ball (a teammate's, or a throw-in's spot): come at it from behind
            motion, walk = skills.walk_to(pose, skills.approach_pose(pose, ball_xy, aim.xy))
            return motion, walk, head
        stalled = self.stall.pushing(self.now_s, ball_xy, ball_rel.distance_m < STALL_NEAR_M)
        if stalled and push_allowed(pose.theta, attack) and self.now_s - self._own_goal_ahead_s >= self.params.kick.own_goal_memory_s:
            self.intention = Intention.KICK  # a stalled ball (agents.behavior.stall): walk on through it
            return Motion.WALK, skills.push(ball_rel), head
        heading_error = _heading_error(pose, ball_xy, aim.xy)
        steps = quick and near and abs(heading_error) <= self.params.throw_in.quick_step_rad
        if quick and not steps:
            tap = self._side_tap(pose, ball_rel, ball_xy, attack)
            if tap is not None:
                return Motion.WALK, tap, head
        if steps:
            motion, walk = self._quick_step(pose, ball_rel, ball_xy, goal_aim.xy, goal_x, heading_error, shot)
            return motion, walk, head
        beyond_m = self.params.throw_in.quick_go_behind_beyond_m if quick else skills.GO_BEHIND_BEYOND_M
        waypoint = skills.behind_ball(pose, ball_xy, aim.xy, beyond_m)
        if waypoint is not None:
            motion, walk = skills.walk_to(pose, waypoint)
            if motion is Motion.STAND:  # at the way round (near enough to it): on to the spot behind the ball
                motion, walk = skills.walk_to(pose, skills.behind_point(ball_xy, aim.xy))
            return motion, walk, head
        motion, walk = skills.chase(ball_rel, heading_error, foot_first=True)
        if motion.is_kick and quick:
            motion, walk = self._first_touch(pose, ball_rel, ball_xy, goal_aim.xy, goal_x, heading_error, shot)
            return motion, walk, head
        if motion.is_kick:
            if not self._may_kick(pose, ball_xy, goal_x, heading_error, aim.clearing, shot, goal_line):
                motion, walk = Motion.WALK, skills.orbit(ball_rel, heading_error or 0.3)
            else:
                self.intention = Intention.KICK
                if aim.push:  # at a goal line a kick gone wrong is a goal, or a miss: push the ball
                    motion, walk = Motion.WALK, skills.push(ball_rel)
        return motion, walk, head

    def _quick_touch(self, ball_xy: tuple[float, float]) -> bool:
        """Whether the ball, believed at ``ball_xy``, still waits for a throw-in's first touch: a throw-in
        less than ``throw_in.quick_touch_s`` ago, or less than ``throw_in.quick_untouched_s`` ago with the ball still
        where the robot first saw it after the put-back, and the ball still near the throw-in line. (A
        striker 0.4 m from the ball, lined up for its tap 10 s after the put-back, once turned to play
        it as in open play instead and touched it 4.6 s later.)"""
        if self._first_touch_s >= self._drop_in_at_s and self.now_s - self._first_touch_s >= self.params.throw_in.quick_push_s:
            return False  # its first touch is taken
        since_s = self.now_s - self._drop_in_at_s
        if since_s >= self.params.throw_in.quick_touch_s:
            seen = self._put_back_seen_xy
            untouched = seen is not None and math.dist(seen, ball_xy) <= self.params.throw_in.quick_untouched_m
            if since_s >= self.params.throw_in.quick_untouched_s or not untouched:
                return False
        line_y = FIELD.half_width - THROW_IN_INSET_M
        return abs(abs(ball_xy[1]) - line_y) < self.params.throw_in.quick_touch_band_m

    def _side_tap(self, pose: Pose2D, ball_rel: BallEstimate, ball_xy: tuple[float, float],
                  attack: float) -> tuple[float, float, float] | None:
        """A throw-in's first touch for a striker on the field side of the ball that comes at it about square
        to the side line or faces the line (``side_tap.approach_rad``): it stands facing the line with
        the ball beside a foot and side-steps into it, tapping it along the line (toward the opponent goal
        in the own half, or back from past the ball when the ball lies ``side_tap.back_tap_clear_m`` or more from
        the own goal line; else away from the robot's side), where walking round the ball to play it along
        the line took seconds. None when the robot comes at the ball otherwise, or stands past it the way
        the tap goes (``side_tap.beyond_m``). Chosen once per throw-in, the way included, from the ball's
        sighting and the robot's heading: a jump of the position estimate that carries the ball over the
        centre line must not turn the tap round (a striker once side-stepped 0.4 m past the ball for it)."""
        side = 1.0 if ball_xy[1] >= 0.0 else -1.0
        tapping = self.now_s - self._side_tap_s < self.params.side_tap.keep_s
        if self._side_tap_for_s != self._drop_in_at_s:  # not chosen yet for this throw-in
            dx, dy = _in_field(Pose2D(0.0, 0.0, pose.theta), ball_rel)  # the ball from the robot by its sighting
            if attack * ball_xy[0] < 0.0:  # own half: toward the opponent goal, or back from past the ball
                along = attack
                if attack * dx < -self.params.side_tap.beyond_m and FIELD.half_length + attack * ball_xy[0] >= self.params.side_tap.back_tap_clear_m:
                    along = -attack
            else:  # away from the robot's side
                along = attack if abs(dx) < 1e-6 else math.copysign(1.0, dx)
            inside = side * dy
            square = math.atan2(abs(dx), inside) <= self.params.side_tap.approach_rad
            facing = abs(math.remainder(side * math.pi / 2 - pose.theta, math.tau)) <= self.params.side_tap.approach_rad
            beyond = -along * dx  # how far the robot is past the ball the way the tap goes
            if inside < self.params.side_tap.forward_m / 2 or not (square or facing) or beyond > self.params.side_tap.beyond_m:
                return None
            self._side_tap_for_s = self._drop_in_at_s
            self._side_tap_along = along
        along = self._side_tap_along
        face = side * math.pi / 2
        left_of_face = -along * side  # +1: the tap goes to the robot's left when it faces the line
        face_error = math.remainder(face - pose.theta, math.tau)
        ball_side = left_of_face * self.params.side_tap.side_m
        if tapping or (abs(ball_rel.x - self.params.side_tap.forward_m) < self.params.side_tap.within_m
                       and abs(ball_rel.y - ball_side) < self.params.side_tap.within_m and abs(face_error) < self.params.side_tap.face_rad):
            self._side_tap_s = self.now_s
            self.intention = Intention.KICK
            if abs(ball_rel.y) < self.params.side_tap.touch_m and self._first_touch_s < self._drop_in_at_s:
                self._first_touch_s = self.now_s
            return skills.walk_command(self.params.side_tap.gain_per_s * (ball_rel.x - self.params.side_tap.forward_m),
                                       left_of_face * skills.WALK_HIGH[1], skills.TURN_GAIN_PER_S * face_error)
        if ball_rel.distance_m < self.params.side_tap.near_m:  # beside the ball first, then up to it: never walk into it
            lined_up = abs(ball_rel.y - ball_side) < self.params.side_tap.lined_up_m
            forward = self.params.side_tap.forward_m if lined_up else self.params.side_tap.clear_m
            return skills.walk_command(self.params.side_tap.gain_per_s * (ball_rel.x - forward),
                                       self.params.side_tap.gain_per_s * (ball_rel.y - ball_side),
                                       skills.TURN_GAIN_PER_S * face_error)
        spot = Pose2D(ball_xy[0] - along * self.params.side_tap.side_m, ball_xy[1] - side * self.params.side_tap.forward_m, face)
        return skills.walk_to(pose, spot)[1]

    def _quick_step(self, pose: Pose2D, ball_rel: BallEstimate, ball_xy: tuple[float, float],
                    goal_aim_xy: tuple[float, float], goal_x: float, heading_error: float,
                    shot: ShotWindow | None) -> tuple[Motion, tuple[float, float, float]]:
        """A throw-in's first touch near the ball, facing about the way the touch goes (``heading_error``):
        late, walk on through it (:meth:`_late_touch`); at the kick spot, the touch (:meth:`_first_touch`);
        else step there, turning to the aim on the way (:func:`agents.behavior.skills.step_to_ball`)."""
        if self._late_touch(ball_rel, heading_error):
            self.intention = Intention.KICK
            return Motion.WALK, skills.push(ball_rel)
        if skills.at_kick_spot(ball_rel):
            return self._first_touch(pose, ball_rel, ball_xy, goal_aim_xy, goal_x, heading_error, shot)
        return Motion.WALK, skills.step_to_ball(ball_rel, heading_error)

    def _late_touch(self, ball_rel: BallEstimate, heading_error: float) -> bool:
        """Whether a throw-in's first touch is late (``throw_in.late_touch_after_s``) and the striker, near the
        ball (:meth:`_quick_step`), comes at it along the touch's aim: then it walks on through the ball
        (from kicking distance on, that push is its first touch)."""
        if (self.now_s - self._drop_in_at_s < self.params.throw_in.late_touch_after_s or abs(ball_rel.bearing_rad) >= self.params.throw_in.late_touch_bearing_rad
                or abs(heading_error) > self.params.throw_in.quick_push_rad):
            return False
        if ball_rel.distance_m < skills.KICK_DISTANCE_M and self._first_touch_s < self._drop_in_at_s:
            self._first_touch_s = self.now_s
        return True

    def _first_touch(self, pose: Pose2D, ball_rel: BallEstimate, ball_xy: tuple[float, float],
                     goal_aim_xy: tuple[float, float], goal_x: float, heading_error: float,
                     shot: ShotWindow | None) -> tuple[Motion, tuple[float, float, float]]:
        """A throw-in's first touch at the ball (``heading_error``: to the touch's aim): the kick at the
        opponent goal if the robot may kick it, else a push (for ``throw_in.quick_push_s``) when facing the
        touch's aim, else the orbit to it."""
        goal_error = _heading_error(pose, ball_xy, goal_aim_xy)
        kick = (abs(goal_error) <= skills.KICK_HEADING_TOLERANCE_RAD
                and self._may_kick(pose, ball_xy, goal_x, goal_error, shot=shot))
        if not kick and abs(heading_error) > self.params.throw_in.quick_push_rad:
            return Motion.WALK, skills.orbit(ball_rel, heading_error)
        self.intention = Intention.KICK
        if self._first_touch_s < self._drop_in_at_s:
            self._first_touch_s = self.now_s
        return (skills.kick_for(ball_rel), skills.STILL) if kick else (Motion.WALK, skills.push(ball_rel))

    def _stand_up(self, obs: Observation) -> Motion:
        """The stand-up for the side it lies on (the accelerometer), once it lies still; lying on a flank
        the reading is unsure, so when a stand-up tried in this fall left it down, the other one."""
        if math.hypot(*obs.gyro_radps) > self.params.posture.settled_gyro_radps:  # still tumbling: the side it lies on is not known yet
            return Motion.STAND
        last = obs.last_motion
        if last is not None and last.is_stand_up and obs.last_motion_sequence > self._fall_sequence:
            return Motion.STAND_UP_FROM_FRONT if last is Motion.STAND_UP_FROM_BACK else Motion.STAND_UP_FROM_BACK
        return skills.stand_up_for(obs.accelerometer_mps2[0])

    def _robots_in_field(self, pose: Pose2D) -> list[tuple[float, float]]:
        """The robots it has seen (not the sonars' echoes: their bearing is vague) in the field frame (m)."""
        c, s = math.cos(pose.theta), math.sin(pose.theta)
        return [(pose.x + c * o.x_m - s * o.y_m, pose.y + s * o.x_m + c * o.y_m)
                for o in self.obstacles.obstacles() if o.kind is not ObstacleKind.UNKNOWN]

    def _just_kicked(self) -> bool:
        return self.now_s - self._kicked_s < self.params.kick.follow_kick_s

    def _contesting(self) -> bool:
        """The striker near its ball goes for it, whoever stands there."""
        ball = self._own_ball()
        return self.role is Role.STRIKER and ball is not None and ball.distance_m < self.params.kick.contest_ball_m

    def _may_kick(self, pose: Pose2D, ball_xy: tuple[float, float], goal_x: float, heading_error: float,
                  clearing: bool = False, shot: ShotWindow | None = None, goal_line: bool = False) -> bool:
        """Facing the opponent goal by the pose (in shooting range, ``shot``: within the open part of
        its mouth, :mod:`agents.behavior.shot_window`; the kick goes where the robot faces), not the
        own goal by the eyes, not out over a side line within a kick's roll; a clearing from the own
        goal mouth (:mod:`agents.behavior.aim`) only faces its aim (``heading_error``) and may go
        out: a throw-in there is no goal. On their goal line (``goal_line``) the push in need only
        pass the posts by :data:`agents.behavior.aim.POST_CLEARANCE_M`, and the push back out in
        front of their goal (a clearing there) is no danger to the own goal, 6 m away, whatever
        the eyes see."""
        if clearing:
            aligned = abs(heading_error) <= self.params.kick.align_rad
            return aligned and (goal_line or self.now_s - self._own_goal_ahead_s >= self.params.kick.own_goal_memory_s)
        on_target = _on_target(pose.theta, ball_xy, goal_x, POST_CLEARANCE_M if goal_line else self.params.kick.post_margin_m)
        if shot is not None:
            if not shot.allows(pose.theta):
                return False
        elif math.hypot(goal_x - ball_xy[0], ball_xy[1]) < self.params.kick.shooting_range_m:
            if not on_target:  # at the goal line: between the posts at least
                return False
        elif abs(heading_error) > self.params.kick.align_rad:
            return False
        if self.now_s - self._own_goal_ahead_s < self.params.kick.own_goal_memory_s:
            return False
        roll_y = ball_xy[1] + math.sin(pose.theta) * skills.KICK_ROLL_M
        if (not on_target and abs(roll_y) > FIELD.half_width - skills.SIDELINE_MARGIN_M
                and roll_y * math.sin(pose.theta) > 0):
            return False
        return True

    def _head(self, pose: Pose2D, ball_rel: BallEstimate | None, ball_field: BallEstimate | None
              ) -> tuple[float, float]:
        now = self.now_s
        sweeping, self._sweeping = self._sweeping, False  # set again below while the sweep goes on
        if self.locator.sigma_m > self.params.head.uncertain_m and now >= self._next_glance_s:
            self._glance_until_s = now + self.params.head.glance_s
            self._next_glance_s = now + self.params.head.glance_every_s
        if now < self._glance_until_s:
            return self._glance(pose)
        if ball_rel is not None and ball_rel.age_s <= self.params.head.track_ball_s:
            return self._look_at(ball_rel)
        if self._just_kicked():  # the ball rolled off ahead
            self._camera = CameraPosition.TOP
            return 0.0, skills.SCAN_PITCH_RAD
        if ball_rel is not None and ball_rel.distance_m < self.params.head.look_at_near_ball_m:  # not seen lately, but near: look
            yaw, pitch = self._look_at(ball_rel)  # there if a frame would show it (not behind a robot or the robot)
            if in_view(ball_rel, yaw, pitch, self._camera, self.obstacles.obstacles()):
                return yaw, pitch
        if ball_rel is None and ball_field is not None and now % self.params.head.search_cycle_s < self.params.head.look_for_team_ball_s:
            return self._look_at(_relative(pose, ball_field))
        self._sweeping = True
        if not sweeping:  # a new search: first a quick look near the feet
            self._near_sweep.restart(0.0, 1.0)
        if not self._near_sweep.swept:
            self._camera = CameraPosition.BOTTOM
            yaw = self._near_sweep.advance(skills.NEAR_SWEEP_RATE_RADPS)
            if self._near_sweep.swept:  # the wide sweep goes on from where the near one ended
                self._sweep.restart(yaw, self._near_sweep.direction)
            return yaw, skills.NEAR_SCAN_PITCH_RAD
        yaw = self._sweep.advance(skills.SEARCH_SCAN_RATE_RADPS)
        if self._sweep.reversals % 2 == 1:
            self._camera = CameraPosition.BOTTOM
            return yaw, skills.MID_SCAN_PITCH_RAD
        self._camera = CameraPosition.TOP
        return yaw, skills.SCAN_PITCH_RAD

    def _look_at(self, ball: BallEstimate) -> tuple[float, float]:
        """Head angles that centre a ball (torso frame), with the camera that sees it at its distance."""
        if ball.distance_m < skills.BOTTOM_CAMERA_BELOW_M:
            self._camera = CameraPosition.BOTTOM
        elif ball.distance_m > skills.TOP_CAMERA_BEYOND_M:
            self._camera = CameraPosition.TOP
        return skills.look_at(ball, self._camera)

    def _penalty_look(self) -> tuple[float, float]:
        """A penalty kicker's head while the kick is set: first at the goal straight ahead (top camera), where
        it sees the goalkeeper (:mod:`agents.behavior.shot_window`), then at the ball before its feet."""
        if self.now_s - self._state_since_s < self.params.head.penalty_look_s:
            self._camera = CameraPosition.TOP
            return 0.0, skills.SCAN_PITCH_RAD
        return self._look_at(BallEstimate(PENALTY_KICKER_BEHIND_BALL_M, 0.0, 0.0, 0.0, 0.0, 0.0))

    def _glance(self, pose: Pose2D) -> tuple[float, float]:
        """Look at the nearer goal's centre with the top camera (its posts are the surest landmarks)."""
        self._camera = CameraPosition.TOP
        best = None
        for goal_x in (-FIELD.half_length, FIELD.half_length):
            bearing = math.remainder(math.atan2(-pose.y, goal_x - pose.x) - pose.theta, math.tau)
            if best is None or abs(bearing) < abs(best):
                best = bearing
        return best, skills.SCAN_PITCH_RAD

    def _message(self, recovering: bool) -> TeamMessage:
        """This step's report; ``recovering``: lying or standing up, so teammates neither count it for the ball
        (its role and time to the ball are those of before the fall) nor take its sightings."""
        pose = self.locator.pose
        ball = None
        rel = self.ball.relative()
        if pose is not None and rel is not None:
            ball = self.ball.in_field((pose.x, pose.y, pose.theta), self.locator.sigma_m, self.locator.sigma_rad)
        self.sequence += 1
        return TeamMessage(
            player=self.player,
            sequence=self.sequence,
            pose=None if pose is None else (pose.x, pose.y, pose.theta),
            pose_sigma_m=self.locator.sigma_m,
            pose_sigma_rad=self.locator.sigma_rad,
            ball_xy=None if ball is None else (ball.x, ball.y),
            ball_velocity=(0.0, 0.0) if ball is None else (ball.vx, ball.vy),
            ball_sigma_m=0.0 if ball is None else ball.sigma_m,
            ball_age_s=0.0 if ball is None else ball.age_s,
            fallen=recovering,
            role=self.role,
            intention=self.intention,
            time_to_ball_s=self._time_to_ball_s,
        )

    def report(self) -> AgentReport | None:
        """What it believes beside its pose, for the match log (``match.protocol.AgentReporter``): its own
        ball and the team ball (field frame) as its last decision used them, its role, and the landmarks
        of its last camera frame if that frame is at most one camera period old. None before it has a pose."""
        if self.locator.pose is None:
            return None
        return AgentReport(
            ball_xy=self._believed_balls[0],
            team_ball_xy=self._believed_balls[1],
            role=None if self.role is Role.NONE else self.role.name.lower(),
            landmarks_seen=self._last_landmarks(),
        )

    def _last_landmarks(self) -> frozenset[int]:
        """The landmarks of the last frame if it is at most one camera period old (matched once per frame)."""
        step, percepts, pose = self._seen
        if pose is None or not 0 <= self.step - step <= CAMERA_EVERY_STEPS:
            return frozenset()
        if self._seen_landmarks[0] != step:
            self._seen_landmarks = (step, landmarks_seen(percepts, pose))
        return self._seen_landmarks[1]


def _on_target(heading_rad: float, ball_xy: tuple[float, float], goal_x: float, margin_m: float) -> bool:
    """Whether a ball kicked along ``heading_rad`` from ``ball_xy`` crosses the goal line at
    ``goal_x`` between the posts, ``margin_m`` inside their centres at least (field frame)."""
    toward = math.cos(heading_rad) * (goal_x - ball_xy[0])
    if toward <= 0.0:
        return False
    y_at_line = ball_xy[1] + math.tan(heading_rad) * (goal_x - ball_xy[0])
    return abs(y_at_line) < FIELD.goal_post_y - margin_m


def _shootout(obs: Observation) -> bool:
    return obs.game.secondary is SecondaryState.PENALTY_SHOOTOUT


def _heading_error(pose: Pose2D, ball_xy: tuple[float, float], aim_xy: tuple[float, float]) -> float:
    """The direction from the ball to ``aim_xy`` minus the robot's heading, normalized (field frame, rad)."""
    return math.remainder(math.atan2(aim_xy[1] - ball_xy[1], aim_xy[0] - ball_xy[0]) - pose.theta, math.tau)


def _into_field(ball_xy: tuple[float, float], margin_m: float) -> tuple[float, float]:
    """A ball believed at ``ball_xy`` (field frame), moved ``margin_m`` inside the lines if beyond them."""
    x_max, y_max = FIELD.half_length - margin_m, FIELD.half_width - margin_m
    return min(max(ball_xy[0], -x_max), x_max), min(max(ball_xy[1], -y_max), y_max)


def _throw_in_wait_pose(spot_xy: tuple[float, float], attack: float, back_m: float) -> Pose2D:
    """Where a striker waits for a ball going out (field frame): ``back_m`` on its own side of the spot
    the referee will put it on (on the throw-in line), facing the opponent goal."""
    return Pose2D(spot_xy[0] - attack * back_m, spot_xy[1], 0.0 if attack > 0 else math.pi)


def _relative(pose: Pose2D, ball: BallEstimate) -> BallEstimate:
    """A field-frame ball in the torso frame of ``pose``."""
    dx, dy = ball.x - pose.x, ball.y - pose.y
    c, s = math.cos(pose.theta), math.sin(pose.theta)
    return BallEstimate(c * dx + s * dy, -s * dx + c * dy, 0.0, 0.0, ball.sigma_m, ball.age_s)


def _in_field(pose: Pose2D, rel: BallEstimate) -> tuple[float, float]:
    """A robot-relative position (m) in the field frame through ``pose``."""
    c, s = math.cos(pose.theta), math.sin(pose.theta)
    return pose.x + c * rel.x - s * rel.y, pose.y + s * rel.x + c * rel.y


def _arc(vx: float, vy: float, omega: float, dt: float) -> Displacement:
    """The displacement of walking at (vx, vy, omega) for ``dt`` (robot frame at the start)."""
    turn = omega * dt
    if abs(turn) < 1e-9:
        return Displacement(vx * dt, vy * dt, 0.0)
    s, c = math.sin(turn), math.cos(turn)
    forward = (vx * s + vy * (c - 1.0)) / omega
    left = (vx * (1.0 - c) + vy * s) / omega
    return Displacement(forward, left, turn)
