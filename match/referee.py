"""The referee (the RobotStadium supervisor): a state machine that reads the world and moves things.

It never renders and never reads a wall clock: every timing is simulated time read from the
pitch after each control step. It reads the ball (position, last toucher) and the robots'
true poses, and it places robots and the ball as a human referee would. The rules it
applies are in :mod:`match.rules`; their facts are in docs/design/world.md section 4. In a penalty
shoot-out, :class:`match.shootout.PenaltyShootout` decides who kicks, where everyone stands
and how each kick ends; the referee changes the states, places things and logs the events.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

from match.errors import MatchConfigError
from match.events import DisallowedReason, EventKind, MatchEvent, ReplacedReason
from match.protocol.game_control import GameControlData, GameState, SecondaryState
from match.protocol.ids import AgentId, Side
from match.protocol.kickoff import kickoff_pose, legal_kickoff_position
from match.protocol.throw_in import throw_in_spot
from match.rules import (
    BallOut,
    OutKind,
    ball_out,
    goal_crossed,
    shift_off_robots,
    sideline_pose,
)
from match.shootout import PenaltyShootout, ShootoutTally
from world.ball import BallState
from world.field import FIELD, GoalColor, Pose2D
from world.teams import TeamColor

log = logging.getLogger(__name__)


class Pitch(Protocol):
    """What the referee needs of the world (:class:`world.world.World` provides it)."""

    time_s: float

    def ball(self) -> BallState: ...

    def robot_truth(self, robot_id: str): ...

    def place_robot(self, robot_id: str, pose: Pose2D) -> None: ...

    def place_ball(self, x: float, y: float, vx: float = 0.0, vy: float = 0.0) -> None: ...

    def set_team_color(self, robot_id: str, team: TeamColor) -> None: ...


@dataclass(frozen=True)
class RefereeConfig:
    """Timings in simulated seconds. ``fallen_limit_s`` None: fallen robots are left alone."""

    half_seconds: float = 600.0
    halves: int = 2  # 1: the match ends (or goes to its shoot-out) after the first half
    initial_seconds: float = 2.0
    ready_seconds: float = 15.0
    set_seconds: float = 3.0
    ball_out_wait_seconds: float = 2.0
    game_control_period_seconds: float = 0.5
    first_kickoff_color: TeamColor = TeamColor.BLUE  # kicks off each half (thesis 2.2.5)
    replace_off_carpet: bool = True
    fallen_limit_s: float | None = 30.0
    touch_gap_seconds: float = 0.2  # contacts further apart than this are separate touches
    shootout: bool = True
    shootout_kicks: int = 5
    sudden_death: bool = True
    max_sudden_death_rounds: int = 5  # then the match ends a draw
    shootout_attempt_seconds: float = 60.0
    shootout_rest_seconds: float = 2.0  # a touched ball at rest this long ends a kick

    def __post_init__(self) -> None:
        positive = ("half_seconds", "game_control_period_seconds", "shootout_attempt_seconds", "touch_gap_seconds")
        non_negative = ("initial_seconds", "ready_seconds", "set_seconds", "ball_out_wait_seconds", "shootout_rest_seconds")
        for name in positive + non_negative:
            value = getattr(self, name)
            ok = isinstance(value, (int, float)) and math.isfinite(value) and (value > 0 if name in positive else value >= 0)
            if not ok:
                raise MatchConfigError(f"referee {name} = {value!r}; expected a finite number {'> 0' if name in positive else '>= 0'}")
        if self.fallen_limit_s is not None and not (math.isfinite(self.fallen_limit_s) and self.fallen_limit_s > 0):
            raise MatchConfigError(f"referee fallen_limit_s = {self.fallen_limit_s!r}; expected a number > 0 or None")
        if isinstance(self.halves, bool) or self.halves not in (1, 2):
            raise MatchConfigError(f"referee halves = {self.halves!r}; expected 1 or 2")
        for name in ("shootout_kicks", "max_sudden_death_rounds"):
            value = getattr(self, name)
            if not isinstance(value, int) or value < (1 if name == "shootout_kicks" else 0):
                raise MatchConfigError(f"referee {name} = {value!r}; expected an integer >= {1 if name == 'shootout_kicks' else 0}")


@dataclass(frozen=True)
class RefereeUpdate:
    """What one referee update produced: new events and the sides that scored."""

    events: tuple[MatchEvent, ...]
    goals: tuple[Side, ...]


@dataclass
class _PendingOut:
    out: BallOut
    toucher: Side | None  # the side that touched the ball last
    since_s: float


class Referee:
    """Runs a match on ``pitch`` for the robots ``agents`` (robot id = ``str(agent)``)."""

    def __init__(self, pitch: Pitch, agents: Sequence[AgentId], config: RefereeConfig | None = None):
        self.pitch = pitch
        self.config = config or RefereeConfig()
        self.agents = tuple(agents)
        self._ids = {a: str(a) for a in self.agents}
        self._side_by_id = {str(a): a.side for a in self.agents}
        self.reset()

    # ---- public state -----------------------------------------------------------------

    def reset(self) -> None:
        """Back to the start of a match (call :meth:`start` next)."""
        self.state = GameState.INITIAL
        self.secondary = SecondaryState.NORMAL
        self.half = 1
        self.home_color = TeamColor.BLUE
        self.home_defends = GoalColor.BLUE
        self.kickoff: Side | None = None
        self.score = {Side.HOME: 0, Side.AWAY: 0}
        self.seconds_remaining = self.config.half_seconds
        self.events: list[MatchEvent] = []
        self.broadcast: GameControlData | None = None
        self._shootout: PenaltyShootout | None = None
        self._entered_s = 0.0
        self._last_update_s = 0.0
        self._next_broadcast_s = 0.0
        self._pending_out: _PendingOut | None = None
        self._drop_in: tuple[Side | None, float] | None = None  # the last throw-in this half: who put it out, when
        self._kickoff_shot_open = False
        self._ball_left_circle = False
        self._last_touch: tuple[str | None, float | None] = (None, None)
        self._fallen_since: dict[str, float] = {}
        self._new_events: list[MatchEvent] = []
        self._new_goals: list[Side] = []

    @property
    def shootout(self) -> ShootoutTally | None:
        """The penalty shoot-out's tally; None until a shoot-out began."""
        return None if self._shootout is None else self._shootout.tally

    def color_of(self, side: Side) -> TeamColor:
        return self.home_color if side is Side.HOME else self.home_color.other

    def defended_goal(self, side: Side) -> GoalColor:
        return self.home_defends if side is Side.HOME else self.home_defends.other

    def side_of_color(self, color: TeamColor) -> Side:
        return Side.HOME if self.home_color is color else Side.AWAY

    def game_control(self) -> GameControlData:
        """The game-control data as of now (broadcasts are snapshots of this)."""
        shootout = (0, 0)
        if self.shootout is not None:
            shootout = (self.shootout.goals(Side.HOME), self.shootout.goals(Side.AWAY))
        return GameControlData(
            state=self.state,
            secondary=self.secondary,
            kickoff=self.kickoff,
            score=(self.score[Side.HOME], self.score[Side.AWAY]),
            shootout_score=shootout,
            seconds_remaining=max(0.0, self.seconds_remaining),
            half=self.half,
            home_color=self.home_color,
            home_defends=self.home_defends,
            time_s=self.pitch.time_s,
            drop_in_team=None if self._drop_in is None else self._drop_in[0],
            seconds_since_drop_in=math.inf if self._drop_in is None else self.pitch.time_s - self._drop_in[1],
        )

    def holds(self, agent: AgentId) -> bool:
        """Whether the robot must stand still now (INITIAL, SET, FINISHED, or out of a shoot-out kick)."""
        if self.state in (GameState.INITIAL, GameState.SET, GameState.FINISHED):
            return True
        if self.secondary is SecondaryState.PENALTY_SHOOTOUT:
            return self._shootout.holds(self._ids[agent])
        return False

    @property
    def finished(self) -> bool:
        return self.state is GameState.FINISHED

    # ---- driving ----------------------------------------------------------------------

    def start(self) -> RefereeUpdate:
        """Begin the first half: robots at their kick-off positions, state INITIAL."""
        self.reset()
        now = self.pitch.time_s
        self._last_update_s = now
        self._next_broadcast_s = now
        self.kickoff = self.side_of_color(self.config.first_kickoff_color)
        for agent in self.agents:
            self.pitch.set_team_color(self._ids[agent], self.color_of(agent.side))
        self._enter(GameState.INITIAL, now)
        self._place_for_kickoff(only_illegal=False)
        self._maybe_broadcast(now)
        return self._flush()

    def play_on(self) -> RefereeUpdate:
        """Play begins now, where the robots and the ball stand (after :meth:`start`, for a start other than a
        kick-off): state PLAYING, no team kicks off, the kick-off-shot rule does not apply."""
        now = self.pitch.time_s
        self.kickoff = None
        self._kickoff_shot_open = False
        self._ball_left_circle = True
        self._pending_out = None
        self._enter(GameState.PLAYING, now)
        self.broadcast = self.game_control()
        return self._flush()

    def update(self) -> RefereeUpdate:
        """Judge the world after one control step; place things; return what happened."""
        now = self.pitch.time_s
        dt = max(0.0, now - self._last_update_s)
        self._last_update_s = now
        elapsed = now - self._entered_s
        cfg = self.config
        if self.state is GameState.INITIAL and elapsed >= cfg.initial_seconds - 1e-9:
            self._enter(GameState.READY, now)
        elif self.state is GameState.READY and elapsed >= cfg.ready_seconds - 1e-9:
            self._enter(GameState.SET, now)
            self._place_for_kickoff(only_illegal=True)
        elif self.state is GameState.SET and elapsed >= cfg.set_seconds - 1e-9:
            self._enter(GameState.PLAYING, now)
            self._begin_play(now)
        elif self.state is GameState.PLAYING:
            ball = self.pitch.ball()
            self._record_touch(ball)
            if self.secondary is SecondaryState.NORMAL:
                self._judge_play(ball, now, dt)
            else:
                self._judge_shootout_kick(ball, now)
        if self.state in (GameState.READY, GameState.PLAYING):
            self._watch_robots(now)
        self._maybe_broadcast(now)
        return self._flush()

    # ---- states -----------------------------------------------------------------------

    def _enter(self, state: GameState, now: float) -> None:
        self.state = state
        self._entered_s = now
        self._event(EventKind.STATE, state=state.name, half=self.half, secondary=self.secondary.name)

    def _begin_play(self, now: float) -> None:
        if self.secondary is SecondaryState.PENALTY_SHOOTOUT:
            self._shootout.begin(now)
            return
        self._kickoff_shot_open = True
        self._ball_left_circle = False
        self._pending_out = None
        self._event(EventKind.KICKOFF, team=self.kickoff.value if self.kickoff else None, half=self.half)

    def _judge_play(self, ball: BallState, now: float, dt: float) -> None:
        self.seconds_remaining -= dt
        if self.seconds_remaining <= 1e-9:
            self.seconds_remaining = 0.0
            self._end_half(now)
            return
        if math.hypot(ball.x, ball.y) > FIELD.center_circle_radius + FIELD.ball_radius:
            self._ball_left_circle = True
        if self._pending_out is not None:
            if now - self._pending_out.since_s >= self.config.ball_out_wait_seconds - 1e-9:
                self._throw_in()
            return
        goal = goal_crossed(ball.x, ball.y, ball.z)
        if goal is not None:
            self._goal(goal, ball, now)
            return
        out = ball_out(ball.x, ball.y, ball.z)
        if out is not None:
            toucher = self._side_of_robot(ball.last_toucher)
            self._pending_out = _PendingOut(out, toucher, now)
            self._event(EventKind.BALL_OUT, line=out.kind.value, x=round(out.x, 3), y=round(out.y, 3),
                        last_toucher=ball.last_toucher)

    def _goal(self, goal: GoalColor, ball: BallState, now: float) -> None:
        scorer = Side.HOME if self.defended_goal(Side.AWAY) is goal else Side.AWAY
        if self._kickoff_shot_open and scorer is self.kickoff:
            # Kick-off-shot rule: no goal before the ball left the circle and was touched
            # again by the kick-off team (or touched by the other team). Placed as an
            # end-line out by the attacking team.
            self._event(EventKind.GOAL_DISALLOWED, team=scorer.value, reason=DisallowedReason.KICKOFF_SHOT.value,
                        last_toucher=ball.last_toucher)
            out = BallOut(OutKind.END_LINE, ball.x, ball.y)
            self._pending_out = _PendingOut(out, scorer, now)
            return
        self.score[scorer] += 1
        self._new_goals.append(scorer)
        self._event(EventKind.GOAL, team=scorer.value, goal=goal.value, last_toucher=ball.last_toucher,
                    score={"home": self.score[Side.HOME], "away": self.score[Side.AWAY]})
        self.kickoff = scorer.other
        self._enter(GameState.READY, now)
        self._place_ball(0.0, 0.0)

    def _throw_in(self) -> None:
        pending = self._pending_out
        self._pending_out = None
        toucher_defends = None if pending.toucher is None else self.defended_goal(pending.toucher)
        spot = throw_in_spot(pending.out.x, pending.out.y, pending.out.kind is OutKind.END_LINE, toucher_defends)
        x, y = shift_off_robots(spot, self._robot_positions())
        self._place_ball(x, y)
        self._drop_in = (pending.toucher, self.pitch.time_s)
        self._event(EventKind.THROW_IN, x=round(x, 3), y=round(y, 3), line=pending.out.kind.value)

    def _end_half(self, now: float) -> None:
        if self.half == 1 and self.config.halves == 2:
            self._event(EventKind.HALF_TIME, score={"home": self.score[Side.HOME], "away": self.score[Side.AWAY]})
            self.half = 2
            self.home_color = self.home_color.other
            self.home_defends = self.home_defends.other
            for agent in self.agents:
                self.pitch.set_team_color(self._ids[agent], self.color_of(agent.side))
            self.seconds_remaining = self.config.half_seconds
            self.kickoff = self.side_of_color(self.config.first_kickoff_color)
            self._pending_out = None
            self._drop_in = None
            self._enter(GameState.INITIAL, now)
            self._place_for_kickoff(only_illegal=False)
        elif self.config.shootout and self.score[Side.HOME] == self.score[Side.AWAY]:
            self._start_shootout(now)
        else:
            self._finish(now)

    def _finish(self, now: float) -> None:
        self.kickoff = None
        winner = self._winner()
        self._event(EventKind.END, winner=winner.value if winner else None,
                    score={"home": self.score[Side.HOME], "away": self.score[Side.AWAY]},
                    shootout=None if self.shootout is None else {
                        "home": self.shootout.goals(Side.HOME), "away": self.shootout.goals(Side.AWAY)})
        self._enter(GameState.FINISHED, now)

    def _winner(self) -> Side | None:
        home, away = self.score[Side.HOME], self.score[Side.AWAY]
        if home != away:
            return Side.HOME if home > away else Side.AWAY
        return self.shootout.winner() if self.shootout is not None else None

    # ---- penalty shoot-out --------------------------------------------------------------

    def _start_shootout(self, now: float) -> None:
        cfg = self.config
        self.secondary = SecondaryState.PENALTY_SHOOTOUT
        tally = ShootoutTally(
            first=self.side_of_color(cfg.first_kickoff_color),
            kicks_each=cfg.shootout_kicks,
            sudden_death=cfg.sudden_death,
            max_sudden_death_rounds=cfg.max_sudden_death_rounds,
        )
        self._shootout = PenaltyShootout(self.agents, tally, cfg.shootout_attempt_seconds, cfg.shootout_rest_seconds)
        self._next_shootout_kick(now)

    def _next_shootout_kick(self, now: float) -> None:
        """SET for the next kick: the kicking team attacks the shoot-out goal, everyone placed."""
        attempt = self._shootout.next_kick()
        self.kickoff = attempt.side
        self.home_defends = attempt.home_defends
        self._enter(GameState.SET, now)
        placement = self._shootout.placement()
        self._place_ball(*placement.ball)
        for robot, pose in placement.robots:
            self.pitch.place_robot(robot, pose)

    def _judge_shootout_kick(self, ball: BallState, now: float) -> None:
        kick = self._shootout.judge(ball, now)
        if kick is None:
            return
        tally = self._shootout.tally
        if kick.scored:
            self._new_goals.append(kick.side)
        self._event(EventKind.SHOOTOUT_KICK, team=kick.side.value, kicker=kick.kicker, keeper=kick.keeper,
                    scored=kick.scored, reason=kick.reason.value,
                    shootout={"home": tally.goals(Side.HOME), "away": tally.goals(Side.AWAY)})
        if tally.is_over():
            self._finish(now)
        else:
            self._next_shootout_kick(now)

    # ---- robots and ball ----------------------------------------------------------------

    def _place_for_kickoff(self, only_illegal: bool) -> None:
        """Robots to their kick-off positions (all, or those not legal as SET begins); ball to the centre."""
        for agent in self.agents:
            robot = self._ids[agent]
            kicking = agent.side is self.kickoff
            defended = self.defended_goal(agent.side)
            if only_illegal:
                truth = self.pitch.robot_truth(robot)
                if not truth.fallen and legal_kickoff_position(truth.pose.x, truth.pose.y, defended, kicking):
                    continue
                self._event(EventKind.ROBOT_PLACED, robot=robot, x=round(truth.pose.x, 3), y=round(truth.pose.y, 3),
                            fallen=truth.fallen)
            self.pitch.place_robot(robot, kickoff_pose(agent.player, kicking, defended))
            self._fallen_since.pop(robot, None)
        self._place_ball(0.0, 0.0)

    def _watch_robots(self, now: float) -> None:
        """Falls are logged; robots off the carpet or down too long go back to the side line."""
        cfg = self.config
        in_shootout = self.secondary is SecondaryState.PENALTY_SHOOTOUT
        for agent in self.agents:
            robot = self._ids[agent]
            truth = self.pitch.robot_truth(robot)
            if truth.fallen and robot not in self._fallen_since:
                self._fallen_since[robot] = now
                self._event(EventKind.FALL, robot=robot, x=round(truth.pose.x, 3), y=round(truth.pose.y, 3))
            elif not truth.fallen:
                self._fallen_since.pop(robot, None)
            if in_shootout:
                continue
            reason = None
            if cfg.replace_off_carpet and not FIELD.is_on_carpet(truth.pose.x, truth.pose.y):
                reason = ReplacedReason.OFF_CARPET
            elif cfg.fallen_limit_s is not None and robot in self._fallen_since:
                if now - self._fallen_since[robot] >= cfg.fallen_limit_s - 1e-9:
                    reason = ReplacedReason.FALLEN
            if reason is not None:
                ball = self.pitch.ball()
                others = [p for r, p in self._robot_positions_by_id().items() if r != robot]
                pose = sideline_pose(self.defended_goal(agent.side), ball.y, others)
                self.pitch.place_robot(robot, pose)
                self._fallen_since.pop(robot, None)
                self._event(EventKind.ROBOT_REPLACED, robot=robot, reason=reason.value,
                            x=round(pose.x, 3), y=round(pose.y, 3))

    def _record_touch(self, ball: BallState) -> None:
        robot, when = ball.last_toucher, ball.last_touch_time_s
        if robot is None or when is None:
            return
        previous_robot, previous_time = self._last_touch
        if (robot, when) == (previous_robot, previous_time):
            return
        self._last_touch = (robot, when)
        if robot == previous_robot and previous_time is not None and when - previous_time <= self.config.touch_gap_seconds:
            return
        side = self._side_of_robot(robot)
        self._event(EventKind.TOUCH, robot=robot, x=round(ball.x, 3), y=round(ball.y, 3))
        if self._kickoff_shot_open and side is not None:
            if side is not self.kickoff or self._ball_left_circle:
                self._kickoff_shot_open = False

    def _place_ball(self, x: float, y: float) -> None:
        self.pitch.place_ball(x, y)

    def _robot_positions_by_id(self) -> dict[str, tuple[float, float]]:
        positions = {}
        for robot in self._ids.values():
            pose = self.pitch.robot_truth(robot).pose
            positions[robot] = (pose.x, pose.y)
        return positions

    def _robot_positions(self) -> list[tuple[float, float]]:
        return list(self._robot_positions_by_id().values())

    def _side_of_robot(self, robot: str | None) -> Side | None:
        return self._side_by_id.get(robot)

    # ---- output -----------------------------------------------------------------------

    def _maybe_broadcast(self, now: float) -> None:
        if now + 1e-9 >= self._next_broadcast_s:
            self.broadcast = self.game_control()
            period = self.config.game_control_period_seconds
            while self._next_broadcast_s <= now + 1e-9:
                self._next_broadcast_s += period

    def _event(self, kind: EventKind, **details) -> None:
        event = MatchEvent(self.pitch.time_s, kind, details)
        self.events.append(event)
        self._new_events.append(event)
        log.debug("%.2f s %s %s", event.time_s, kind.value, details)

    def _flush(self) -> RefereeUpdate:
        update = RefereeUpdate(tuple(self._new_events), tuple(self._new_goals))
        self._new_events.clear()
        self._new_goals.clear()
        return update
