"""Policies as a user would write them in their own module, chosen by ``tests.user_policies:Name``."""

from __future__ import annotations

import os
import time

import cv2
import numpy as np

from agents.radio import TeamMessage
from match.protocol import Action, CameraChoice, Motion, make_action, parse_action, policy_builder


class Spinner:
    """Turns in place with the walk, camera off; remembers who it plays."""

    def __init__(self) -> None:
        self.agent_id = ""
        self.seed = -1
        self.steps = 0

    def reset(self, agent_id: str, seed: int) -> None:
        self.agent_id, self.seed, self.steps = agent_id, seed, 0

    def act(self, observation: dict) -> dict:
        self.steps += 1
        return make_action(Motion.WALK, walk=(0.0, 0.0, 0.5), camera=CameraChoice.OFF)


class WalkForward(Spinner):
    """Walks straight ahead at 0.15 m/s."""

    def act(self, observation: dict) -> dict:
        self.steps += 1
        return make_action(Motion.WALK, walk=(0.15, 0.0, 0.0), camera=CameraChoice.OFF)


class NoReset:
    """Not a policy: it has no reset()."""

    def act(self, observation: dict) -> dict:
        return make_action(Motion.STAND)


NOT_A_CLASS = 3


class RadioFuzzer(Spinner):
    """Stands and sends garbage to its teammates: random bytes, truncated and future-version packets."""

    def reset(self, agent_id: str, seed: int) -> None:
        super().reset(agent_id, seed)
        self.rng = np.random.default_rng(seed)
        self.good = TeamMessage(int(agent_id[-1]), 1, (0.0, 0.0, 0.0), ball_xy=(1.0, 1.0)).encode()

    def act(self, observation: dict) -> dict:
        self.steps += 1
        kind = self.steps % 4
        if kind == 0:
            data = self.rng.integers(0, 256, int(self.rng.integers(1, 129)), dtype=np.uint8).tobytes()
        elif kind == 1:
            data = self.good[: int(self.rng.integers(1, len(self.good)))]
        elif kind == 2:
            data = self.good[:2] + bytes([99]) + self.good[3:]
        else:
            data = b"RS" + bytes(125)
        return make_action(Motion.STAND, camera=CameraChoice.OFF, radio=data)


class ExitsAtHome(Spinner):
    """Kills its own process (``os._exit(3)``) on its 50th act when it plays for the home team."""

    def act(self, observation: dict) -> dict:
        self.steps += 1
        if self.steps == 50 and self.agent_id.startswith("home"):
            os._exit(3)
        return make_action(Motion.STAND, camera=CameraChoice.OFF)


class RaisesEveryTenth(Spinner):
    """Raises on every 10th act; stands otherwise."""

    def act(self, observation: dict) -> dict:
        self.steps += 1
        if self.steps % 10 == 0:
            raise RuntimeError(f"act {self.steps} of {self.agent_id} fails")
        return make_action(Motion.STAND, camera=CameraChoice.OFF)


class Counted(Spinner):
    """Walks in a circle with its camera on; counts its acts and the observations' step times it saw."""

    def act(self, observation: dict) -> dict:
        self.steps += 1
        return make_action(Motion.WALK, walk=(0.1, 0.0, 0.3), camera=CameraChoice.TOP)

    def pose_estimate(self) -> tuple[float, float, float]:
        return (float(self.steps % 100) / 100.0, 0.0, 0.0)  # counts the acts, for the log


class ThinksLater(Counted):
    """Counted, whose acts are counted in :meth:`think` (a :class:`~match.protocol.policy.Thinker`) when a
    controller calls it, else at the next act; every 7th think raises."""

    def reset(self, agent_id: str, seed: int) -> None:
        super().reset(agent_id, seed)
        self.thoughts = 0  # acts to be counted
        self.thinks = 0

    def act(self, observation: dict) -> dict:
        self.think()
        self.thoughts = 1
        return make_action(Motion.WALK, walk=(0.1, 0.0, 0.3), camera=CameraChoice.TOP)

    def think(self) -> None:
        if not self.thoughts:
            return
        self.steps, self.thoughts = self.steps + self.thoughts, 0
        self.thinks += 1
        if self.thinks % 7 == 0:
            raise RuntimeError(f"think {self.thinks} of {self.agent_id} fails")


