"""The other team's kick-off: the defender and the supporter hold their places, out of the kick's lane.

Until the ball is believed played (``kickoff.played_m`` from the centre spot) and ``kickoff.lane_s``
after, within ``kickoff.free_s`` of the kick-off (the rules' free time). Walking up from its kick-off
place at once, a defender crossed the lane of the kick past the striker, 1.5 m away a second later, and
its legs turned the ball toward its own goal.
"""

from __future__ import annotations

from agents.radio import Intention
from agents.team.behavior.requests import MotionRequest, STAND
from agents.team.modelling.representations import WorldModel
from agents.team.params import TeamParams
from match.protocol import KickOff

HOLD = MotionRequest(STAND.motion, STAND.walk, Intention.POSITION)


def holds_lane(world: WorldModel, params: TeamParams) -> bool:
    if world.game.kickoff is not KickOff.OPPONENT:
        return False
    now = world.now_s
    return (now - world.game.state_since_s < params.kickoff.free_s
            and now - world.play.kickoff_played_s < params.kickoff.lane_s)
