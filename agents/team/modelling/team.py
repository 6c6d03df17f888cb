"""Radio in: the teammates' messages into the team model (:mod:`agents.modelling.team_model`).

A packet that is not one of ours, or whose player is not its sender, is counted and ignored.
"""

from __future__ import annotations

from agents.modelling.team_model import TeamModel
from agents.observation import Observation
from agents.radio import DecodeStats, decode
from agents.team.modelling.representations import TeamState


class TeamListener:
    """Provides :class:`TeamState`."""

    def __init__(self, player: int):
        self.model = TeamModel(player)
        self.decode_stats = DecodeStats()

    def update(self, obs: Observation, now_s: float) -> TeamState:
        for packet in obs.packets:
            message = decode(packet.data, self.decode_stats)
            if message is not None and message.player == packet.sender:
                self.model.hear(message, now_s)
            elif message is not None:
                self.decode_stats.ignored["sender mismatch"] += 1
        return TeamState(self.model.teammates(now_s), self.model.silent_for_s(now_s))
