"""Team radio: one emitter and one receiver per robot (RobotStadium style, SPL limits).

A packet sent in control step ``k`` reaches the sender's teammates in the observation of
step ``k + 1`` (plus the configured latency, rounded up to whole steps), never the other
team. Each robot may send one packet per ``min_interval_s``; a packet over that budget
is dropped, counted, and reported to its sender. Loss and range are optional and seeded.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from match.errors import MatchConfigError, RadioPacketError
from match.protocol.ids import AgentId
from match.protocol.packets import INBOX_CAPACITY, MAX_PACKET_BYTES


@dataclass(frozen=True)
class RadioConfig:
    min_interval_s: float = 0.2  # send budget: one packet per 0.2 s per robot
    latency_s: float = 0.0  # delay on top of the one step every packet takes
    loss_probability: float = 0.0  # each receiver misses a packet with this probability
    range_m: float | None = None  # None: the whole field

    def __post_init__(self) -> None:
        checks = {
            "min_interval_s": self.min_interval_s >= 0,
            "latency_s": self.latency_s >= 0,
            "loss_probability": 0 <= self.loss_probability <= 1,
            "range_m": self.range_m is None or self.range_m > 0,
        }
        for name, ok in checks.items():
            value = getattr(self, name)
            if value is not None and not (isinstance(value, (int, float)) and math.isfinite(value)):
                ok = False
            if not ok:
                raise MatchConfigError(f"radio {name} = {value!r} is outside its range")


@dataclass(frozen=True)
class RadioMessage:
    """A packet as received: who sent it (a teammate) and when (simulated seconds)."""

    sender: AgentId
    data: bytes
    sent_s: float


@dataclass
class RadioCounts:
    sent: int = 0  # accepted by the emitter
    delivered: int = 0  # packet-receiver pairs that arrived
    dropped_budget: int = 0  # over the send budget
    lost: int = 0  # packet-receiver pairs lost at random
    out_of_range: int = 0
    inbox_overflow: int = 0  # arrived when the inbox was full

    def to_json(self) -> dict:
        return dict(self.__dict__)


@dataclass
class _InFlight:
    message: RadioMessage
    due_step: int


@dataclass
class Radio:
    agents: Sequence[AgentId]
    config: RadioConfig = field(default_factory=RadioConfig)
    step_s: float = 0.04

    def __post_init__(self) -> None:
        self.agents = tuple(self.agents)
        self.reset(np.random.default_rng(0))

    def reset(self, rng: np.random.Generator) -> None:
        self.rng = rng
        self.counts = RadioCounts()
        self._in_flight: list[_InFlight] = []
        self._last_sent_s: dict[AgentId, float] = {}
        self._unreported_drops = {a: 0 for a in self.agents}

    @property
    def _latency_steps(self) -> int:
        return math.ceil(self.config.latency_s / self.step_s - 1e-9)

    def send(self, sender: AgentId, data: bytes, now_s: float, step: int) -> bool:
        """Hand ``data`` to the emitter in control step ``step``; False if over budget (dropped)."""
        if sender not in self._unreported_drops:
            raise ValueError(f"radio sender {sender} is not one of {[str(a) for a in self.agents]}")
        if not isinstance(data, (bytes, bytearray)) or len(data) > MAX_PACKET_BYTES:
            shown = f"<{len(data)} bytes>" if isinstance(data, (bytes, bytearray)) else data
            raise RadioPacketError(str(sender), "radio", shown, f"bytes of length at most {MAX_PACKET_BYTES}")
        if not data:
            return True
        last = self._last_sent_s.get(sender)
        if last is not None and now_s - last < self.config.min_interval_s - 1e-9:
            self.counts.dropped_budget += 1
            self._unreported_drops[sender] += 1
            return False
        self._last_sent_s[sender] = now_s
        self.counts.sent += 1
        message = RadioMessage(sender, bytes(data), now_s)
        self._in_flight.append(_InFlight(message, step + 1 + self._latency_steps))
        return True

    def deliver(
        self, step: int, positions: Mapping[AgentId, tuple[float, float]] | None = None
    ) -> dict[AgentId, list[RadioMessage]]:
        """The inboxes of control step ``step``: packets due by then, to teammates only."""
        inboxes: dict[AgentId, list[RadioMessage]] = {a: [] for a in self.agents}
        due = [f for f in self._in_flight if f.due_step <= step]
        if not due:
            return inboxes
        self._in_flight = [f for f in self._in_flight if f.due_step > step]
        cfg = self.config
        for flight in due:
            message = flight.message
            for receiver in self.agents:
                if receiver.side is not message.sender.side or receiver == message.sender:
                    continue
                if cfg.range_m is not None and positions is not None:
                    (sx, sy), (rx, ry) = positions[message.sender], positions[receiver]
                    if math.hypot(sx - rx, sy - ry) > cfg.range_m:
                        self.counts.out_of_range += 1
                        continue
                if cfg.loss_probability > 0 and self.rng.random() < cfg.loss_probability:
                    self.counts.lost += 1
                    continue
                if len(inboxes[receiver]) >= INBOX_CAPACITY:
                    self.counts.inbox_overflow += 1
                    continue
                inboxes[receiver].append(message)
                self.counts.delivered += 1
        return inboxes

    def take_drops(self, agent: AgentId) -> int:
        """Packets of ``agent`` dropped over budget since the last call (then reset to 0)."""
        drops = self._unreported_drops[agent]
        self._unreported_drops[agent] = 0
        return drops