class ImageProbe(Spinner):
    """Stands; reports what the image of its last observation showed, as a pose estimate (for the tests):
    its first byte / 10, the sum of its bytes modulo 1000 / 100, and its height in pixels."""

    def reset(self, agent_id: str, seed: int) -> None:
        super().reset(agent_id, seed)
        self.seen = (0.0, 0.0, 0.0)

    def act(self, observation: dict) -> dict:
        image = np.asarray(observation["image"])
        self.seen = (image.flat[0] / 10.0, int(image.sum()) % 1000 / 100.0, float(image.shape[0]))
        return make_action(Motion.STAND, camera=CameraChoice.TOP)

    def pose_estimate(self) -> tuple[float, float, float]:
        return self.seen


class ReportsPriority(Spinner):
    """Stands; reports its process's scheduling niceness as a pose estimate ``(niceness, 0, 0)`` (for the tests)."""

    def pose_estimate(self) -> tuple[float, float, float]:
        return (float(os.getpriority(os.PRIO_PROCESS, 0)), 0.0, 0.0)


class ReportsOpenCVThreads(Spinner):
    """Stands; reports OpenCV's thread count in its process as a pose estimate ``(threads, 0, 0)`` (for the tests)."""

    def pose_estimate(self) -> tuple[float, float, float]:
        return (float(cv2.getNumThreads()), 0.0, 0.0)


class Misbehaves(Spinner):
    """Each act, in turn: raises, raises SystemExit, returns garbage, returns an Action with a bad field
    (a head beyond its joint limits), returns a walk past the walk limits; reports a pose of two numbers."""

    def act(self, observation: dict) -> object:
        self.steps += 1
        kind = self.steps % 5
        if kind == 0:
            raise RuntimeError("policy bug")
        if kind == 1:
            raise SystemExit(4)
        if kind == 2:
            return object()
        if kind == 3:
            return Action(Motion.STAND, head=(9.0, 0.0))
        return make_action(Motion.WALK, walk=(0.3, 0.3, 0.0))

    def pose_estimate(self) -> tuple[float, float]:
        return (1.0, 2.0)


class ExitsOften(Spinner):
    """Ends its own process (``os._exit(5)``) on every 20th act."""

    def act(self, observation: dict) -> dict:
        self.steps += 1
        if self.steps % 20 == 0:
            os._exit(5)
        return make_action(Motion.STAND, camera=CameraChoice.OFF)


class Sleeps(Spinner):
    """Takes 2 s over every act (far past any step budget)."""

    def act(self, observation: dict) -> dict:
        time.sleep(2.0)
        return make_action(Motion.STAND, camera=CameraChoice.OFF)


class Hoards(Spinner):
    """Keeps 10 MB more on every act."""

    def reset(self, agent_id: str, seed: int) -> None:
        super().reset(agent_id, seed)
        self.hoard: list[np.ndarray] = []

    def act(self, observation: dict) -> dict:
        self.hoard.append(np.ones(1_250_000))
        return make_action(Motion.STAND, camera=CameraChoice.OFF)


class ExitsOnReset(Spinner):
    """Ends its own process (``os._exit(6)``) when it is reset."""

    def reset(self, agent_id: str, seed: int) -> None:
        os._exit(6)


class RaisesOnReset(Spinner):
    """Its reset raises; its acts are fine."""

    def reset(self, agent_id: str, seed: int) -> None:
        super().reset(agent_id, seed)
        raise RuntimeError("cannot reset")


