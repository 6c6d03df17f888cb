"""Open play's situation: a ball going out and where it comes back, and whether a kick-off was played.

Who put a ball out is guessed from who last meant to touch it: this robot (its last intention was to
kick or push) or a teammate whose fresh message (``ball_out.teammate_kick_heard_s``) says it kicks;
a ball believed going out or out for less than ``ball_out.out_wait_s`` (the referee puts it back 2 s
after it left; believed out longer, it is in) comes back on the rule's spot
(:mod:`agents.modelling.ball_out`). A kick-off's ball is played once believed ``kickoff.played_m``
from the centre spot.
"""

from __future__ import annotations

import math

from agents.modelling.ball_out import OWN_TOUCH_MEMORY_S, expected_spot, leaving_point
from agents.modelling.ball_model import BallEstimate
from agents.radio import Intention
from agents.team.modelling.representations import GameSituation, PlayStatus, TeamState
from agents.team.params import TeamParams
from match.protocol import GoalColor


class RestartProvider:
    """Provides :class:`PlayStatus` (in PLAYING, while the robot stands and no kick plays)."""

    def __init__(self, params: TeamParams):
        self.params = params
        self._own_touch_s = -math.inf  # when it or a teammate last meant to kick or push the ball
        self._kickoff_played_s = math.inf
        self._kickoff_state_since_s = -math.inf  # the state (by its start) that kick-off time belongs to
        self._status = PlayStatus(None, math.inf)

    def update(self, ball: BallEstimate | None, ball_in_s: float, game: GameSituation, team: TeamState,
               last_intention: Intention, now_s: float) -> PlayStatus:
        """``ball``: the team ball (field frame); ``ball_in_s``: when it was last believed in the field."""
        if last_intention is Intention.KICK or any(
                m.message.intention is Intention.KICK and m.age_s < self.params.ball_out.teammate_kick_heard_s
                for m in team.teammates):
            self._own_touch_s = now_s
        restart = None if game.shootout else self.expected_restart(ball, ball_in_s, game.defended, now_s)
        if self._kickoff_state_since_s != game.state_since_s:  # a new state: its kick-off not played yet
            self._kickoff_played_s, self._kickoff_state_since_s = math.inf, game.state_since_s
        if ball is not None and math.hypot(ball.x, ball.y) >= self.params.kickoff.played_m:
            self._kickoff_played_s = min(self._kickoff_played_s, now_s)
        if self._status.restart_field != restart or self._status.kickoff_played_s != self._kickoff_played_s:
            self._status = PlayStatus(restart, self._kickoff_played_s)  # else the last one serves again
        return self._status

    def expected_restart(self, ball: BallEstimate | None, ball_in_s: float, defended: GoalColor,
                         now_s: float) -> tuple[float, float] | None:
        """Where the referee will put back the team's ball (field frame) if it is going out or just out."""
        if ball is None or now_s - ball_in_s >= self.params.ball_out.out_wait_s:
            return None
        out = leaving_point(ball)
        if out is None:
            return None
        return expected_spot(out, now_s - self._own_touch_s < OWN_TOUCH_MEMORY_S, defended)

    def note_own_touch(self, now_s: float) -> None:
        """The own team touched the ball at ``now_s`` (for tests and drills that set the scene)."""
        self._own_touch_s = now_s
