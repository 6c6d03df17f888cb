"""What a camera draws from one pose, kept for the next frames from the same pose."""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Callable, Hashable
from typing import Generic, TypeVar

import numpy as np

T = TypeVar("T")


class PoseCache(Generic[T]):
    """The values of the last ``size`` camera poses (least recently used dropped first)."""

    def __init__(self, size: int):
        self._size = size
        self._values: OrderedDict[tuple, T] = OrderedDict()

    def get(self, rotation: np.ndarray, position: np.ndarray, extra: tuple[Hashable, ...],
            make: Callable[[], T]) -> T:
        """The value kept for this pose (rotation camera->world, position m) and ``extra`` (image size, focal
        length...), else ``make()``'s, kept."""
        key = (np.asarray(rotation, float).tobytes(), np.asarray(position, float).tobytes(), *extra)
        value = self._values.get(key)
        if value is None:
            value = make()
            self._values[key] = value
            if len(self._values) > self._size:
                self._values.popitem(last=False)
        else:
            self._values.move_to_end(key)
        return value
