"""Robot cameras drawn in a worker process that holds a render-only copy of the world.

A camera frame is most of a simulator step's work, and a frame depends only on where every
body is. A :class:`RenderWorker` builds the same world in a process of its own (the same
robots, ball and hall, made in the same order, so TinyRenderer draws the same triangles in
the same order) and, before each batch of frames, is given :class:`BodyPoses`: every
robot's base pose and joint angles, the ball's pose and the team colours. Forward
kinematics from the same numbers gives the same link poses, bit for bit, and so the same
pixels: a frame from the worker is the frame the world would have drawn
(``tests/test_render_workers.py`` compares every pixel). The simulator draws other cameras
meanwhile. Frames come back through shared memory.

A worker that fails (it dies, answers something else, or takes longer than
:data:`RENDER_TIMEOUT_S`) raises :class:`RenderWorkerError`; the world then stops it and
draws every frame itself (the same images, later).
"""

from __future__ import annotations

import ctypes
import multiprocessing
import os
from collections.abc import Sequence
from dataclasses import dataclass
from multiprocessing.connection import Connection

import numpy as np

from world.camera_model import NAO_CAMERA
from world.config import RobotSpec, WorldConfig
from world.process_memory import peak_resident_mb
from world.robot_model import TeamColor

FRAME_SHAPE = (NAO_CAMERA.height_px, NAO_CAMERA.width_px, 3)  # one robot camera frame, RGB uint8
START_TIMEOUT_S = 60.0  # a worker builds its world in about a second
RENDER_TIMEOUT_S = 10.0  # a batch of frames takes milliseconds


def default_render_workers(parallel_matches: int = 1) -> int:
    """One render worker per match when the machine has a core to spare for each, else none."""
    return 1 if (os.cpu_count() or 1) >= 2 * parallel_matches else 0


class RenderWorkerError(RuntimeError):
    """A render worker could not draw the frames it was asked for."""


@dataclass(frozen=True)
class BodyPoses:
    """Where every body of a world is, enough to draw it (world frame; m, quaternions x, y, z, w).

    ``robots``: per robot of the roster, in order, its base position, base orientation and the
    angles (rad) of its movable joints in joint order; ``ball``: its position and
    orientation; ``teams``: each robot's waistband colour.
    """

    robots: tuple[tuple[tuple[float, ...], tuple[float, ...], tuple[float, ...]], ...]
    ball: tuple[tuple[float, ...], tuple[float, ...]]
    teams: tuple[TeamColor, ...]


