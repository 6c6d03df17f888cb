"""The game situation: state, kick-off, shoot-out, throw-ins, and the resets they call for.

The self-locator is reset at the kick-off pose (thesis 5.5) in INITIAL, and in SET when the robot
lay fallen or believes it stood where it may not stay (the referee placed it); in a penalty
shoot-out at the kicker's or goalkeeper's place when a kick is set. After a throw-in (the
game-control data's drop-in) the balls seen before it are forgotten, and the rule gives where the
ball is now, from where the ball was believed to leave the field (its first belief out, on the line
it crossed; else where it was last believed) and who put it out: a kicked ball rolls on beyond the line
until the put-back, and the spot taken from where it was last seen can lie far from the referee's.
"""

from __future__ import annotations

import math

from agents.modelling.ball_model import BallModel
from agents.modelling.self_locator import SelfLocator
from agents.observation import Observation
from agents.team.modelling.team_ball import TeamBallProvider
from agents.team.modelling.representations import GameSituation
from match.protocol import (
    DropIn,
    GameState,
    GoalColor,
    KickOff,
    SecondaryState,
    kickoff_pose,
    legal_kickoff_position,
    penalty_pose,
    throw_in_spot,
)
from world.field import FIELD


class GameProvider:
    """Provides :class:`GameSituation`, resetting the self-locator and the ball model as the game asks."""

    def __init__(self, player: int, locator: SelfLocator, ball: BallModel, ball_out: TeamBallProvider):
        self.player, self.locator, self.ball, self.ball_out = player, locator, ball, ball_out
        self._state: GameState | None = None
        self._state_since_s = 0.0
        self._defended: GoalColor | None = None
        self._drop_in_since_s = math.inf  # the last broadcast's seconds since a throw-in
        self.drop_in_at_s = -math.inf
        self._drop_in_spot: tuple[float, float] | None = None
        self._key: tuple | None = None  # the fields of the last situation provided
        self._situation: GameSituation | None = None

    def update(self, obs: Observation, now_s: float, own_goal_ahead_s: float) -> GameSituation:
        game = obs.game
        if game.state is not self._state:
            self._state_since_s = now_s
        since = game.seconds_since_drop_in
        if since < self._drop_in_since_s:  # the count started again: a new throw-in
            self._throw_in(obs, now_s, since)
        self._drop_in_since_s = since
        shootout = game.secondary is SecondaryState.PENALTY_SHOOTOUT
        if shootout:
            self._reset_for_penalty(obs)
        else:
            self._reset_for_kickoff(obs)
        self._state, self._defended = game.state, game.defended_goal
        key = (game.state, self._state_since_s, game.kickoff, shootout, game.defended_goal, game.drop_in_team,
               self.drop_in_at_s, self._drop_in_spot, own_goal_ahead_s)
        if key != self._key:  # most steps change none of it: the last snapshot's value serves again
            self._key, self._situation = key, GameSituation(*key)
        return self._situation

    def _reset_for_penalty(self, obs: Observation) -> None:
        state, defended = obs.game.state, obs.game.defended_goal
        set_anew = state is GameState.SET and (self._state is not GameState.SET or defended is not self._defended)
        if set_anew or not self.locator.has_pose:
            self.locator.reset(penalty_pose(obs.game.kickoff is KickOff.OWN_TEAM, defended))
            self.ball.reset()

    def _reset_for_kickoff(self, obs: Observation) -> None:
        state, defended = obs.game.state, obs.game.defended_goal
        kicking = obs.game.kickoff is KickOff.OWN_TEAM
        if state is GameState.INITIAL and (self._state is not GameState.INITIAL or defended is not self._defended):
            self.locator.reset(kickoff_pose(self.player, kicking, defended))
            self.ball.reset()
        elif state is GameState.SET and self._state is not GameState.SET:
            # The referee put it at its kick-off pose if it lay fallen or stood where it may not stay.
            pose = self.locator.pose
            if pose is None or obs.fallen or not legal_kickoff_position(pose.x, pose.y, defended, kicking):
                self.locator.reset(kickoff_pose(self.player, kicking, defended))
        elif not self.locator.has_pose:
            self.locator.reset(kickoff_pose(self.player, kicking, defended))

    def _throw_in(self, obs: Observation, now_s: float, since_s: float) -> None:
        """The referee put the ball back ``since_s`` ago: every sighting from before is of a ball that is gone."""
        self.drop_in_at_s = now_s - since_s
        if self.ball.age_s > since_s:
            self.ball.reset()
        self._drop_in_spot = None
        defended = obs.game.defended_goal
        toucher_defends = {DropIn.OWN_TEAM: defended, DropIn.OPPONENT: defended.other}.get(obs.game.drop_in_team)
        left, last = self.ball_out.left_at, self.ball_out.last_ball_field
        if left is not None:  # where it was believed to leave, not where it rolled on to
            self._drop_in_spot = throw_in_spot(left.x, left.y, left.over_end_line, toucher_defends)
        elif last is not None:
            bx, by = last
            self._drop_in_spot = throw_in_spot(bx, by, abs(bx) > FIELD.half_length, toucher_defends)
        self.ball_out.put_back()
