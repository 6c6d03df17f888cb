"""The team ball: the best of the own and the teammates' balls, else a throw-in's spot; and where it left.

The team model picks the freshest and surest estimate (:meth:`agents.modelling.team_model.TeamModel.team_ball`),
sightings from before the last throw-in left out; with none, the ball is believed at the throw-in's
spot for ``ball.drop_in_spot_s``. Tracked along: the last ball believed, where it first was believed
out of the field (the point on the line it crossed, :func:`agents.modelling.ball_out.leaving_point`),
and when it was last believed in (or no ball was).
"""

from __future__ import annotations

from agents.modelling.ball_model import BallEstimate
from agents.modelling.ball_out import BallOut, leaving_point, out_of_field
from agents.modelling.team_model import TeamModel
from agents.team.modelling.representations import BallModel, GameSituation, TeamBall, TeamState
from agents.team.params import TeamParams


class TeamBallProvider:
    """Provides :class:`TeamBall`; remembers where the believed ball left the field for the throw-in's spot."""

    def __init__(self, team: TeamModel, params: TeamParams):
        self.team, self.params = team, params
        self.last_ball_field: tuple[float, float] | None = None  # the last ball it believed in
        self.left_at: BallOut | None = None  # where the believed ball left the field, while it is believed out
        self.ball_in_s = 0.0  # when it last believed the ball in the field (or believed no ball)
        # the own ball and the team ball (field frame) as the last decision used them, for reports
        self.believed: tuple[tuple[float, float] | None, tuple[float, float] | None] = (None, None)

    def update(self, own: BallModel, game: GameSituation, now_s: float, team: TeamState | None = None) -> TeamBall:
        """``team``: the step's teammates (else read from the team model)."""
        since_drop_in = now_s - game.drop_in_at_s
        teammates = None if team is None else team.teammates
        best = self.team.team_ball(own.field, now_s, max_age_s=since_drop_in, teammates=teammates)
        team = None if best is None else best[0]
        spot = game.drop_in_spot_field
        if team is None and spot is not None and since_drop_in < self.params.ball.drop_in_spot_s:
            team = BallEstimate(*spot, 0.0, 0.0, self.params.ball.drop_in_spot_sigma_m, since_drop_in)
        if team is not None:
            self.last_ball_field = (team.x, team.y)
            if not out_of_field(self.last_ball_field):
                self.left_at = None
            elif self.left_at is None:  # its first belief out, on the line it crossed
                self.left_at = leaving_point(team)
        believed = own.field if own.field is not None else team
        if believed is None or not out_of_field((believed.x, believed.y)):
            self.ball_in_s = now_s
        self.believed = (None if own.field is None else (own.field.x, own.field.y),
                         None if team is None else (team.x, team.y))
        return TeamBall(team)

    def put_back(self) -> None:
        """The referee put the ball back: it is no longer out."""
        self.left_at = None