class RenderWorker:
    """One worker process drawing robot camera frames for a world of ``robots`` built with ``config``.

    The process starts at once and builds its world while the caller goes on; the first
    :meth:`submit` waits for it. :meth:`submit` sends poses and camera poses and returns
    at once; :meth:`collect` waits for the frames.
    """

    def __init__(self, robots: Sequence[RobotSpec], config: WorldConfig, slots: int):
        # spawn: a fresh interpreter, so the worker shares nothing with the simulator's process and
        # leaves the forkserver (and its preloads) to the controller processes
        context = multiprocessing.get_context("spawn")
        self._buffer = context.RawArray(ctypes.c_uint8, max(slots, 1) * int(np.prod(FRAME_SHAPE)))
        self._frames = np.frombuffer(self._buffer, dtype=np.uint8).reshape(-1, *FRAME_SHAPE)
        parent, child = context.Pipe()
        self._process = context.Process(target=serve, args=(child, list(robots), config, self._buffer),
                                        daemon=True, name="render worker")
        self._process.start()
        child.close()
        self._conn: Connection | None = parent
        self._ready = False
        self._asked = 0

    def peak_resident_mb(self) -> float | None:
        """The process's peak resident memory since it started (MiB), None where the system does not say or
        it has stopped."""
        return None if self._process is None else peak_resident_mb(self._process.pid)

    @property
    def slots(self) -> int:
        """How many frames one batch can hold."""
        return len(self._frames)

    def submit(self, poses: BodyPoses, cameras: Sequence[tuple[np.ndarray, np.ndarray]]) -> None:
        """Ask for one frame per camera (rotation camera->world 3x3, position (3,) m) of the world at ``poses``."""
        if len(cameras) > self.slots:
            raise ValueError(f"{len(cameras)} frames asked of a render worker with {self.slots} slots")
        if not self._ready:
            self._expect("ready", START_TIMEOUT_S)
            self._ready = True
        if self._asked:  # a batch nobody collected (its caller stopped early): its answer comes first
            self.collect()
        self._send(("render", poses, [(np.asarray(r, float), np.asarray(p, float)) for r, p in cameras]))
        self._asked = len(cameras)

    def collect(self) -> list[np.ndarray]:
        """The frames of the last :meth:`submit`, in its order (copies, RGB (h, w, 3) uint8)."""
        if not self._asked:
            raise RenderWorkerError("no frames were asked of the render worker")
        self._expect("done", RENDER_TIMEOUT_S)
        frames = [self._frames[i].copy() for i in range(self._asked)]
        self._asked = 0
        return frames

    def close(self) -> None:
        """Stop the process: told to end, and killed if it has not within a second (it holds nothing to save)."""
        if self._conn is not None:
            try:
                self._conn.send(("close",))
            except (OSError, ValueError):
                pass
            self._conn.close()
            self._conn = None
        if self._process is not None:
            self._process.join(timeout=1.0)
            if self._process.is_alive():
                self._process.kill()
                self._process.join(timeout=5.0)
            self._process = None

    def _send(self, message: tuple) -> None:
        if self._conn is None:
            raise RenderWorkerError("the render worker is closed")
        try:
            self._conn.send(message)
        except (OSError, ValueError) as error:
            raise RenderWorkerError(f"cannot reach the render worker ({error}; exit code "
                                    f"{self._exit_code()})") from error

    def _expect(self, kind: str, timeout_s: float) -> None:
        if self._conn is None:
            raise RenderWorkerError("the render worker is closed")
        try:
            if not self._conn.poll(timeout_s):
                raise RenderWorkerError(f"no answer from the render worker within {timeout_s:g} s")
            message = self._conn.recv()
        except (EOFError, OSError) as error:
            raise RenderWorkerError(f"the render worker ended (exit code {self._exit_code()})") from error
        if not (isinstance(message, tuple) and message and message[0] == kind):
            raise RenderWorkerError(f"the render worker answered {str(message)[:200]!r}; expected {kind!r}")

    def _exit_code(self) -> int | None:
        if self._process is None:
            return None
        self._process.join(timeout=0.5)
        return self._process.exitcode


def serve(conn: Connection, robots: list[RobotSpec], config: WorldConfig, buffer) -> None:
    """The worker's loop: build the world, then draw the frames it is asked for until told to close, or until
    the simulator's end of ``conn`` is closed (it stopped, or was stopped, without a word): then it ends quietly."""
    try:
        _draw_frames(conn, robots, config, buffer)
    except (EOFError, BrokenPipeError, ConnectionResetError):
        return


def _draw_frames(conn: Connection, robots: list[RobotSpec], config: WorldConfig, buffer) -> None:
    from world.world import World  # the world imports this module

    frames = np.frombuffer(buffer, dtype=np.uint8).reshape(-1, *FRAME_SHAPE)
    try:
        world = World(robots, config)
    except Exception as error:
        conn.send(("failed", f"{type(error).__name__}: {error}"))
        return
    with world:
        conn.send(("ready",))
        while True:
            message = conn.recv()
            if message[0] != "render":
                return
            _, poses, cameras = message
            try:
                world.set_body_poses(poses)
                for slot, (rotation, position) in enumerate(cameras):
                    frames[slot] = world.render_camera_at(rotation, position)
            except Exception as error:
                conn.send(("failed", f"{type(error).__name__}: {error}"))
                return
            conn.send(("done",))
