"""Team radio: next-step delivery to teammates only, send budget, size limit, seeded loss."""

from __future__ import annotations

import numpy as np
import pytest

from match.errors import MatchConfigError, RadioPacketError
from match.protocol.ids import AgentId, Side, roster
from match.radio import Radio, RadioConfig

HOME_0, HOME_1, HOME_2 = (AgentId(Side.HOME, p) for p in range(3))
AWAY_0 = AgentId(Side.AWAY, 0)


def make_radio(**config) -> Radio:
    radio = Radio(roster(3, 2), RadioConfig(**config), step_s=0.04)
    radio.reset(np.random.default_rng(5))
    return radio


def test_packet_reaches_teammates_at_the_next_step_and_never_the_other_team():
    radio = make_radio()
    assert radio.send(HOME_0, b"hello", now_s=0.0, step=0)
    assert all(not inbox for inbox in radio.deliver(0).values())  # not in the same step
    inboxes = radio.deliver(1)
    assert [m.data for m in inboxes[HOME_1]] == [b"hello"] and [m.data for m in inboxes[HOME_2]] == [b"hello"]
    assert inboxes[HOME_0] == [] and inboxes[AWAY_0] == []
    assert inboxes[HOME_1][0].sender == HOME_0
    assert all(not inbox for inbox in radio.deliver(2).values())  # delivered once
    assert radio.counts.sent == 1 and radio.counts.delivered == 2


def test_send_budget_drops_and_reports_once():
    radio = make_radio(min_interval_s=0.2)
    assert radio.send(HOME_0, b"a", 0.0, 0)
    assert not radio.send(HOME_0, b"b", 0.04, 1)
    assert not radio.send(HOME_0, b"c", 0.16, 4)
    assert radio.send(HOME_0, b"d", 0.2, 5)
    assert radio.send(HOME_1, b"e", 0.04, 1)  # the budget is per robot
    assert radio.counts.dropped_budget == 2
    assert radio.take_drops(HOME_0) == 2 and radio.take_drops(HOME_0) == 0


def test_oversize_or_wrong_type_packet_is_a_typed_error_and_changes_nothing():
    radio = make_radio()
    with pytest.raises(RadioPacketError, match="129 bytes"):
        radio.send(HOME_0, b"x" * 129, 0.0, 0)
    with pytest.raises(RadioPacketError, match="bytes"):
        radio.send(HOME_0, "text", 0.0, 0)
    assert radio.counts.sent == 0 and radio.send(HOME_0, b"x" * 128, 0.0, 0)


def test_latency_delays_by_whole_steps():
    radio = make_radio(latency_s=0.1)  # 3 steps of 40 ms on top of the one step
    radio.send(HOME_0, b"late", 0.0, 0)
    assert not any(radio.deliver(step)[HOME_1] for step in range(1, 4))
    assert [m.data for m in radio.deliver(4)[HOME_1]] == [b"late"]


def test_loss_is_seeded():
    def lost_pattern(seed: int) -> list[bool]:
        radio = Radio(roster(2, 1), RadioConfig(loss_probability=0.5, min_interval_s=0.0))
        radio.reset(np.random.default_rng(seed))
        pattern = []
        for step in range(60):
            radio.send(HOME_0, b"p", step * 0.04, step)
            pattern.append(bool(radio.deliver(step + 1)[HOME_1]))
        return pattern

    assert lost_pattern(1) == lost_pattern(1)
    assert lost_pattern(1) != lost_pattern(2)
    assert 10 < sum(lost_pattern(1)) < 50


def test_range_limits_delivery():
    radio = make_radio(range_m=2.0)
    radio.send(HOME_0, b"near", 0.0, 0)
    positions = {HOME_0: (0.0, 0.0), HOME_1: (1.0, 0.0), HOME_2: (2.5, 0.0), AWAY_0: (0.5, 0.0), AgentId(Side.AWAY, 1): (0, 0)}
    inboxes = radio.deliver(1, positions)
    assert inboxes[HOME_1] and not inboxes[HOME_2]
    assert radio.counts.out_of_range == 1


def test_bad_radio_settings_are_refused():
    with pytest.raises(MatchConfigError, match="loss_probability"):
        RadioConfig(loss_probability=1.5)
    with pytest.raises(MatchConfigError, match="range_m"):
        RadioConfig(range_m=0.0)
