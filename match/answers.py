"""What the simulator reads from a controller process: one answer, bounded in size, time and kind.

A controller process runs policies the simulator does not trust, and a policy can reach its
process's end of the pipe. So an answer is not read with ``Connection.recv`` (which reads a
message of any length and unpickles anything, code included) but with an :class:`AnswerReader`:

- its length (the :mod:`multiprocessing.connection` framing: a 4-byte big-endian length) is
  checked against :data:`MAX_ANSWER_BYTES` before any byte of it is read: a huge message is
  refused at the cost of its header, and never crosses the pipe;
- its bytes are read as they arrive, never waited for: one that sends part of a message and
  stops holds nobody (it is still busy, and the hang limit of :mod:`match.controllers` ends it);
- it is unpickled with only the classes an answer holds (:data:`ANSWER_CLASSES`), so reading it
  runs nothing of the controller's choosing;
- its shape is checked (:class:`Answer`): the reports are the plain values the controller's
  own checks make, the faults a bounded list of short texts.

Anything else raises :class:`AnswerRefused`, naming what was wrong; the controller is then
stopped and restarted (:mod:`match.controllers`).
"""

from __future__ import annotations

import io
import os
import pickle
import struct
import sys
from collections.abc import Mapping
from dataclasses import dataclass
from multiprocessing.connection import Connection, wait

from match.protocol.actions import Action
from match.protocol.policy import AgentReport
from match.protocol.spaces import CameraChoice
from world.motions import Motion

MAX_ANSWER_BYTES = 1 << 20  # an answer of a whole team with every fault is a few kB
MAX_FAULTS = 64  # faults in one answer (a few per robot at most)
MAX_FAULT_CHARS = 5000  # a fault's text or its place (file:line)
ANSWER_CLASSES = {(cls.__module__, cls.__qualname__): cls
                  for cls in (Action, Motion, CameraChoice, AgentReport, frozenset)}
KINDS = {"reset": 4, "act": 6}  # message kind -> its length: (kind, [sequence, actions,] estimates, reports, faults)
_HEADER = struct.Struct("!i")


class AnswerRefused(Exception):
    """An answer the simulator does not take: too long, or not of an answer's kind (its message names which)."""


@dataclass(frozen=True)
class Answer:
    """One message of a controller: ``kind`` ``reset`` (its policies were reset; ``sequence`` 0, no actions)
    or ``act`` (the actions of the step it was asked as ``sequence``); every robot's estimate and report
    (agent id -> value, checked again by the reader), and its faults as (agent, error, where) texts."""

    kind: str
    sequence: int
    actions: Mapping[str, object]
    estimates: Mapping[str, object]
    reports: Mapping[str, object]
    faults: tuple[tuple[str, str, str | None], ...]


class AnswerReader:
    """Reads the answers of one controller from its end of the pipe ``conn``, as their bytes arrive: a call of
    :meth:`read` never waits for bytes that are not there, so a controller that sends part of a message and
    stops holds nobody (it is still busy, and the controllers' hang limit applies)."""

    def __init__(self, conn: Connection):
        self.conn = conn
        self._header = bytearray()
        self._size: int | None = None  # of the message under way, once its header is read
        self._body = bytearray()

    def read(self) -> Answer | None:
        """Read what has arrived (the pipe was seen readable): the answer it completes, or None while one is
        under way. Raises ``EOFError`` when the controller's end is closed (``OSError`` when the pipe fails)
        and :class:`AnswerRefused` for an answer the simulator does not take (its bytes are not read)."""
        if sys.platform == "win32":  # no descriptor to read from: the length is still checked first
            try:
                return _shaped(_unpickled(self.conn.recv_bytes(MAX_ANSWER_BYTES)))
            except OSError as error:
                raise AnswerRefused(f"an answer over {MAX_ANSWER_BYTES} bytes ({error})") from None
        fd = self.conn.fileno()
        first = True
        while first or wait([self.conn], timeout=0):  # only what has arrived
            first = False
            if self._size is None:
                self._take(os.read(fd, _HEADER.size - len(self._header)), self._header)
                if len(self._header) == _HEADER.size:
                    self._size = _checked_size(_HEADER.unpack(self._header)[0])
            else:
                self._take(os.read(fd, self._size - len(self._body)), self._body)
            if self._size is not None and len(self._body) == self._size:
                data = bytes(self._body)
                self._header, self._size, self._body = bytearray(), None, bytearray()
                return _shaped(_unpickled(data))
        return None

    @property
    def under_way(self) -> bool:
        """Whether part of a message has arrived."""
        return bool(self._header)

    def _take(self, chunk: bytes, into: bytearray) -> None:
        if not chunk:
            raise EOFError("the controller's end of the pipe is closed"
                           + (" in the middle of a message" if self.under_way else ""))
        into += chunk