def _parent_of(pid: int) -> int:
    with open(f"/proc/{pid}/stat", "rb") as stat:
        return int(stat.read().rsplit(b")", 1)[1].split()[1])


class SnoopsImages(Spinner):
    """Looks for camera images beyond its own, as a hostile policy would, and zeroes what it can open: the
    image memory files held open by its ancestors (the simulator among them, ``/proc/PID/fd``), and the
    image memory mapped in its own process. Reports (files of its ancestors it opened, image slots it maps,
    0)."""

    def reset(self, agent_id: str, seed: int) -> None:
        super().reset(agent_id, seed)
        self.found = (0.0, 0.0, 0.0)

    def act(self, observation: dict) -> dict:
        import mmap

        opened = 0
        pid = os.getpid()
        for _ in range(3):  # the server process that forked it, the simulator, what started that
            pid = _parent_of(pid)
            try:
                entries = os.listdir(f"/proc/{pid}/fd")
            except OSError:
                continue
            for entry in entries:
                try:
                    target = os.readlink(f"/proc/{pid}/fd/{entry}")
                    if "robot-images" not in target:
                        continue
                    fd = os.open(f"/proc/{pid}/fd/{entry}", os.O_RDWR)
                except OSError:
                    continue
                try:
                    size = os.fstat(fd).st_size
                    if size:
                        with mmap.mmap(fd, size) as memory:
                            memory[:] = bytes(size)
                        opened += 1
                finally:
                    os.close(fd)
        slots = 0
        with open("/proc/self/maps", encoding="utf-8") as maps:
            for line in maps:
                if "robot-images" in line:
                    low, high = (int(part, 16) for part in line.split()[0].split("-"))
                    slots += (high - low) // (120 * 160 * 3)
        self.found = (float(opened), float(slots), 0.0)
        return make_action(Motion.STAND, camera=CameraChoice.TOP)

    def pose_estimate(self) -> tuple[float, float, float]:
        return self.found


LEFT_BEHIND = "9876.54321"  # how long the processes of LeavesChildren sleep: the tests look for it


def left_behind() -> list[int]:
    """The processes of :class:`LeavesChildren` still running, wherever they went (found by their command line
    in ``/proc``)."""
    found = []
    for entry in filter(str.isdigit, os.listdir("/proc")):
        try:
            with open(f"/proc/{entry}/cmdline", "rb") as cmdline:
                if LEFT_BEHIND.encode() in cmdline.read():
                    found.append(int(entry))
        except OSError:
            continue
    return found


class LeavesChildren(Spinner):
    """Starts processes that would outlive its controller: a child in its session, one in a session of its
    own, a forked copy of itself, and a daemon (forked twice, in a new session); each sleeps
    :data:`LEFT_BEHIND` seconds. Stands."""

    def act(self, observation: dict) -> dict:
        return make_action(Motion.STAND, camera=CameraChoice.OFF)

    def reset(self, agent_id: str, seed: int) -> None:
        import subprocess

        super().reset(agent_id, seed)
        subprocess.Popen(["sleep", LEFT_BEHIND])
        subprocess.Popen(["sleep", LEFT_BEHIND], start_new_session=True)
        if os.fork() == 0:
            os.execvp("sleep", ["sleep", LEFT_BEHIND])
        if os.fork() == 0:
            os.setsid()
            if os.fork() == 0:
                os.execvp("sleep", ["sleep", LEFT_BEHIND])
            os._exit(0)


class InterruptsItself(Spinner):
    """Raises ``KeyboardInterrupt`` in every act."""

    def act(self, observation: dict) -> dict:
        raise KeyboardInterrupt("not the user's")


class ClosesOutput(Spinner):
    """Closes the process's ``sys.stdout`` and ``sys.stderr`` in its first act."""

    def act(self, observation: dict) -> dict:
        import sys

        sys.stdout.close()
        sys.stderr.close()
        return super().act(observation)


