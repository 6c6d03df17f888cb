"""Actions, checked field by field before anything of a step is applied.

One check for every path: :func:`parse_actions` (the whole step's dict of agent id ->
action) and :func:`parse_action` (one agent's action) turn whatever an agent hands over (an
action dict, an :class:`Action`, or None for "stand") into a frozen :class:`Action` of plain
values, or raise a :class:`~match.errors.StepRefusedError` naming the agent, the field, the
value and what was expected. An :class:`Action` is checked like a dict (its constructor
checks nothing, and ``object.__setattr__`` can change a frozen one): every check of an Action
reads its fields again, one by one; one whose fields are exactly what :func:`parse_action`
builds passes as itself at the cost of a few type and bound comparisons, any other is checked
like a dict. :meth:`match.game.Match.check_actions` adds the world's walk limits, and
:meth:`match.game.Match.step` applies nothing until every action has passed. A refusal costs
what its message does, never the size of the value refused: containers are read only as far
as the check needs (an action dict past its five fields, a packet past 128 bytes are refused
unread) and the message shows a short prefix (:func:`~match.errors.shown`).

What is accepted (anything else is refused, not converted):

- keys, of the step's dict (agent ids) and of an action dict (field names): ``str`` (a
  subclass is taken by its text; two keys of the same text are refused).
- ``motion``: a :class:`~world.motions.Motion`, its name (ASCII, any case), or an integer
  index into :data:`~match.protocol.spaces.MOTIONS` (a Python int or a numpy integer scalar
  or 0-d array, not a bool); absent: stand.
- ``walk`` (vx m/s, vy m/s, omega rad/s) and ``head`` (yaw rad, pitch rad): a list or tuple
  of Python ints and floats and numpy integer and floating scalars or 0-d arrays (not bools,
  strings, complex numbers or sequences), or a 1-D numpy array of integer or floating dtype
  (not a masked or object array); finite and within the action space's bounds (the head's are its
  joint limits, the ones the world checks); values at most 1e-6 past a bound (float32
  rounding) are clamped onto it. ``walk`` absent: zeros; ``head`` absent or None: unchanged.
- ``camera``: a :class:`~match.protocol.spaces.CameraChoice`, its name (ASCII, any case) or
  an integer 0-2 as for ``motion``; absent or None: unchanged.
- ``radio``: a packet dict as :func:`~match.protocol.packets.packet_space` lays it out
  (exactly the keys ``data``, a 1-D numpy array of 128 integers in [0, 255], and ``length``,
  an integer 0-128 as for ``motion``; ``data[:length]`` is sent), or bytes or bytearray of at
  most :data:`~match.protocol.packets.MAX_PACKET_BYTES`; absent, None, ``b""`` or length 0:
  no packet.

:func:`make_action` builds an action dict for agents.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from itertools import islice

import numpy as np

from match.errors import InvalidActionError, RadioPacketError, StepRefusedError, UnknownAgentError, shown
from match.protocol.packets import MAX_PACKET_BYTES, PACKET_KEYS
from match.protocol.spaces import HEAD_HIGH, HEAD_LOW, MOTIONS, WALK_HIGH, WALK_LOW, CameraChoice
from world.motions import Motion

ACTION_KEYS = ("motion", "walk", "head", "camera", "radio")
# float32 bounds of the action space may round just past the float64 limits
_BOUND_SLACK = 1e-6
_REAL_KINDS = "iuf"  # numpy dtype kinds taken as numbers: signed, unsigned, floating
_MOTION_NAMES = frozenset(m.value for m in Motion)
_CAMERA_NAMES = frozenset(c.name.lower() for c in CameraChoice)
_LONGEST_NAME = max(map(len, _MOTION_NAMES | _CAMERA_NAMES))
_LONGEST_KEY = 64  # longer than any agent id or field name
_WALK_BOX = tuple(zip(map(float, WALK_LOW), map(float, WALK_HIGH)))  # (low, high) per component, plain floats
_HEAD_BOX = tuple(zip(map(float, HEAD_LOW), map(float, HEAD_HIGH)))


class _Missing:
    """A field an :class:`Action` built without its constructor does not have."""

    def __repr__(self) -> str:
        return "<missing>"


_MISSING = _Missing()


@dataclass(frozen=True)
class Action:
    """An action of plain values as :func:`parse_action` returns it. ``None`` fields keep what
    the robot is doing. The constructor checks nothing: a step checks every Action again."""

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


def parse_actions(actions: object, agents: Iterable[str]) -> dict[str, Action]:
    """Every agent's checked action (agents without one stand), from a dict agent id -> action.

    Raises a :class:`StepRefusedError` when ``actions`` is not a dict, a key is not one of
    ``agents`` (:class:`UnknownAgentError`) or an action is invalid (:class:`InvalidActionError`).
    """
    agents = tuple(agents)
    if not isinstance(actions, Mapping):
        raise StepRefusedError(f"actions = {shown(actions)} is invalid; expected a dict of agent id -> action")
    given: dict[str, object] = {}
    for key, raw in _items(actions, len(agents), None, "actions", "a dict of agent id -> action"):
        name = _text(key)
        if name not in agents:
            raise UnknownAgentError(key, agents)
        if name in given:
            raise StepRefusedError(f"agent {shown(name)} is given two actions (keys equal as text)", name)
        given[name] = raw
    return {agent: parse_action(agent, given.get(agent)) for agent in agents}


def parse_action(agent: str, raw: object) -> Action:
    """Check every field of ``raw`` (an action dict, an :class:`Action`, or None for "stand")
    and build the Action of plain values (see the module docstring for what is accepted); an
    Action whose fields already are such values is returned as itself."""
    if raw is None:
        return STAND
    if type(raw) is Action and _as_built(raw):
        return raw
    if isinstance(raw, Action):
        fields = _action_fields(agent, raw)
    elif isinstance(raw, Mapping):
        fields = _dict_fields(agent, raw)
    else:
        expected = f"a dict with keys among {list(ACTION_KEYS)}, an Action, or None"
        raise InvalidActionError(agent, "action", raw, expected)
    motion = _motion(agent, fields.get("motion", Motion.STAND))
    walk = (0.0, 0.0, 0.0)
    if "walk" in fields:
        walk = _vector(agent, "walk", fields["walk"], WALK_LOW, WALK_HIGH, "(vx m/s, vy m/s, omega rad/s)")
    head = None
    if fields.get("head") is not None:
        head = _vector(agent, "head", fields["head"], HEAD_LOW, HEAD_HIGH, "(yaw rad, pitch rad)")
    camera = None
    if fields.get("camera") is not None:
        camera = _camera(agent, fields["camera"])
    radio = _packet(agent, fields.get("radio"))
    return Action(motion=motion, walk=walk, head=head, camera=camera, radio=radio)


def _as_built(action: Action) -> bool:
    """Whether the fields of an Action (read from the instance, as a forger sets them) are of the exact
    types and within the bounds :func:`parse_action` gives them: a check of plain types, no conversion."""
    try:
        fields = object.__getattribute__(action, "__dict__")
        motion, walk, head = fields["motion"], fields["walk"], fields["head"]
        camera, radio = fields["camera"], fields["radio"]
    except (AttributeError, KeyError, TypeError):  # a field deleted, or no instance dict at all
        return False
    return (type(motion) is Motion and _in_box(walk, _WALK_BOX) and (head is None or _in_box(head, _HEAD_BOX))
            and (camera is None or type(camera) is CameraChoice)
            and type(radio) is bytes and len(radio) <= MAX_PACKET_BYTES)


def _in_box(values: object, box: tuple[tuple[float, float], ...]) -> bool:
    """A plain tuple of plain floats, one per (low, high) of ``box`` and within it (NaN is not)."""
    if type(values) is not tuple or len(values) != len(box):
        return False
    for v, (lo, hi) in zip(values, box):
        if type(v) is not float or not lo <= v <= hi:
            return False
    return True


def _dict_fields(agent: str, raw: Mapping) -> dict[str, object]:
    fields: dict[str, object] = {}
    for key, value in _items(raw, len(ACTION_KEYS), agent, "action", f"a dict with keys among {list(ACTION_KEYS)}"):
        name = _text(key)
        if name not in ACTION_KEYS:
            field = shown(key) if name is None else name
            raise InvalidActionError(agent, field, value, f"a field among {list(ACTION_KEYS)}")
        if name in fields:
            raise InvalidActionError(agent, name, value, "one value per field (keys equal as text)")
        fields[name] = value
    return fields


def _action_fields(agent: str, raw: Action) -> dict[str, object]:
    """The fields of an Action built without checks (a missing motion is refused)."""
    fields: dict[str, object] = {}
    for name in ACTION_KEYS:
        try:
            value = getattr(raw, name, _MISSING)
        except Exception as error:  # a subclass's property may raise anything
            raise InvalidActionError(agent, name, raw, f"a readable field ({type(error).__name__})") from None
        if value is _MISSING:
            raise InvalidActionError(agent, name, value, f"an Action with its field {name!r} set")
        fields[name] = value
    return fields


def _items(mapping: Mapping, most: int, agent: str | None, what: str, expected: str) -> list[tuple[object, object]]:
    """The first ``most + 1`` items of a mapping, read once (a dict's own storage, whatever a subclass
    overrides): one more than a valid mapping holds is enough to refuse it, however big it is. A mapping
    whose items cannot be read is refused."""
    try:
        items = dict.items(mapping) if isinstance(mapping, dict) else mapping.items()
        return list(islice(items, most + 1))
    except Exception as error:  # a user's Mapping may raise anything while read
        message = f"{what} = {shown(mapping)} cannot be read ({type(error).__name__}); expected {expected}"
        if agent is not None:
            message = f"agent {shown(agent)}: {message}"
        raise StepRefusedError(message, agent) from None


def _text(key: object) -> str | None:
    """A key as a plain str (str subclasses compared by their text), None if it is not text or longer than
    any key (an agent id or a field name), unread."""
    if not isinstance(key, str) or str.__len__(key) > _LONGEST_KEY:
        return None
    return str.__str__(key)


def _name(text: str) -> str | None:
    """An ASCII name in lower case (case folding outside ASCII may turn other letters into names); None for
    text longer than any name, unread."""
    if str.__len__(text) > _LONGEST_NAME:
        return None
    plain = str.__str__(text)
    return plain.lower() if plain.isascii() else None


def _motion(agent: str, value: object) -> Motion:
    if isinstance(value, Motion):
        return value
    if isinstance(value, str):
        name = _name(value)
        if name in _MOTION_NAMES:
            return Motion(name)
    else:
        index = _index(value)
        if index is not None and 0 <= index < len(MOTIONS):
            return MOTIONS[index]
    expected = f"a Motion, an index in [0, {len(MOTIONS) - 1}] or a name among {[m.value for m in MOTIONS]}"
    raise InvalidActionError(agent, "motion", value, expected)


def _camera(agent: str, value: object) -> CameraChoice:
    if isinstance(value, CameraChoice):
        return value
    if isinstance(value, str):
        name = _name(value)
        if name in _CAMERA_NAMES:
            return CameraChoice[name.upper()]
    else:
        index = _index(value)
        if index is not None and index in tuple(CameraChoice):
            return CameraChoice(index)
    expected = "a CameraChoice, 0 (off), 1 (top), 2 (bottom) or one of their names"
    raise InvalidActionError(agent, "camera", value, expected)


def _index(value: object) -> int | None:
    """An integer (Python int or numpy integer, scalar or 0-d array; not a bool) as an int, else None."""
    if isinstance(value, bool):
        return None
    if isinstance(value, int):
        return int.__index__(value)
    if isinstance(value, np.generic) or type(value) is np.ndarray:
        if value.dtype.kind in "iu" and value.shape == ():
            return int(value[()])
    return None


def _vector(agent: str, field: str, value: object, low, high, meaning: str) -> tuple[float, ...]:
    numbers = _numbers(value, len(low))
    if numbers is None or not all(
            math.isfinite(v) and lo - _BOUND_SLACK <= v <= hi + _BOUND_SLACK for v, lo, hi in zip(numbers, low, high)):
        bounds = ", ".join(f"[{lo:.4f}, {hi:.4f}]" for lo, hi in zip(low, high))
        expected = (f"{len(low)} finite numbers {meaning} within {bounds}: a list or tuple of ints and floats, "
                    "or a numpy array of integer or floating dtype")
        raise InvalidActionError(agent, field, value, expected)
    return tuple(min(max(v, lo), hi) for v, lo, hi in zip(numbers, low, high))


def _numbers(value: object, size: int) -> list[float] | None:
    """``size`` real numbers as Python floats (values past float64's range become inf), None if not such numbers."""
    if type(value) is np.ndarray:  # a subclass (a masked array) may mean more than its data
        if value.dtype.kind not in _REAL_KINDS or value.shape != (size,):
            return None
        if value.dtype.itemsize <= 8 or value.dtype.kind != "f":
            return value.astype(np.float64).tolist()
        with np.errstate(over="ignore"):  # a long double past float64's range
            return value.astype(np.float64).tolist()
    if not isinstance(value, (list, tuple)):
        return None
    base = list if isinstance(value, list) else tuple
    try:
        if base.__len__(value) != size:  # its stored length: a long one is refused unread
            return None
        items = list(islice(value, size + 1))  # read once, as far as it needs (a subclass's iterator may not end)
        if len(items) != size or not all(_is_real_scalar(v) for v in items):
            return None
        return [_as_float(v) for v in items]
    except Exception:  # a subclass's iteration or conversion may raise anything
        return None


def _is_real_scalar(value: object) -> bool:
    """A Python int or float (not a bool), or a numpy integer or floating scalar (or 0-d array)."""
    if isinstance(value, bool):
        return False
    if isinstance(value, (int, float)):
        return True
    if isinstance(value, np.generic) or (type(value) is np.ndarray and value.shape == ()):
        return value.dtype.kind in _REAL_KINDS
    return False


def _as_float(value: object) -> float:
    if isinstance(value, int):
        number = int.__index__(value)
        try:
            return float(number)
        except OverflowError:  # past float64's range
            return float("inf") if number > 0 else float("-inf")
    if isinstance(value, float):
        return float.__float__(value)
    with np.errstate(over="ignore"):
        return float(np.float64(value))


def _packet(agent: str, value: object) -> bytes:
    expected = (f"bytes or bytearray of length at most {MAX_PACKET_BYTES}, a packet dict {{'data': {MAX_PACKET_BYTES} "
                f"integers in [0, 255] (a 1-D numpy array), 'length': an integer in [0, {MAX_PACKET_BYTES}]}}, "
                "or None for no packet")
    if value is None:
        return b""
    if isinstance(value, Mapping):
        return _packet_dict(agent, value, expected)
    if not isinstance(value, (bytes, bytearray)):
        raise RadioPacketError(agent, "radio", value, expected)
    view = memoryview(value)  # the buffer itself, whatever a subclass's __len__ or __bytes__ say
    if view.nbytes > MAX_PACKET_BYTES:
        raise RadioPacketError(agent, "radio", value, f"at most {MAX_PACKET_BYTES} bytes, got {view.nbytes} bytes")
    return view.tobytes()


def _packet_dict(agent: str, value: Mapping, expected: str) -> bytes:
    """The bytes of a packet in the layout of :func:`~match.protocol.packets.packet_space`."""
    fields: dict[str, object] = {}
    for key, item in _items(value, len(PACKET_KEYS), agent, "radio", expected):
        name = _text(key)
        if name not in PACKET_KEYS or name in fields:
            raise RadioPacketError(agent, "radio", value, f"{expected}; got the key {shown(key)}")
        fields[name] = item
    if len(fields) != len(PACKET_KEYS):
        raise RadioPacketError(agent, "radio", value, f"{expected}; got the keys {sorted(fields)}")
    length = _index(fields["length"])
    if length is None or not 0 <= length <= MAX_PACKET_BYTES:
        raise RadioPacketError(agent, "radio.length", fields["length"], f"an integer in [0, {MAX_PACKET_BYTES}]")
    data = fields["data"]
    if (type(data) is not np.ndarray or data.dtype.kind not in "iu" or data.shape != (MAX_PACKET_BYTES,)
            or int(data.min()) < 0 or int(data.max()) > 255):
        raise RadioPacketError(agent, "radio.data", data,
                               f"a 1-D numpy array of {MAX_PACKET_BYTES} integers in [0, 255] (dtype uint8)")
    return data[:length].astype(np.uint8).tobytes()
