"""One check for every action: whatever an agent hands over, the step is either refused with a
:class:`StepRefusedError` naming the agent before anything of it happens, or accepted as an
Action of plain values.

Every generated value carries what it must become: the checked value, or ``BAD`` when it must
be refused. Actions the check built and a forger then changed (``object.__setattr__``, which a
frozen dataclass does not stop) are among them. Thousands of actions go through
:func:`parse_action` and ``Match.check_actions`` (no physics); a few dozen sequences of steps go
through two real environments side by side, one of them also fed the refused steps (as a whole
step, or turn by turn through the AEC env), which must stay identical to the other. A refusal
costs what its message costs, never the size of the value refused.
"""

from __future__ import annotations

import math
import time
from collections import OrderedDict
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from decimal import Decimal
from fractions import Fraction
from types import MappingProxyType

import numpy as np
import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from match import RobotStadiumEnv, parallel_env
from match.errors import InvalidActionError, StepRefusedError, UnknownAgentError, shown
from match.free_play import FreePlay
from match.game import MatchConfig
from match.protocol import MOTIONS, STAND, Action, AgentId, CameraChoice, Motion, Side, make_action, parse_action
from match.protocol.spaces import HEAD_HIGH, HEAD_LOW, WALK_HIGH, WALK_LOW, WALK_LIMITS
from world.field import Pose2D
from world.locomotion import head_limits_check