class Forges(Spinner):
    """Returns Actions the check built, then changed with ``object.__setattr__`` (frozen is no protection):
    in turn a camera 7, a 5,000-byte packet, a NaN walk, a motion index past the last, a head past its limits,
    and a deleted motion; every act is invalid."""

    FORGERIES = (("camera", 7), ("radio", b"x" * 5000), ("walk", (float("nan"), 0.0, 0.0)), ("motion", 99),
                 ("head", (9.0, 0.0)), ("motion", None))

    def act(self, observation: dict) -> Action:
        field, value = self.FORGERIES[self.steps % len(self.FORGERIES)]
        self.steps += 1
        action = parse_action(self.agent_id, make_action(Motion.STAND, head=(0.2, 0.1)))
        if value is None:
            object.__delattr__(action, field)
        else:
            object.__setattr__(action, field, value)
        return action


@policy_builder
def spinner_builder(**options) -> Spinner:
    """A function that builds policies, marked as one: a policy name may stand for it."""
    return Spinner(**options)


def unmarked_builder() -> Spinner:
    """The same function unmarked: callable, but not taken as a policy."""
    return Spinner()


def _controller_pipes() -> list:
    """The open ends of pipes in this process (a controller's, to the simulator): what a hostile policy finds."""
    import gc
    from multiprocessing.connection import Connection

    return [o for o in gc.get_objects() if isinstance(o, Connection) and not o.closed]


class _WritesToItsPipe(Spinner):
    """Writes to the simulator itself, through its controller's pipe, in place of its answers (:meth:`forge`)."""

    def act(self, observation: dict) -> dict:
        for conn in _controller_pipes():
            self.forge(conn)
        return make_action(Motion.STAND, camera=CameraChoice.OFF)

    def forge(self, conn) -> None:
        raise NotImplementedError


class FloodsItsPipe(_WritesToItsPipe):
    """Sends a 200 MiB message (it blocks there: the simulator reads none of it)."""

    def forge(self, conn) -> None:
        conn.send_bytes(bytes(200 << 20))


CODE_RAN = "robotstadium-answer-code-ran"  # the directory a forged answer's code would make (in the temp dir)


class RunsCodeWhenRead:
    """Unpickled, makes the directory :data:`CODE_RAN`."""

    def __reduce__(self):
        import tempfile

        return os.mkdir, (os.path.join(tempfile.gettempdir(), CODE_RAN),)


class SendsCode(_WritesToItsPipe):
    """Sends an answer whose unpickling would run code of its choosing (make the directory :data:`CODE_RAN`)."""

    def forge(self, conn) -> None:
        conn.send(("act", 1, {self.agent_id: RunsCodeWhenRead()}, {}, {}, []))


class SendsPartOfAnAnswer(_WritesToItsPipe):
    """Sends the first bytes of a message of 1,000 and stops there (sleeps)."""

    def forge(self, conn) -> None:
        import struct

        os.write(conn.fileno(), struct.pack("!i", 1000) + b"\x80\x05" * 5)
        time.sleep(3600)


class SendsHugePackets(Spinner):
    """Returns an action with a 200 MiB radio packet in every act."""

    def act(self, observation: dict) -> dict:
        return {"motion": "stand", "radio": bytes(200 << 20)}


class KillsItself(Spinner):
    """Kills its own process (SIGKILL) on every 10th act; stands otherwise."""

    def act(self, observation: dict) -> dict:
        import signal

        self.steps += 1
        if self.steps % 10 == 0:
            os.kill(os.getpid(), signal.SIGKILL)
        return make_action(Motion.STAND, camera=CameraChoice.OFF)


class SpinsInC(Spinner):
    """Spends every act in a regular expression that backtracks for ever (a loop in C, the processor busy)."""

    def act(self, observation: dict) -> dict:
        import re

        re.match(r"(a|aa)*b", "a" * 60)
        return make_action(Motion.STAND, camera=CameraChoice.OFF)
