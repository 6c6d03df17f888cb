"""What the simulator reads from a controller's pipe (match.answers): an answer of the kind a controller sends
is taken; anything else is refused at the cost of its header, runs nothing, and never waits for bytes."""

from __future__ import annotations

import os
import pickle
import struct
import sys
import tempfile
import time
from multiprocessing import Pipe

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from match.answers import MAX_ANSWER_BYTES, AnswerReader, AnswerRefused
from match.protocol import AgentReport, make_action, parse_action
from tests.user_policies import CODE_RAN, RunsCodeWhenRead

pytestmark = pytest.mark.skipif(sys.platform == "win32", reason="answers are read from a descriptor")

ACTION = parse_action("home_0", make_action("walk", walk=(0.1, 0.0, 0.2), radio=b"hi"))
REPORT = AgentReport(ball_xy=(1.0, 2.0), role="striker", landmarks_seen=[1, 3])
GOOD = ("act", 7, {"home_0": ACTION}, {"home_0": (0.5, -0.5, 1.0)}, {"home_0": REPORT},
        [("home_0", "RuntimeError: think", "policy.py:3")])


@pytest.fixture
def pipe():
    simulator, controller = Pipe()
    yield AnswerReader(simulator), controller
    simulator.close()
    controller.close()


def _forged_report(**fields) -> AgentReport:
    report = AgentReport()
    object.__setattr__(report, "__dict__", {**REPORT.__dict__, **fields})
    return report


def test_an_answer_as_a_controller_sends_it_is_taken(pipe) -> None:
    reader, controller = pipe
    controller.send(GOOD)
    answer = reader.read()
    assert answer is not None and (answer.kind, answer.sequence) == ("act", 7)
    assert answer.actions == {"home_0": ACTION} and answer.reports == {"home_0": REPORT}
    assert answer.faults == (("home_0", "RuntimeError: think", "policy.py:3"),)
    controller.send(("reset", {"home_0": None}, {}, []))
    assert reader.read().kind == "reset"


def test_a_200_mib_answer_is_refused_at_its_header(pipe) -> None:
    reader, controller = pipe
    os.write(controller.fileno(), struct.pack("!i", 200 << 20) + bytes(1000))  # what a sender writes first
    started = time.perf_counter()
    with pytest.raises(AnswerRefused, match=f"209715200 bytes; at most {MAX_ANSWER_BYTES}"):
        reader.read()
    assert time.perf_counter() - started < 0.05
    simulator, controller = Pipe()
    with simulator, controller:
        os.write(controller.fileno(), struct.pack("!i", -1) + struct.pack("!Q", 5 << 30))
        with pytest.raises(AnswerRefused, match="over 2 GiB"):
            AnswerReader(simulator).read()


def test_an_answer_that_would_run_code_is_refused_and_runs_nothing(pipe) -> None:
    reader, controller = pipe
    ran = os.path.join(tempfile.gettempdir(), CODE_RAN)
    if os.path.isdir(ran):
        os.rmdir(ran)
    controller.send(("act", 1, {"home_0": RunsCodeWhenRead()}, {}, {}, []))
    with pytest.raises(AnswerRefused, match="names posix.mkdir"):
        reader.read()
    assert not os.path.exists(ran)


def test_part_of_an_answer_is_kept_without_waiting_for_the_rest(pipe) -> None:
    reader, controller = pipe
    data = pickle.dumps(GOOD)
    message = struct.pack("!i", len(data)) + data
    for part in (message[:2], message[2:9], message[9:]):
        os.write(controller.fileno(), part)
        started = time.perf_counter()
        answer = reader.read()
        assert time.perf_counter() - started < 0.05
    assert answer is not None and answer.sequence == 7
    os.write(controller.fileno(), message[:30])
    assert reader.read() is None and reader.under_way
    controller.close()
    with pytest.raises(EOFError, match="in the middle of a message"):
        reader.read()


BAD = {
    "not a tuple": ["act", 1, {}, {}, {}, []],
    "unknown kind": ("think", {}, {}, []),
    "short": ("act", 1, {}, {}, []),
    "step a bool": ("act", True, {}, {}, {}, []),
    "actions a list": ("act", 1, [], {}, {}, []),
    "agent ids not text": ("act", 1, {0: None}, {}, {}, []),
    "estimate of 2": ("act", 1, {}, {"home_0": (0.0, 0.0)}, {}, []),
    "estimate of ints": ("act", 1, {}, {"home_0": (0, 0, 0)}, {}, []),
    "estimate huge": ("act", 1, {}, {"home_0": (10**400, 0.0, 0.0)}, {}, []),
    "report a dict": ("act", 1, {}, {}, {"home_0": {"role": "x"}}, []),
    "report nested": ("act", 1, {}, {}, {"home_0": _forged_report(ball_xy=[[[[1.0]]]])}, []),
    "report huge int": ("act", 1, {}, {}, {"home_0": _forged_report(ball_xy=(10**400, 0.0))}, []),
    "report extra field": ("act", 1, {}, {}, {"home_0": _forged_report(secret=1)}, []),
    "faults a tuple": ("act", 1, {}, {}, {}, ()),
    "too many faults": ("act", 1, {}, {}, {}, [("home_0", "x", None)] * 65),
    "fault too long": ("act", 1, {}, {}, {}, [("home_0", "x" * 5001, None)]),
    "fault not text": ("act", 1, {}, {}, {}, [("home_0", 3, None)]),
}


@pytest.mark.parametrize("message", list(BAD.values()), ids=list(BAD))
def test_a_message_not_of_an_answers_kind_is_refused(pipe, message) -> None:
    reader, controller = pipe
    controller.send(message)
    with pytest.raises(AnswerRefused, match="^an answer|^a message that is not an answer"):
        reader.read()


@pytest.mark.parametrize("data", [b"", b"\x80\x05garbage", pickle.dumps(GOOD)[:-3] + b"...", b"\x80\x05K\x01."])
def test_damaged_or_empty_answers_are_refused(pipe, data) -> None:
    reader, controller = pipe
    os.write(controller.fileno(), struct.pack("!i", len(data)) + data)
    with pytest.raises(AnswerRefused):
        reader.read()


@settings(max_examples=300, deadline=None, derandomize=True, database=None)
@given(data=st.one_of(st.binary(max_size=300),
                      st.tuples(st.integers(0, len(pickle.dumps(GOOD)) - 1), st.binary(min_size=1, max_size=8)).map(
                          lambda p: pickle.dumps(GOOD)[:p[0]] + p[1] + pickle.dumps(GOOD)[p[0] + len(p[1]):])))
def test_any_bytes_give_an_answer_or_its_refusal_and_nothing_else(data: bytes) -> None:
    """Random messages and valid answers with bytes overwritten: an Answer, or AnswerRefused; never another error."""
    simulator, controller = Pipe()
    with simulator, controller:
        os.write(controller.fileno(), struct.pack("!i", len(data)) + data)
        try:
            answer = AnswerReader(simulator).read()
        except AnswerRefused as error:
            assert "\n" not in str(error) and len(str(error)) < 400
        else:
            assert answer is not None and answer.kind in ("reset", "act")
