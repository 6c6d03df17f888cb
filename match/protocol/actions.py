"""One agent's action, checked field by field before anything is applied.

:func:`parse_action` turns the dict an agent hands the environment into a frozen
:class:`Action`, or raises :class:`InvalidActionError` naming the agent, the field, the
value and what was allowed. :func:`make_action` builds such a dict for agents.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from match.errors import InvalidActionError, RadioPacketError
from match.protocol.packets import MAX_PACKET_BYTES
from match.protocol.spaces import HEAD_HIGH, HEAD_LOW, MOTIONS, WALK_HIGH, WALK_LOW, CameraChoice
from world.motions import Motion

ACTION_KEYS = ("motion", "walk", "head", "camera", "radio")
# float32 bounds of the action space may round just past the float64 limits
_BOUND_SLACK = 1e-6


@dataclass(frozen=True)
class Action:
    """A checked action. ``None`` fields keep what the robot is doing."""

    motion: Motion
    walk: tuple[float, float, float] = (0.0, 0.0, 0.0)  # vx m/s, vy m/s, omega rad/s
    head: tuple[float, float] | None = None  # yaw, pitch targets, rad
    camera: CameraChoice | None = None
    radio: bytes = b""  # empty: no packet


STAND = Action(Motion.STAND)


def make_action(
    motion: Motion | str = Motion.STAND,
    *,
    walk: tuple[float, float, float] = (0.0, 0.0, 0.0),
    head: tuple[float, float] | None = None,
    camera: CameraChoice | None = None,
    radio: bytes = b"",
) -> dict:
    """An action dict in the action space's layout (``head``/``camera`` left out when None)."""
    action: dict = {
        "motion": MOTIONS.index(Motion.parse(motion)),
        "walk": np.asarray(walk, dtype=np.float32),
        "radio": bytes(radio),
    }
    if head is not None:
        action["head"] = np.asarray(head, dtype=np.float32)
    if camera is not None:
        action["camera"] = int(camera)
    return action


def parse_action(agent: str, raw: object) -> Action:
    """Check every field of ``raw`` (a dict, or None for "stand"), then build the Action.

    An :class:`Action` (already checked) is returned as it is.
    """
    if raw is None:
        return STAND
    if isinstance(raw, Action):
        return raw
    if not isinstance(raw, Mapping):
        raise InvalidActionError(agent, "action", raw, f"a dict with keys among {list(ACTION_KEYS)}, or None")
    unknown = [k for k in raw if k not in ACTION_KEYS]
    if unknown:
        raise InvalidActionError(agent, str(unknown[0]), raw[unknown[0]], f"no such field; fields are {list(ACTION_KEYS)}")
    motion = _motion(agent, raw.get("motion", MOTIONS.index(Motion.STAND)))
    walk = (0.0, 0.0, 0.0)
    if "walk" in raw:
        walk = _vector(agent, "walk", raw["walk"], WALK_LOW, WALK_HIGH, "(vx m/s, vy m/s, omega rad/s)")
    head = None
    if raw.get("head") is not None:
        head = _vector(agent, "head", raw["head"], HEAD_LOW, HEAD_HIGH, "(yaw rad, pitch rad)")
    camera = None
    if raw.get("camera") is not None:
        camera = _camera(agent, raw["camera"])
    radio = _packet(agent, raw.get("radio", b""))
    return Action(motion=motion, walk=walk, head=head, camera=camera, radio=radio)


def _motion(agent: str, value: object) -> Motion:
    if isinstance(value, Motion):
        return value
    if isinstance(value, str):
        try:
            return Motion.parse(value)
        except ValueError:
            pass
    elif _is_integer(value) and 0 <= int(value) < len(MOTIONS):
        return MOTIONS[int(value)]
    raise InvalidActionError(
        agent, "motion", value, f"an index in [0, {len(MOTIONS) - 1}] or a name among {[m.value for m in MOTIONS]}"
    )


def _camera(agent: str, value: object) -> CameraChoice:
    if isinstance(value, str) and value.upper() in CameraChoice.__members__:
        return CameraChoice[value.upper()]
    if _is_integer(value) and int(value) in tuple(CameraChoice):
        return CameraChoice(int(value))
    raise InvalidActionError(agent, "camera", value, "0 (off), 1 (top) or 2 (bottom)")


def _vector(agent: str, field: str, value: object, low, high, meaning: str) -> tuple[float, ...]:
    expected = f"{len(low)} finite numbers {meaning} within {list(low)} .. {list(high)}"
    try:
        array = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InvalidActionError(agent, field, value, expected) from None
    if array.shape != (len(low),) or not np.all(np.isfinite(array)):
        raise InvalidActionError(agent, field, value, expected)
    if np.any(array < np.asarray(low) - _BOUND_SLACK) or np.any(array > np.asarray(high) + _BOUND_SLACK):
        raise InvalidActionError(agent, field, value, expected)
    return tuple(float(min(max(v, lo), hi)) for v, lo, hi in zip(array, low, high))


def _packet(agent: str, value: object) -> bytes:
    if value is None:
        return b""
    if not isinstance(value, (bytes, bytearray)):
        raise RadioPacketError(agent, "radio", value, f"bytes of length at most {MAX_PACKET_BYTES} (b'' for none)")
    if len(value) > MAX_PACKET_BYTES:
        raise RadioPacketError(agent, "radio", f"<{len(value)} bytes>", f"at most {MAX_PACKET_BYTES} bytes")
    return bytes(value)


def _is_integer(value: object) -> bool:
    if isinstance(value, bool):
        return False
    if isinstance(value, (int, np.integer)):
        return True
    return isinstance(value, np.ndarray) and value.shape == () and np.issubdtype(value.dtype, np.integer)