BAD = "<must be refused>"  # the expected outcome of a value that must be refused
SLACK = 1e-6  # how far past a bound a float32-rounded value may be and still be clamped
FUZZ = settings(max_examples=1000, deadline=None, derandomize=True, database=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
AGENTS = ("home_0", "home_1", "away_0")
STARTS = (("home_0", Pose2D(-1.0, 0.0, 0.0)), ("home_1", Pose2D(-1.0, 1.0, 0.0)), ("away_0", Pose2D(1.0, 0.0, math.pi)))


class Text(str):
    """A str subclass: taken by its text."""


class Twin(str):
    """A str subclass that a dict keeps beside the equal plain str (its own hash and equality)."""

    def __hash__(self) -> int:
        return object.__hash__(self)

    def __eq__(self, other: object) -> bool:
        return self is other


class Broken:
    """An object whose repr, equality and conversions fail (it hashes, so that it can be a key)."""

    def __repr__(self) -> str:
        raise RuntimeError("no repr")

    def _repr_pretty_(self, printer, cycle) -> None:  # how hypothesis shows a failing example
        printer.text("Broken()")

    def __eq__(self, other: object) -> bool:
        raise RuntimeError("no eq")

    def __hash__(self) -> int:
        return 7

    def __float__(self) -> float:
        raise RuntimeError("no float")

    def __index__(self) -> int:
        raise RuntimeError("no index")


class BrokenMapping(Mapping):
    """A Mapping whose items cannot be read."""

    def __init__(self, fail_on: str):
        self.fail_on = fail_on

    def __getitem__(self, key):
        raise RuntimeError("no item")

    def __iter__(self) -> Iterator:
        if self.fail_on == "iter":
            raise RuntimeError("no iter")
        return iter(["motion"])

    def __len__(self) -> int:
        return 1


class BrokenList(list):
    """A list that cannot be iterated."""

    def __iter__(self):
        raise RuntimeError("no iter")


def _recursive_list() -> list:
    items: list = [0.0, 0.0]
    items.append(items)
    return items


GARBAGE = [
    0, 1, -1, 1.5, True, np.bool_(False), "stand", "", b"", b"motion", 1j, [], [("motion", 0)], (0,), {0},
    Motion.STAND, CameraChoice.TOP, np.zeros(3), np.array(0), Decimal(1), Fraction(1, 2), np.timedelta64(1),
    np.datetime64(0, "s"), Broken(), object(), 10**400, 10**5000, _recursive_list(), range(3), memoryview(b"x"),
]


def _one_of(values: list):
    """One of ``values``, drawn by index (some, like a generic timedelta64, cannot be hashed)."""
    return st.integers(0, len(values) - 1).map(values.__getitem__)


def _bad(strategy):
    return strategy.map(lambda value: (value, BAD))


@st.composite
def _mostly_good(draw, good, bad, bad_share: int = 4):
    """One bad value for ``bad_share - 1`` good ones."""
    return draw(bad if draw(st.integers(0, bad_share - 1)) == 0 else good)


# ---- the fields -----------------------------------------------------------------------------

INT_TYPES = (int, np.int8, np.int16, np.int32, np.int64, np.uint8, np.uint16, np.uint64, np.array)  # np.array: 0-d


def _typed_ints(low: int, high: int):
    """An integer in [low, high] as any accepted integer type."""
    pairs = st.tuples(st.integers(low, high), st.sampled_from(INT_TYPES))
    return pairs.filter(lambda p: p[0] >= 0 or p[1] not in (np.uint8, np.uint16, np.uint64))


def _cased(names):
    return st.tuples(st.sampled_from(names), st.sampled_from((str.lower, str.upper, str.title, Text, np.str_)))


def _name_is(text: str, names) -> bool:
    return text.isascii() and text.lower() in names


MOTION_NAMES = [m.value for m in MOTIONS]
good_motion = st.one_of(
    st.sampled_from(MOTIONS).map(lambda m: (m, m)),
    _cased(MOTION_NAMES).map(lambda p: (p[1](p[0]), Motion(p[0]))),
    _typed_ints(0, len(MOTIONS) - 1).map(lambda p: (p[1](p[0]), MOTIONS[p[0]])),
    st.sampled_from(CameraChoice).map(lambda c: (c, MOTIONS[int(c)])),  # an IntEnum is an int
)
bad_motion = _bad(st.one_of(
    st.integers(max_value=-1), st.integers(min_value=len(MOTIONS)),
    st.integers(-128, -1).map(np.int8), st.integers(len(MOTIONS), 255).map(np.uint8),
    st.text(max_size=16).filter(lambda text: not _name_is(text, MOTION_NAMES)),
    _one_of([n for n in MOTION_NAMES if "i" in n]).map(lambda n: n.upper().replace("I", "\u0130")),  # not ASCII
    _one_of([
        True, False, np.bool_(True), 1.0, np.float32(2.0), math.nan, "1", "0", b"walk", 1 + 0j, None, np.complex64(1),
        np.timedelta64(3), np.datetime64(3, "s"), [3], (3,), np.array([3]), np.ma.masked_array(3), np.array(3.0),
        np.array(True), Decimal(1), Fraction(1), Broken(), 10**5000,
    ]),
))

CAMERA_NAMES = [c.name.lower() for c in CameraChoice]
good_camera = st.one_of(
    st.sampled_from(CameraChoice).map(lambda c: (c, c)),
    _cased(CAMERA_NAMES).map(lambda p: (p[1](p[0]), CameraChoice[p[0].upper()])),
    _typed_ints(0, 2).map(lambda p: (p[1](p[0]), CameraChoice(p[0]))),
    st.just((None, None)),  # unchanged
)
bad_camera = _bad(st.one_of(
    st.integers(max_value=-1), st.integers(min_value=3),
    st.text(max_size=8).filter(lambda text: not _name_is(text, CAMERA_NAMES)),
    _one_of([
        "o\ufb00", "\u1e9eide", True, np.bool_(False), 1.0, "1", "side", np.timedelta64(1), 1 + 0j, [1], np.array([1]),
        np.ma.masked_array(1), Motion.STAND, Decimal(1), Broken(), 10**400,
    ]),
))

@st.composite
def _packet_dicts(draw):
    """(a packet dict in the layout of packet_space, the bytes it sends): data of any integer dtype."""
    data = draw(st.binary(min_size=128, max_size=128))
    length, int_type = draw(_typed_ints(0, 128).filter(lambda p: p[0] < 128 or p[1] is not np.int8))
    dtype = draw(st.sampled_from((np.uint8, np.int16, np.int64, np.uint64)))
    packet = {"data": np.frombuffer(data, np.uint8).astype(dtype), "length": int_type(length)}
    if draw(st.booleans()):
        packet = {Text("length"): packet["length"], "data": packet["data"]}
    return packet, data[:length]


def _spoiled_packet(spoil: str) -> dict:
    packet = {"data": np.zeros(128, np.uint8), "length": 3}
    if spoil == "length":
        packet["length"] = 129
    elif spoil == "negative":
        packet["length"] = -1
    elif spoil == "bool":
        packet["length"] = True
    elif spoil == "float":
        packet["length"] = 3.0
    elif spoil == "short":
        packet["data"] = np.zeros(127, np.uint8)
    elif spoil == "floats":
        packet["data"] = np.zeros(128, np.float32)
    elif spoil == "big":
        packet["data"] = np.full(128, 256, np.int16)
    elif spoil == "below":
        packet["data"] = np.full(128, -1, np.int8)
    elif spoil == "list":
        packet["data"] = [0] * 128
    elif spoil == "bytes":
        packet["data"] = bytes(128)
    elif spoil == "masked":
        packet["data"] = np.ma.masked_array(np.zeros(128, np.uint8))
    elif spoil == "2d":
        packet["data"] = np.zeros((1, 128), np.uint8)
    elif spoil == "missing":
        del packet["length"]
    elif spoil == "extra":
        packet["sender"] = 1
    elif spoil == "twice":
        packet[Twin("length")] = 3
    return packet


PACKET_SPOILS = ["length", "negative", "bool", "float", "short", "floats", "big", "below", "list", "bytes", "masked",
                 "2d", "missing", "extra", "twice"]
good_radio = st.one_of(
    st.binary(max_size=128).map(lambda data: (data, data)),
    st.binary(max_size=128).map(lambda data: (bytearray(data), data)),
    _packet_dicts(),
    st.just((None, b"")),
)
bad_radio = _bad(st.one_of(
    st.binary(min_size=129, max_size=300),
    st.binary(min_size=129, max_size=300).map(bytearray),
    st.text(max_size=10),
    st.sampled_from(PACKET_SPOILS).map(_spoiled_packet),
    _one_of([memoryview(b"x"), [1, 2], np.frombuffer(b"ab", np.uint8), 0, [b""], Broken(), b"x" * 10**5,
             BrokenMapping("iter"), {}]),
))


def _scalars(lo: float, hi: float):
    """A number within [lo, hi] of any accepted scalar type."""
    floats = st.floats(lo, hi)
    return st.one_of(
        floats, floats.map(np.float64), floats.map(np.float32), floats.map(np.longdouble), floats.map(np.array),
        floats.map(np.float16).filter(lambda v: lo - SLACK <= float(v) <= hi + SLACK),
        _typed_ints(math.ceil(lo), math.floor(hi)).map(lambda p: p[1](p[0])),
    )


BAD_SCALARS = _one_of([
    math.nan, math.inf, -math.inf, 10**400, -(10**400), True, np.bool_(False), "0.1", b"0", "0", 1j, complex(0.1, 0.0),
    np.complex64(0), None, [0.0], (0.0,), np.array([0.0]), np.ma.masked_array(0.0), np.array(True), Decimal("0.1"),
    Fraction(1, 10), np.timedelta64(1), np.datetime64(0, "s"), Broken(),
])


def _vector(low, high):
    """(value, expected) pairs of a vector field within bounds ``low`` .. ``high``."""
    size = len(low)
    scalars = st.tuples(*[_scalars(lo, hi) for lo, hi in zip(low, high)])
    floats = st.tuples(*[st.floats(lo, hi) for lo, hi in zip(low, high)])
    ints = st.tuples(*[st.integers(math.ceil(lo), math.floor(hi)) for lo, hi in zip(low, high)])
    good_values = st.one_of(
        scalars.map(list), scalars,
        st.tuples(floats, st.sampled_from((np.float64, np.float32, np.longdouble))).map(lambda p: np.array(p[0], p[1])),
        floats.map(lambda v: np.array(v, np.float16)).filter(
            lambda a: all(lo - SLACK <= float(x) <= hi + SLACK for x, lo, hi in zip(a, low, high))
        ),
        st.tuples(ints, st.sampled_from((np.int8, np.int64))).map(lambda p: np.array(p[0], p[1])),
        st.sampled_from((np.asarray(low, np.float32), np.asarray(high, np.float32))),  # float32-rounded bounds
    )

    def expected(value) -> tuple[float, ...]:
        numbers = np.asarray(value, dtype=np.float64)
        return tuple(float(min(max(float(x), lo), hi)) for x, lo, hi in zip(numbers, low, high))

    good = good_values.map(lambda value: (value, expected(value)))

    def bad_scalar(i: int):
        """A value that spoils component ``i``: out of its bounds, not finite, or not a real number."""
        below = st.floats(1e-4, 1e300).map(lambda d: low[i] - d)
        return st.one_of(st.floats(high[i] + 1e-4, 1e300), below, BAD_SCALARS)

    spoilers = [bad_scalar(i) for i in range(size)]

    @st.composite
    def one_bad(draw):
        values, i = list(draw(floats)), draw(st.integers(0, size - 1))
        values[i] = draw(spoilers[i])
        return draw(st.sampled_from((list, tuple)))(values)

    bad = _bad(st.one_of(
        one_bad(),
        floats.map(lambda v: [*v, 0.0]), floats.map(lambda v: list(v)[:-1]),
        floats.map(np.ma.masked_array), floats.map(lambda v: np.ma.masked_array(v, mask=[1] + [0] * (size - 1))),
        floats.map(lambda v: np.array(v, dtype=object)), floats.map(lambda v: np.array(v)[None, :]),
        floats.map(lambda v: np.array(v)[:, None]), floats.map(lambda v: np.array(v, dtype=complex)),
        floats.map(lambda v: np.array(v, dtype=bool)), ints.map(lambda v: np.array(v, dtype="m8[s]")),
        floats.map(lambda v: np.array(v).astype(str)), floats.map(lambda v: [[x] for x in v]),
        floats.map(lambda v: np.array([np.longdouble("1e4000"), *v[1:]], dtype=np.longdouble)),
        floats.map(lambda v: np.float64(v[0])), floats.map(lambda v: np.array(v[0])),
        floats.map(lambda v: (x for x in v)), floats.map(BrokenList), floats.map(lambda v: dict(enumerate(v))),
        floats.map(set), floats.map(lambda v: " ".join(map(str, v))), st.just(range(size)),
        st.just(np.array([np.nan] * size)), st.just(np.array([2**63] * size, dtype=np.uint64)),
    ))
    return good, bad


good_walk, bad_walk = _vector(WALK_LOW, WALK_HIGH)
bad_walk = st.one_of(bad_walk, st.just((None, BAD)))  # walk None is not "no walk"
good_head, bad_head = _vector(HEAD_LOW, HEAD_HIGH)
good_head = st.one_of(good_head, st.just((None, None)))  # head None: unchanged
bad_head = st.one_of(bad_head, st.tuples(st.floats(2.1, 9.0), st.floats(-0.5, 0.5)).map(lambda v: (v, BAD)))

FIELDS = {
    "motion": _mostly_good(good_motion, bad_motion),
    "walk": _mostly_good(good_walk, bad_walk),
    "head": _mostly_good(good_head, bad_head),
    "camera": _mostly_good(good_camera, bad_camera),
    "radio": _mostly_good(good_radio, bad_radio),
}
DEFAULTS = {"motion": Motion.STAND, "walk": (0.0, 0.0, 0.0), "head": None, "camera": None, "radio": b""}
UNKNOWN_FIELDS = st.one_of(
    st.text(max_size=8).filter(lambda text: text not in FIELDS),
    _one_of(["kick", "Motion", " walk", "head ", "radios", 0, 1.5, None, b"motion", ("motion",), frozenset(), Motion.WALK,
             Broken()]),
)


def _expected_action(expected: dict) -> Action | str:
    if BAD in expected.values():
        return BAD
    return Action(**{name: expected.get(name, DEFAULTS[name]) for name in DEFAULTS})


# ---- whole actions --------------------------------------------------------------------------

FORGED_FROM = (
    make_action(Motion.WALK, walk=(0.1, 0.0, 0.2), head=(0.1, 0.2), camera=CameraChoice.TOP, radio=b"hi"),
    make_action(Motion.STAND),
    make_action(Motion.KICK_RIGHT, head=(-0.3, 0.0), camera=CameraChoice.OFF),
)


@st.composite
def forged_actions(draw) -> tuple[Action, object]:
    """(an Action the check built, then one field set or deleted with ``object.__setattr__``, the Action it
    must give or BAD): the check reads every field again."""
    built = parse_action("home_0", draw(st.sampled_from(FORGED_FROM)))
    expected = {name: getattr(built, name) for name in DEFAULTS}
    name = draw(st.sampled_from(sorted(FIELDS)))
    if draw(st.integers(0, 9)) == 0:
        object.__delattr__(built, name)  # the class default shows through; motion has none
        expected[name] = BAD if name == "motion" else DEFAULTS[name]
    else:
        value, expected[name] = draw(FIELDS[name])
        object.__setattr__(built, name, value)
    return built, _expected_action(expected)


@st.composite
def agent_actions(draw) -> tuple[object, object]:
    """(an agent's action, the Action it must give or BAD)."""
    kind = draw(st.sampled_from(["dict"] * 5 + ["action"] * 4 + ["forged"] * 3 + ["none", "garbage", "broken"]))
    if kind == "none":
        return None, STAND
    if kind == "forged":
        return draw(forged_actions())
    if kind == "garbage":
        return draw(_one_of(GARBAGE)), BAD
    if kind == "broken":
        return BrokenMapping(draw(st.sampled_from(["iter", "item"]))), BAD
    drawn = draw(st.fixed_dictionaries({}, optional=FIELDS))
    values = {name: value for name, (value, _) in drawn.items()}
    expected = {name: result for name, (_, result) in drawn.items()}
    if kind == "action":
        if "motion" not in values and draw(st.booleans()):
            values["motion"], expected["motion"] = draw(good_motion)
        if "motion" in values and draw(st.booleans()):
            return Action(**values), _expected_action(expected)
        action = object.__new__(Action)  # no checks at all; a field not set takes the class default, motion has none
        for name, value in values.items():
            object.__setattr__(action, name, value)
        return action, BAD if "motion" not in values else _expected_action(expected)
    raw: dict = dict(values)
    extra = draw(st.sampled_from(["none"] * 6 + ["unknown", "alias", "twice"]))
    if extra == "unknown":
        raw[draw(UNKNOWN_FIELDS)] = draw(st.sampled_from([0, None, "x"]))
        expected["?"] = BAD
    elif extra in ("alias", "twice") and values:
        name = draw(st.sampled_from(sorted(values)))
        if extra == "alias":
            raw[draw(st.sampled_from([Text, np.str_]))(name)] = raw.pop(name)
        else:
            raw[Twin(name)] = values[name]
            expected[name] = BAD
    wrap = draw(st.sampled_from([dict, dict, dict, OrderedDict, MappingProxyType]))
    return wrap(raw), _expected_action(expected)


@dataclass(frozen=True)
class Refusal:
    """What refuses a step: the ``actions`` argument itself, an unknown ``agent`` id or an ``action``;
    ``culprits``: the ids the error may name (the first one found)."""

    kind: str
    culprits: tuple


def _assert_refusal(error: StepRefusedError, refusal: Refusal | None, raw: object) -> None:
    assert refusal is not None, f"refused valid actions {shown(raw)}: {error}"
    message = str(error)
    assert "\n" not in message and len(message) < 1200, message
    if refusal.kind == "actions":
        assert type(error) is StepRefusedError and error.agent is None, message
        return
    assert any(error.agent is c or (type(c) is str and type(error.agent) is str and error.agent == c)
               for c in refusal.culprits), message
    assert shown(error.agent) in message
    assert isinstance(error, UnknownAgentError) is (refusal.kind == "agent"), message
    if refusal.kind == "agent":
        assert isinstance(error, LookupError)


UNKNOWN_AGENTS = ["home_2", "away_7", "", "HOME_0", "home_0 ", "home0", 0, None, 1.5, b"home_0", ("home_0",),
                  AgentId(Side.HOME, 0), Broken()]


@st.composite
def step_actions(draw) -> tuple[object, dict | str, Refusal | None]:
    """(the actions of one step, {agent: Action} or BAD, the refusal they must meet)."""
    kind = draw(st.sampled_from(["dict"] * 12 + ["garbage", "broken"]))
    if kind == "garbage":
        return draw(_one_of([None, [], "home_0", 0, [("home_0", None)], b"", Broken()])), BAD, Refusal("actions", ())
    if kind == "broken":
        return BrokenMapping(draw(st.sampled_from(["iter", "item"]))), BAD, Refusal("actions", ())
    raw: dict = {}
    expected: dict = {}
    for agent in AGENTS:
        if draw(st.booleans()):
            raw[agent], expected[agent] = draw(agent_actions())
    refusal = None
    culprits = tuple(agent for agent, action in expected.items() if action is BAD)
    if culprits:
        refusal = Refusal("action", culprits)
    extra = draw(st.sampled_from(["none"] * 8 + ["unknown", "alias", "twice"]))
    if extra == "unknown":
        key = draw(_one_of(UNKNOWN_AGENTS))
        raw[key] = None
        refusal = Refusal("agent", (key,))  # agent ids are checked before the actions
    elif extra in ("alias", "twice") and raw:
        agent = draw(st.sampled_from(sorted(raw)))
        if extra == "alias":
            raw[Text(agent)] = raw.pop(agent)
        else:
            raw[Twin(agent)] = None
            refusal = Refusal("action", (agent,))
    if refusal is not None:
        return raw, BAD, refusal
    return raw, {agent: expected.get(agent, STAND) for agent in AGENTS}, None


# ---- what an accepted action must be ----------------------------------------------------------

def _assert_plain(action: Action) -> None:
    assert type(action) is Action and type(action.motion) is Motion
    assert type(action.walk) is tuple and len(action.walk) == 3 and all(type(v) is float for v in action.walk)
    WALK_LIMITS.check(*action.walk)
    if action.head is not None:
        assert type(action.head) is tuple and len(action.head) == 2 and all(type(v) is float for v in action.head)
        assert head_limits_check(*action.head) is None  # the world's joint limits
    assert action.camera is None or type(action.camera) is CameraChoice
    assert type(action.radio) is bytes and len(action.radio) <= 128


@FUZZ
@given(case=agent_actions())
def test_every_action_is_checked_field_by_field(case) -> None:
    raw, expected = case
    try:
        action = parse_action("away_0", raw)
    except StepRefusedError as error:
        event(f"refused: {type(error).__name__}")
        assert expected is BAD, f"refused a valid action {shown(raw)}: {error}"
        _assert_refusal(error, Refusal("action", ("away_0",)), raw)
        if isinstance(error, InvalidActionError):
            assert shown(error.field) in str(error)
        return
    event("accepted")
    assert expected is not BAD, f"accepted an invalid action {shown(raw)} as {action}"
    _assert_plain(action)
    assert action == expected


@pytest.fixture(scope="module")
def twins():
    """Two free-play environments of three robots (nobody held, every command applied)."""
    envs = [parallel_env(config=MatchConfig(free_play=FreePlay(STARTS, settle_steps=0))) for _ in range(2)]
    yield envs
    for env in envs:
        env.close()


@settings(FUZZ, max_examples=500)
@given(case=step_actions())
def test_every_step_is_checked_before_anything_happens(twins, case) -> None:
    raw, expected, refusal = case
    try:
        checked = twins[0].match.check_actions(raw)
    except StepRefusedError as error:
        event(f"refused: {type(error).__name__}")
        _assert_refusal(error, refusal, raw)
        return
    event("accepted")
    assert expected is not BAD, f"accepted invalid actions {shown(raw)} as {checked}"
    assert {str(agent): action for agent, action in checked.items()} == expected


# ---- a refused step changes nothing -------------------------------------------------------------

FOLLOW = {
    "home_0": make_action(Motion.WALK, walk=(0.1, 0.05, 0.2), head=(0.3, 0.1), radio=b"after"),
    "home_1": make_action(Motion.TURN_LEFT_20, camera=2, radio=b"again"),
    "away_0": make_action(Motion.FORWARD, head=(-0.2, 0.2), camera=1),
}


def _arrays(value, path: str = "") -> Iterator[tuple[str, str, tuple, bytes]]:
    if isinstance(value, dict):
        for key in sorted(value):
            yield from _arrays(value[key], f"{path}/{key}")
    elif isinstance(value, (list, tuple)):
        for i, item in enumerate(value):
            yield from _arrays(item, f"{path}/{i}")
    else:
        array = np.asarray(value)
        yield path, array.dtype.str, array.shape, array.tobytes()


def _state(env: RobotStadiumEnv) -> tuple:
    match = env.match
    return (match.truth(), match.step_index, env.num_cycles, match.world.rng.bit_generator.state,
            match.radio.rng.bit_generator.state, match.radio.counts)


def _assert_same_step(result, twin_result) -> None:
    assert list(_arrays(result)) == list(_arrays(twin_result))


@pytest.mark.render
@settings(FUZZ, max_examples=25)
@given(steps=st.lists(step_actions(), min_size=1, max_size=3), seed=st.integers(0, 3))
def test_a_refused_step_changes_nothing(twins, steps, seed) -> None:
    """The environment fed every step stays byte for byte the twin fed only the accepted ones."""
    env, twin = twins
    _assert_same_step(env.reset(seed=seed), twin.reset(seed=seed))
    for raw, expected, refusal in steps:
        try:
            result = env.step(raw)
        except StepRefusedError as error:
            event("a step refused")
            _assert_refusal(error, refusal, raw)
            assert _state(env) == _state(twin)
            continue
        event("a step accepted")
        assert expected is not BAD
        _assert_same_step(result, twin.step(raw))
        assert _state(env) == _state(twin)
    # commands, packets and draws a refused step let through would show now
    _assert_same_step(env.step(FOLLOW), twin.step(FOLLOW))
    assert _state(env) == _state(twin)


REPORTED = {
    "action head past its joint limit": Action(Motion.STAND, head=(9.0, 0.0)),
    "action motion index too large": Action(motion=99),
    "action motion a bool": Action(motion=True),
    "walk past float range": {"walk": [10**400, 0, 0]},
    "camera a timedelta": {"camera": np.timedelta64(1)},
    "motion a timedelta": {"motion": np.timedelta64(1)},
    "walk numeric strings": {"walk": ["0.1", b"0", "0"]},
    "head bools": {"head": [True, False]},
    "motion a bool": {"motion": True},
    "head complex": {"head": [0.1 + 0.5j, 0.0]},
    "head masked": {"head": np.ma.masked_array([9.0, 0.0], mask=[True, False])},
    "head object array": {"head": np.array([0.0, 0.0], dtype=object)},
    "walk nested": {"walk": [[0.0], [0.0], [0.0]]},
}


@pytest.mark.render
@pytest.mark.parametrize("bad", list(REPORTED.values()), ids=list(REPORTED))
def test_the_reported_actions_are_refused_and_change_nothing(twins, bad) -> None:
    env, twin = twins
    env.reset(seed=5)
    twin.reset(seed=5)
    with pytest.raises(StepRefusedError, match="'home_1'"):
        env.step({"home_0": make_action(Motion.FORWARD, radio=b"hi"), "home_1": bad})
    assert _state(env) == _state(twin)
    _assert_same_step(env.step(FOLLOW), twin.step(FOLLOW))


@pytest.mark.render
def test_a_step_without_a_dict_of_actions_is_refused(twins) -> None:
    env, _ = twins
    env.reset(seed=0)
    for actions in (None, [("home_0", None)], "home_0"):
        with pytest.raises(StepRefusedError, match="expected a dict of agent id -> action") as raised:
            env.step(actions)
        assert type(raised.value) is StepRefusedError and raised.value.agent is None


def test_an_action_of_plain_checked_values_passes_again_as_itself_and_only_such_a_one() -> None:
    checked = parse_action("home_0", {"motion": "walk", "walk": (0.0, 0.0, 0.2), "head": (0.1, 0.2)})
    assert parse_action("away_1", checked) is checked  # checked again, e.g. in a controller process's answer
    twin = Action(checked.motion, walk=(False, 0.0, 0.2), head=checked.head)  # equal to it, but not plain values
    assert twin == checked
    with pytest.raises(InvalidActionError, match="walk"):
        parse_action("home_0", twin)
    forged = Action(Motion.WALK, walk=(float("nan"), 0.0, 0.0))
    with pytest.raises(InvalidActionError, match="walk"):
        parse_action("home_0", forged)
    object.__setattr__(checked, "camera", 7)  # the reported forgery: frozen does not stop object.__setattr__
    with pytest.raises(InvalidActionError, match="'home_0': action field 'camera' = 7 is invalid"):
        parse_action("home_0", checked)
    object.__setattr__(checked, "camera", 1)  # a value the check accepts: a new Action of plain values
    assert parse_action("home_0", checked) == Action(Motion.WALK, (0.0, 0.0, 0.2), (0.1, 0.2), CameraChoice.TOP)


@pytest.mark.render
def test_a_step_with_a_forged_action_moves_no_head(twins) -> None:
    """The reported half-applied step: a forged 5,000-byte packet of home_1 and a head command of home_0."""
    env, twin = twins
    env.reset(seed=2)
    twin.reset(seed=2)
    forged = parse_action("home_1", make_action(Motion.STAND))
    object.__setattr__(forged, "radio", b"x" * 5000)
    with pytest.raises(InvalidActionError, match="'home_1': action field 'radio' = <bytes of length 5000") as raised:
        env.step({"home_0": make_action(Motion.STAND, head=(1.5, 0.3)), "home_1": forged})
    assert raised.value.agent == "home_1" and raised.value.field == "radio"
    assert _state(env) == _state(twin)
    _assert_same_step(env.step(FOLLOW), twin.step(FOLLOW))


def test_a_policy_returning_forged_actions_costs_only_its_robot_in_process(tmp_path) -> None:
    import json

    from scenarios.matches.play import Lineup, run_lineup_match

    lineup = Lineup("stand", "stand", {"home_0": "tests.user_policies:Forges"})
    run_lineup_match(tmp_path, lineup, home=2, away=1, half_seconds=60.0, seed=1, progress=False, max_steps=12,
                     referee={"initial_seconds": 0.2, "ready_seconds": 0.4, "set_seconds": 0.2}, controllers=None)
    summary = json.loads((tmp_path / "summary.json").read_text(encoding="utf-8"))
    assert summary["completed"] and summary["steps"] == 12
    assert summary["faults"]["by_agent"] == {"home_0": 12}  # each forgery refused: the robot stood
    errors = [d["error"] for d in summary["faults"]["details"]]
    for field in ("camera", "radio", "walk", "motion", "head"):
        assert any(f"action field '{field}'" in error for error in errors), field
    assert all(error.startswith(("InvalidActionError", "RadioPacketError")) for error in errors)


# ---- the AEC env: each action checked at its own agent's turn ------------------------------------


def _aec(parallel: RobotStadiumEnv):
    """The env's AEC view as ``match.env.env`` builds it, over an env of the fixture."""
    from pettingzoo.utils.wrappers import OrderEnforcingWrapper

    from match.env import CheckedTurns

    return OrderEnforcingWrapper(CheckedTurns(parallel))


@pytest.mark.render
def test_the_aec_env_refuses_the_reported_action_to_its_agent_and_goes_on(twins) -> None:
    env, twin = twins
    aec = _aec(env)
    aec.reset(seed=3)
    twin.reset(seed=3)
    assert aec.agent_selection == "home_0"
    with pytest.raises(InvalidActionError) as raised:
        aec.step({"motion": 17, "walk": [math.nan, 0, 0]})
    message = str(raised.value)
    assert raised.value.agent == "home_0" and "'home_0'" in message and "expected" in message
    assert raised.value.field in ("motion", "walk") and f"'{raised.value.field}'" in message
    assert aec.agent_selection == "home_0" and _state(env) == _state(twin)
    for agent in AGENTS:  # the turn goes on: every agent acts, the match steps once
        assert aec.agent_selection == agent
        aec.step(FOLLOW[agent])
    twin.step(FOLLOW)
    assert _state(env) == _state(twin)


@pytest.mark.render
@settings(FUZZ, max_examples=12)
@given(turns=st.lists(agent_actions(), min_size=3, max_size=8), seed=st.integers(0, 3))
def test_a_refused_turn_is_refused_to_its_agent_and_changes_nothing(twins, turns, seed) -> None:
    """The AEC env fed every turn stays the twin parallel env fed only the accepted actions, step by step."""
    env, twin = twins
    aec = _aec(env)
    aec.reset(seed=seed)
    twin.reset(seed=seed)
    taken: dict[str, object] = {}
    for raw, expected in turns:
        agent = aec.agent_selection
        try:
            aec.step(raw)
        except StepRefusedError as error:
            event("a turn refused")
            assert expected is BAD, f"refused a valid action {shown(raw)}: {error}"
            _assert_refusal(error, Refusal("action", (agent,)), raw)
            assert aec.agent_selection == agent
            assert _state(env) == _state(twin)
            continue
        event("a turn accepted")
        assert expected is not BAD, f"accepted an invalid action {shown(raw)}"
        taken[agent] = raw
        if agent == AGENTS[-1]:  # the last turn stepped the match
            observations = twin.step(taken)[0]
            taken = {}
            for name in AGENTS:
                _assert_same_step(aec.observe(name), observations[name])
        assert _state(env) == _state(twin)


# ---- a refusal costs its message, not the payload --------------------------------------------------


REFUSAL_S = 0.05  # any payload: CPU time of the refusing thread, whatever else the machine runs
HUGE_REFUSAL_S = 0.5  # the 200 MiB one: wall time, on a machine shared with other jobs


def _payload(kind: str, size: int) -> tuple[str, object]:
    """(the agent whose action carries it, a step's actions with a payload of about ``size`` bytes or items)."""
    blob = b"x" * size
    if kind == "forged radio":
        action = parse_action("home_1", make_action(Motion.STAND))
        object.__setattr__(action, "radio", blob)
        return "home_1", {"home_1": action}
    if kind == "forged walk":
        action = parse_action("home_1", make_action(Motion.STAND))
        object.__setattr__(action, "walk", (0.0,) * size)
        return "home_1", {"home_1": action}
    values = {
        "radio bytes": {"radio": blob},
        "radio bytearray": {"radio": bytearray(blob)},
        "packet data": {"radio": {"data": np.frombuffer(blob, np.uint8), "length": 3}},
        "packet keys": {"radio": {**dict.fromkeys(range(size // 64)), "data": np.zeros(128, np.uint8), "length": 3}},
        "walk list": {"walk": [0.0] * (size // 8)},
        "head array": {"head": np.zeros(size // 8)},
        "motion text": {"motion": "w" * size},
        "camera text": {"camera": Text("t" * size)},
        "field keys": dict.fromkeys(map(str, range(size // 64))),
    }
    if kind == "agent keys":
        return "", {"home_0": None, **dict.fromkeys(map(str, range(size // 64)))}
    return "home_1", {"home_0": make_action(Motion.STAND, head=(1.0, 0.2)), "home_1": values[kind]}


PAYLOADS = ["forged radio", "forged walk", "radio bytes", "radio bytearray", "packet data", "packet keys", "walk list",
            "head array", "motion text", "camera text", "field keys", "agent keys"]


def _refusal_seconds(check, actions: object, clock=time.perf_counter) -> tuple[float, StepRefusedError]:
    started = clock()
    try:
        check(actions)
    except StepRefusedError as error:
        elapsed = clock() - started
        return elapsed, error
    raise AssertionError("the payload was accepted")


@settings(FUZZ, max_examples=60)
@given(kind=st.sampled_from(PAYLOADS), size=st.integers(10, 23).map(lambda k: 2**k))
def test_a_refusal_costs_its_message_not_the_payload(twins, kind, size) -> None:
    agent, actions = _payload(kind, size)
    seconds, error = _refusal_seconds(twins[0].match.check_actions, actions, time.thread_time)
    assert seconds < REFUSAL_S, (kind, size, seconds)
    message = str(error)
    assert "\n" not in message and len(message) < 1200, message
    if agent:
        assert error.agent == agent and isinstance(error, InvalidActionError)
    else:
        assert isinstance(error, UnknownAgentError)


@pytest.mark.render
def test_a_step_with_a_200_mib_packet_is_refused_at_once_and_changes_nothing(twins) -> None:
    env, twin = twins
    env.reset(seed=1)
    twin.reset(seed=1)
    for kind in ("radio bytes", "forged radio"):
        _, actions = _payload(kind, 200 << 20)
        seconds, error = _refusal_seconds(env.step, actions)
        assert seconds < HUGE_REFUSAL_S, (kind, seconds)
        assert error.agent == "home_1" and len(str(error)) < 400
        assert _state(env) == _state(twin)
    _assert_same_step(env.step(FOLLOW), twin.step(FOLLOW))


@pytest.mark.render
@settings(FUZZ, max_examples=30)
@given(kind=st.sampled_from([kind for kind in PAYLOADS if kind != "agent keys"]),
       size=st.integers(10, 23).map(lambda k: 2**k))
def test_the_aec_env_refuses_any_payload_at_its_turn_at_once_and_goes_on(twins, kind, size) -> None:
    """A payload at home_1's turn: refused in its message's time, to home_1, with the turn and the match as they
    were; the turn then goes on as in the twin fed only the valid actions."""
    env, twin = twins
    aec = _aec(env)
    aec.reset(seed=1)
    twin.reset(seed=1)
    aec.step(FOLLOW["home_0"])
    _, actions = _payload(kind, size)
    seconds, error = _refusal_seconds(aec.step, actions["home_1"], time.thread_time)
    assert seconds < REFUSAL_S, (kind, size, seconds)
    assert isinstance(error, InvalidActionError) and error.agent == "home_1" and len(str(error)) < 1200
    assert aec.agent_selection == "home_1" and _state(env) == _state(twin)
    aec.step(FOLLOW["home_1"])
    aec.step(FOLLOW["away_0"])
    twin.step(FOLLOW)
    assert _state(env) == _state(twin)
