"""Camera images to a controller process through shared memory instead of its pipe.

Every observation carries a 160x120 RGB image (57.6 kB, zeros when the camera is off), and a
pipe holds 64 kB: sent inline, a team's four images fill it several times over and the
simulator waits for the controller to drain it. :class:`SharedImages` keeps one image slot
per robot of a controller in memory both processes map; :meth:`SharedImages.pack` copies each
image into its robot's slot and sends an :class:`ImageSlot` in its place (a blank image is
sent as :data:`BLANK`, nothing copied), and :func:`unpack` on the controller's side puts a
copy of the slot back. The policy gets the same array, byte for byte.

Each controller process's slots are a memory file of their own with no name (``memfd_create``;
an unlinked temporary file where there is none), whose descriptor goes to that process alone,
over its pipe, and is then closed in the simulator (:meth:`SharedImages.hand_over`,
:func:`receive_frames`): a controller maps its own robots' slots and nothing else (a heap
shared by every controller would put the other team's images in its address space), and the
simulator's open descriptors do not lead to them.

The simulator writes a slot only when it asks the controller, which it does only when the
controller has answered the step before (see :mod:`match.controllers`): a controller never
reads a slot that is being written.
"""

from __future__ import annotations

import ctypes
import mmap
import os
import tempfile
from collections.abc import Mapping
from dataclasses import dataclass
from multiprocessing.connection import Connection
from multiprocessing.reduction import recv_handle, send_handle
from typing import Any

import numpy as np

from match.protocol.spaces import IMAGE_SHAPE, CameraChoice

IMAGE_BYTES = int(np.prod(IMAGE_SHAPE))


@dataclass(frozen=True)
class ImageSlot:
    """Stands for an observation's image in a sent observation: slot ``index`` of the shared images,
    or a blank image (zeros) for :data:`BLANK`."""

    index: int


BLANK = ImageSlot(-1)


class SharedImages:
    """``slots`` image slots in a memory file of their own, for one controller process (:meth:`hand_over`)."""

    def __init__(self, slots: int):
        size = max(slots, 1) * IMAGE_BYTES
        self._fd = _anonymous_file()
        try:
            os.ftruncate(self._fd, size)
            self._map = _Mapping(self._fd, size)
        except BaseException:
            os.close(self._fd)
            raise
        self._frames = self._map.frames()

    def hand_over(self, conn: Connection, pid: int) -> None:
        """Pass the slots' descriptor to the controller process ``pid`` at the other end of ``conn`` (it takes
        it with :func:`receive_frames` before its first message), then close it here: the mapping stays."""
        try:
            send_handle(conn, self._fd, pid)
        finally:
            self._close_descriptor()

    def close(self) -> None:
        """Unmap the slots (and close the descriptor if it was never handed over); idempotent."""
        self._close_descriptor()
        self._frames = np.empty((0, *IMAGE_SHAPE), np.uint8)
        self._map.close()

    def _close_descriptor(self) -> None:
        if self._fd >= 0:
            os.close(self._fd)
            self._fd = -1

    def pack(self, observations: Mapping[str, Any]) -> dict[str, Any]:
        """The observations to send, the i-th one's image moved into slot i. An observation
        whose image is not a camera image (another shape or type: a policy's own test data) is
        sent as it is."""
        packed: dict[str, Any] = {}
        for slot, (agent, observation) in enumerate(observations.items()):
            image = observation.get("image") if isinstance(observation, dict) else None
            if slot >= len(self._frames) or not _is_camera_image(image):
                packed[agent] = observation
            elif observation.get("camera") == int(CameraChoice.OFF) and not image.any():
                packed[agent] = {**observation, "image": BLANK}
            else:
                self._frames[slot] = image
                packed[agent] = {**observation, "image": ImageSlot(slot)}
        return packed


def receive_frames(conn: Connection) -> np.ndarray:
    """In the controller process: the image slots :meth:`SharedImages.send` passed over ``conn``, mapped,
    (slots, height, width, 3) uint8 (the descriptor is closed once mapped)."""
    fd = recv_handle(conn)
    try:
        return _Mapping(fd, os.fstat(fd).st_size).frames()  # mapped for the rest of the process
    finally:
        os.close(fd)


class _Mapping:
    """``size`` bytes of the file ``fd`` mapped shared, read-write, by the C library's ``mmap``: unlike
    :class:`mmap.mmap`, it keeps no descriptor of its own open."""

    _libc = ctypes.CDLL(None, use_errno=True)
    _libc.mmap.restype = ctypes.c_void_p
    _libc.mmap.argtypes = (ctypes.c_void_p, ctypes.c_size_t, ctypes.c_int, ctypes.c_int, ctypes.c_int, ctypes.c_long)
    _libc.munmap.argtypes = (ctypes.c_void_p, ctypes.c_size_t)

    def __init__(self, fd: int, size: int):
        address = self._libc.mmap(None, size, mmap.PROT_READ | mmap.PROT_WRITE, mmap.MAP_SHARED, fd, 0)
        if address in (None, ctypes.c_void_p(-1).value):
            error = ctypes.get_errno()
            raise OSError(error, f"cannot map {size} bytes of image slots: {os.strerror(error)}")
        self._address, self._size = address, size

    def frames(self) -> np.ndarray:
        """The mapped slots as (slots, height, width, 3) uint8, without a copy."""
        memory = (ctypes.c_uint8 * self._size).from_address(self._address)
        return np.frombuffer(memory, dtype=np.uint8).reshape(-1, *IMAGE_SHAPE)

    def close(self) -> None:
        """Unmap (idempotent); no array from :meth:`frames` may be used after."""
        if self._address is not None:
            self._libc.munmap(self._address, self._size)
            self._address = None


def _anonymous_file() -> int:
    """A descriptor of a memory file without a name, closed on exec."""
    if hasattr(os, "memfd_create"):
        return os.memfd_create("robot-images", os.MFD_CLOEXEC)
    handle = tempfile.TemporaryFile()  # unlinked at once where there is no memfd_create
    fd = os.dup(handle.fileno())
    handle.close()
    return fd


def unpack(frames: np.ndarray, observations: Mapping[str, Any]) -> dict[str, Any]:
    """The observations as they were packed: each :class:`ImageSlot` replaced by a copy of its image."""
    unpacked: dict[str, Any] = {}
    for agent, observation in observations.items():
        image = observation.get("image") if isinstance(observation, dict) else None
        if isinstance(image, ImageSlot):
            restored = np.zeros(IMAGE_SHAPE, np.uint8) if image.index < 0 else frames[image.index].copy()
            observation = {**observation, "image": restored}
        unpacked[agent] = observation
    return unpacked


def _is_camera_image(image: object) -> bool:
    return isinstance(image, np.ndarray) and image.dtype == np.uint8 and image.shape == IMAGE_SHAPE