def _checked_size(size: int) -> int:
    if size == -1:  # the framing of a message past 2 GiB
        raise AnswerRefused(f"an answer of over 2 GiB; at most {MAX_ANSWER_BYTES} bytes are read")
    if not 0 < size <= MAX_ANSWER_BYTES:
        raise AnswerRefused(f"an answer of {size} bytes; at most {MAX_ANSWER_BYTES} bytes are read")
    return size


class _AnswerUnpickler(pickle.Unpickler):
    def find_class(self, module: str, name: str) -> type:
        cls = ANSWER_CLASSES.get((module, name))
        if cls is None:
            raise AnswerRefused(f"an answer that names {module[:80]}.{name[:80]}; an answer holds only "
                                f"{sorted(cls.__qualname__ for cls in ANSWER_CLASSES.values())}")
        return cls

    def persistent_load(self, pid: object) -> object:
        raise AnswerRefused("an answer with a persistent reference")


def _unpickled(data: bytes) -> object:
    try:
        return _AnswerUnpickler(io.BytesIO(data)).load()
    except AnswerRefused:
        raise
    except Exception as error:  # any damage: truncated, unknown opcode, a constructor that refused its values
        raise AnswerRefused(f"an unreadable answer ({type(error).__name__})") from None


def _shaped(message: object) -> Answer:
    """The answer of a message, its estimates, reports and faults of exactly the kinds a controller sends."""
    if type(message) is not tuple or not message or message[0] not in KINDS or len(message) != KINDS[message[0]]:
        raise AnswerRefused(f"a message that is not an answer (expected a tuple of one of the kinds {list(KINDS)})")
    if message[0] == "reset":
        kind, estimates, reports, faults = message
        sequence, actions = 0, {}
    else:
        kind, sequence, actions, estimates, reports, faults = message
        if type(sequence) is not int:
            raise AnswerRefused("an answer whose step number is not an int")
    for name, value in (("actions", actions), ("estimates", estimates), ("reports", reports)):
        if type(value) is not dict or not all(type(key) is str for key in value):
            raise AnswerRefused(f"an answer whose {name} are not a dict of agent id -> value")
    for agent, estimate in estimates.items():
        if estimate is not None and not _floats(estimate, 3):
            raise AnswerRefused(f"an answer whose estimate of {agent[:40]} is not None or 3 floats")
    for agent, report in reports.items():
        if report is not None and not _plain_report(report):
            raise AnswerRefused(f"an answer whose report of {agent[:40]} is not None or an AgentReport of plain values")
    return Answer(kind, sequence, actions, estimates, reports, _faults(faults))


def _floats(value: object, count: int) -> bool:
    return type(value) is tuple and len(value) == count and all(type(v) is float for v in value)


def _plain_report(report: object) -> bool:
    """An AgentReport whose fields are of the types its checks give them (checked again by the reader)."""
    if type(report) is not AgentReport:
        return False
    fields = getattr(report, "__dict__", None)
    if type(fields) is not dict or set(fields) != {"ball_xy", "team_ball_xy", "role", "landmarks_seen"}:
        return False
    role, landmarks = fields["role"], fields["landmarks_seen"]
    return (all(fields[name] is None or _floats(fields[name], 2) for name in ("ball_xy", "team_ball_xy"))
            and (role is None or type(role) is str)
            and type(landmarks) is frozenset and all(type(index) is int for index in landmarks))


def _faults(faults: object) -> tuple[tuple[str, str, str | None], ...]:
    if type(faults) is not list or len(faults) > MAX_FAULTS:
        raise AnswerRefused(f"an answer whose faults are not a list of at most {MAX_FAULTS}")
    for fault in faults:
        if (type(fault) is not tuple or len(fault) != 3 or not all(type(text) is str for text in fault[:2])
                or not (fault[2] is None or type(fault[2]) is str)
                or any(text is not None and len(text) > MAX_FAULT_CHARS for text in fault)):
            raise AnswerRefused(f"an answer with a fault that is not (agent, error, where) texts of at most "
                                f"{MAX_FAULT_CHARS} characters")
    return tuple(faults)
