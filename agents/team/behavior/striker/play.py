"""The striker option: its ball, then the first card that plays it.

Without any ball it searches (:mod:`.search`); a ball going out is waited for behind the spot it comes
back on (:mod:`agents.team.behavior.set_plays.ball_out`); a ball lying at the own goal line in front of
the goal is held off (no way behind it but through the goal, :mod:`agents.behavior.tactics.goal_line`).
Else it aims (:mod:`.targeting`) and plays the cards in order: the team's ball and a stalled one
(:mod:`.open_play`), a ball beside the own goal at its line cleared toward the side line
(:mod:`agents.team.behavior.set_plays.clear_line`), the throw-in's first touches
(:mod:`agents.team.behavior.set_plays`) and open play (:mod:`.open_play`). The goalkeeper clears a ball
near it with the same option.
"""

from __future__ import annotations

from agents.behavior.tactics.goal_line import at_own_goal_line, hold_off
from agents.modelling.ball_out import out_of_field
from agents.radio import Intention
from agents.team.behavior.framework import deck
from agents.team.behavior.geometry import heading_error, in_field, into_field
from agents.team.behavior.requests import MotionRequest
from agents.team.behavior.set_plays.ball_out import wait_for_restart
from agents.team.behavior.set_plays.clear_line import ClearLine
from agents.team.behavior.set_plays.first_touch import QuickStep
from agents.team.behavior.set_plays.side_tap import SideTap
from agents.team.behavior.set_plays.throw_in import ThrowInTouch
from agents.team.behavior.striker.context import StrikeContext
from agents.team.behavior.striker.open_play import ApproachTeamBall, Chase, GoBehind, StalledPush
from agents.team.behavior.striker.search import search
from agents.team.behavior.striker.targeting import Targeting
from agents.team.modelling.representations import WorldModel
from agents.team.params import TeamParams
from world.field import FIELD


class Striker:
    """Plays the ball; ``lining_up``: whether this step's aim asked for the top camera's frames."""

    def __init__(self, params: TeamParams):
        self.params = params
        self.targeting = Targeting(params)
        self.throw_in = ThrowInTouch(params)
        self.side_tap = SideTap(params, self.throw_in)
        self.cards = (ApproachTeamBall(), StalledPush(params), ClearLine(params, self.throw_in), self.side_tap,
                      QuickStep(params, self.throw_in), GoBehind(params), Chase(params, self.throw_in))
        self.lining_up = False

    def play(self, world: WorldModel, following_kick: bool, looking_near_feet: bool,
             restart: tuple[float, float] | None = None) -> MotionRequest:
        """``restart``: where the referee will put back a ball going out (field frame)."""
        self.lining_up = False
        ball_rel, team_ball = world.ball.recent, world.team_ball.field
        if ball_rel is None and team_ball is None:
            return search(self.params, following_kick, looking_near_feet)
        pose, attack = world.robot.pose_field, world.game.attack
        if restart is not None:
            return wait_for_restart(pose, restart, attack, self.params.ball_out.throw_in_wait_back_m)
        ball_xy = (team_ball.x, team_ball.y) if ball_rel is None else in_field(pose, ball_rel)
        if at_own_goal_line(ball_xy, attack):  # no way behind it but through the goal: hold off
            return MotionRequest.of(hold_off(pose, ball_xy, attack), Intention.POSITION)
        if out_of_field(ball_xy):  # not put back: it lies on a line, believed a little beyond it
            ball_xy = into_field(ball_xy, self.params.ball.in_field_margin_m)
        return deck(self.cards, self._context(world, ball_xy))

    def _context(self, world: WorldModel, ball_xy: tuple[float, float]) -> StrikeContext:
        pose, attack, ball_rel = world.robot.pose_field, world.game.attack, world.ball.recent
        goal_x = FIELD.half_length * attack
        target = self.targeting.target(ball_xy, ball_rel, attack, pose.y, goal_x, world.obstacles.robots_field)
        self.lining_up = target.lining_up
        self.throw_in.follow(world)
        self.throw_in.note_ball(world, ball_rel, ball_xy)
        quick = self.throw_in.waits(world, ball_xy)
        near = ball_rel is not None and ball_rel.distance_m < self.params.throw_in.quick_step_within_m
        aim = self.throw_in.aim(pose, ball_xy, near, attack) if quick else target.aim
        error = heading_error(pose, ball_xy, aim.xy)
        return StrikeContext(world, pose, ball_rel, ball_xy, attack, goal_x, aim, target.aim, target.shot,
                             target.goal_line, quick, near, error)


