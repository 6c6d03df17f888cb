"""Camera images to a controller process through shared memory instead of its pipe.

Every observation carries a 160x120 RGB image (57.6 kB, zeros when the camera is off), and a
pipe holds 64 kB: sent inline, a team's four images fill it several times over and the
simulator waits for the controller to drain it. :class:`SharedImages` keeps one image slot
per robot of a controller in memory both processes map; :meth:`SharedImages.pack` copies each
image into its robot's slot and sends an :class:`ImageSlot` in its place (a blank image is
sent as :data:`BLANK`, nothing copied), and :func:`unpack` on the controller's side puts a
copy of the slot back. The policy gets the same array, byte for byte.

The simulator writes a slot only when it asks the controller, which it does only when the
controller has answered the step before (see :mod:`match.controllers`): a controller never
reads a slot that is being written.
"""

from __future__ import annotations

import ctypes
from collections.abc import Mapping
from dataclasses import dataclass
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
    """``slots`` image slots in shared memory, made with a multiprocessing ``context``; pass
    :attr:`buffer` to the controller process (as a :class:`~multiprocessing.Process` argument)."""

    def __init__(self, context, slots: int):
        self.buffer = context.RawArray(ctypes.c_uint8, max(slots, 1) * IMAGE_BYTES)
        self._frames = frames_of(self.buffer)

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


def frames_of(buffer) -> np.ndarray:
    """The image slots of a shared buffer, (slots, height, width, 3) uint8, without a copy."""
    return np.frombuffer(buffer, dtype=np.uint8).reshape(-1, *IMAGE_SHAPE)


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
