"""Views of the env for learners: image-only and flat-vector observations, discrete actions.

Each is a PettingZoo parallel wrapper of :class:`match.env.RobotStadiumEnv` (or of another of
these wrappers) that gives every agent the same standard gymnasium space, so SuperSuit's
wrappers (``color_reduction_v0``, ``resize_v1``, ``frame_stack_v1``) and vector envs
(``pettingzoo_env_to_vec_env_v1``, ``concat_vec_envs_v1``) and Stable-Baselines3 take them as
they are. A wrapper holds only its settings and the env it wraps, so a copy (``pickle``,
``copy.deepcopy``, a SuperSuit worker process) builds its own world as the env does.

- :class:`ImageObservations`: the camera image alone, ``Box(0, 255, (120, 160, 3), uint8)``.
- :class:`FlatObservations`: everything but the image as one float32 vector, each entry
  scaled onto [-1, 1] (:mod:`match.flat_scales`), or in its own units.
- :class:`DiscreteActions`: ``MultiDiscrete`` (or ``Discrete``) choices of a motion, head
  angles and a camera, and optionally a one-byte radio symbol (:class:`ActionSet`).

A learner that wants the landmarks and the ball an agent sees, without pixels, uses
:class:`agents.learning.PerceptObservations` (it runs the agents' vision, which ``match``
may not import: docs/design/index.md section 2).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from gymnasium import spaces
from pettingzoo.utils.wrappers import BaseParallelWrapper

from match.errors import InvalidActionError, MatchConfigError, shown
from match.flat_scales import scaled_layout
from match.protocol.actions import make_action
from match.protocol.spaces import HEAD_HIGH, HEAD_LOW, IMAGE_SHAPE, WALK_HIGH, WALK_LOW, CameraChoice
from world.motions import Motion

# ---- observations -------------------------------------------------------------------------


class _ObservationWrapper(BaseParallelWrapper):
    """A parallel wrapper that maps every agent's observation (``_convert``) into ``_space``."""

    _space: spaces.Space

    def observation_space(self, agent: str) -> spaces.Space:
        self.env.observation_space(agent)  # refuses an unknown agent as the env does
        return self._space

    def reset(self, seed: int | None = None, options: dict | None = None):
        observations, infos = self.env.reset(seed=seed, options=options)
        return {a: self._convert(a, o) for a, o in observations.items()}, infos

    def step(self, actions: dict):
        observations, rewards, terminations, truncations, infos = self.env.step(actions)
        return {a: self._convert(a, o) for a, o in observations.items()}, rewards, terminations, truncations, infos

    def _convert(self, agent: str, observation):  # pragma: no cover - every subclass has its own
        raise NotImplementedError


class ImageObservations(_ObservationWrapper):
    """Each agent's observation is its camera image alone.

    ``Box(0, 255, (120, 160, 3), uint8)``: RGB, rows top to bottom, from the camera the
    action chose (top or bottom); all zeros on a step whose camera is off, so keep the
    camera on (``camera`` 1 or 2 in every action, or :class:`DiscreteActions` with cameras
    ``(TOP,)``). SuperSuit's image wrappers apply as they are, e.g.
    ``frame_stack_v1(resize_v1(color_reduction_v0(ImageObservations(env)), 84, 84), 4)``.
    """

    def __init__(self, env):
        super().__init__(env)
        self._space = spaces.Box(0, 255, IMAGE_SHAPE, np.uint8)

    def _convert(self, agent: str, observation) -> np.ndarray:
        return observation["image"]


RADIO_PACKET_KEYS = ("sender", "length", "data")  # of the inbox: left out of a flat vector without radio


@dataclass(frozen=True)
class FlatLayout:
    """Where each value of an observation dict lies in a flat vector.

    ``paths``: the key path of every value, in the order of the vector (the order of the
    observation space's keys); ``sizes``: how many entries each takes (a ``Discrete`` value
    one, its index; a ``Box`` or ``MultiBinary`` all its elements, flattened in C order);
    ``labels``: one name per entry (``"head/0"``, ``"game/score/1"``, ``"fallen"``);
    ``space``: the float32 ``Box`` of the vector, with the observation space's bounds.
    """

    paths: tuple[tuple[str, ...], ...]
    sizes: tuple[int, ...]
    labels: tuple[str, ...]
    space: spaces.Box

    def flatten(self, observation: Mapping) -> np.ndarray:
        """The vector (float32) of an observation dict laid out as the observation space."""
        parts = []
        for path in self.paths:
            value = observation
            for key in path:
                value = value[key]
            parts.append(np.asarray(value, np.float32).reshape(-1))
        return np.concatenate(parts)


def flat_layout(space: spaces.Dict, radio: bool = False) -> FlatLayout:
    """The layout of the non-image part of an observation space (:func:`match.protocol.observation_space`).

    Without ``radio`` the inbox's packets (``radio/sender``, ``radio/length``,
    ``radio/data``: 8 + 8 + 1024 entries) are left out; ``radio/count`` and
    ``radio/dropped`` stay. Units are the observation's own (SI: m, s, rad, m/s^2, rad/s);
    discrete values (game state, motion, camera...) are their indices, not one-hot.
    """
    paths: list[tuple[str, ...]] = []
    sizes: list[int] = []
    labels: list[str] = []
    lows: list[np.ndarray] = []
    highs: list[np.ndarray] = []

    def visit(sub: spaces.Space, path: tuple[str, ...]) -> None:
        if isinstance(sub, spaces.Dict):
            for key, child in sub.spaces.items():
                visit(child, (*path, key))
            return
        if path == ("image",) or (not radio and path[0] == "radio" and path[-1] in RADIO_PACKET_KEYS):
            return
        if isinstance(sub, spaces.Discrete):
            low, high = np.array([sub.start]), np.array([sub.start + sub.n - 1])
        elif isinstance(sub, spaces.MultiBinary):
            low, high = np.zeros(int(np.prod(sub.shape))), np.ones(int(np.prod(sub.shape)))
        elif isinstance(sub, spaces.Box):
            low, high = sub.low.reshape(-1), sub.high.reshape(-1)
        else:
            raise MatchConfigError(f"observation space at {'/'.join(path)} is {sub!r}; expected Discrete, MultiBinary "
                                   "or Box")
        name = "/".join(path)
        paths.append(path)
        sizes.append(low.size)
        labels.extend([name] if sub.shape == () else [f"{name}/{i}" for i in range(low.size)])
        lows.append(low.astype(np.float64))
        highs.append(high.astype(np.float64))

    visit(space, ())
    box = spaces.Box(np.concatenate(lows).astype(np.float32), np.concatenate(highs).astype(np.float32), dtype=np.float32)
    return FlatLayout(tuple(paths), tuple(sizes), tuple(labels), box)


class FlatObservations(_ObservationWrapper):
    """Each agent's observation is a float32 vector of everything but its image.

    The entries are the observation dict's values in the order of the observation space's
    keys (``accelerometer`` m/s^2, ``bumpers``, ``camera``, ``fallen``, ``game/...``,
    ``gyro`` rad/s, ``head`` rad, the motion status, ``odometry`` m, m, rad, ``radio/count``,
    ``radio/dropped``, ``sonar`` m; torso frame; discrete values as their index). With
    ``radio=True`` the inbox's senders, lengths and bytes are in it too (1040 more entries).

    ``scaled=True`` (the default): every entry lies in [-1, 1] (:mod:`match.flat_scales`: each
    value clipped to its documented range and mapped linearly; the two placeholder values,
    ``motion_remaining_s`` of the endless walk and ``game/seconds_since_drop_in`` before any
    throw-in, as a flag plus a bounded value); 45 entries without radio; ``labels`` names each.
    ``scaled=False``: the values in their own units within the observation space's bounds
    (43 entries; ``layout.labels``), placeholders included.
    """

    def __init__(self, env, radio: bool = False, scaled: bool = True):
        if not isinstance(radio, bool):
            raise MatchConfigError(f"radio = {shown(radio)}; expected True or False")
        if not isinstance(scaled, bool):
            raise MatchConfigError(f"scaled = {shown(scaled)}; expected True or False")
        super().__init__(env)
        self.radio = radio
        self.scaled = scaled
        self.layout = flat_layout(env.observation_space(env.possible_agents[0]), radio=radio)
        self.scales = scaled_layout(self.layout.paths, self.layout.sizes, self.layout.labels, self.layout.space)
        self.labels = self.scales.labels if scaled else self.layout.labels
        self._space = self.scales.space if scaled else self.layout.space

    def _convert(self, agent: str, observation) -> np.ndarray:
        raw = self.layout.flatten(observation)
        return self.scales.scale(raw) if self.scaled else raw


# ---- actions ------------------------------------------------------------------------------

Walk = tuple[float, float, float]
STILL: Walk = (0.0, 0.0, 0.0)

DEFAULT_MOTIONS: tuple[tuple[Motion, Walk], ...] = (
    (Motion.STAND, STILL),
    (Motion.WALK, (0.2, 0.0, 0.0)),  # ahead, m/s
    (Motion.WALK, (-0.1, 0.0, 0.0)),
    (Motion.WALK, (0.0, 0.1, 0.0)),  # left
    (Motion.WALK, (0.0, -0.1, 0.0)),
    (Motion.WALK, (0.0, 0.0, 0.6)),  # turn left, rad/s
    (Motion.WALK, (0.0, 0.0, -0.6)),
    (Motion.WALK, (0.15, 0.0, 0.4)),  # curve left
    (Motion.WALK, (0.15, 0.0, -0.4)),
    (Motion.KICK_LEFT, STILL),
    (Motion.KICK_RIGHT, STILL),
    (Motion.STAND_UP_FROM_FRONT, STILL),
    (Motion.STAND_UP_FROM_BACK, STILL),
)
"""(motion, walk (vx m/s, vy m/s, omega rad/s)) choices of :class:`ActionSet`: standing, eight
walks, both kicks and both ways of standing up."""

_DEG = math.pi / 180.0
DEFAULT_HEADS: tuple[tuple[float, float], ...] = tuple(
    (yaw * _DEG, pitch * _DEG) for pitch in (0.0, 15.0, 29.0) for yaw in (-90.0, -45.0, 0.0, 45.0, 90.0)
)
"""(yaw, pitch) head targets, rad (yaw CCW positive, pitch positive looking down): yaw -90 to 90
degrees in steps of 45, at pitch 0, 15 and 29 degrees down (15 choices)."""

DEFAULT_CAMERAS: tuple[CameraChoice, ...] = (CameraChoice.TOP, CameraChoice.BOTTOM, CameraChoice.OFF)
MAX_RADIO_SYMBOLS = 255


@dataclass(frozen=True)
class ActionSet:
    """The choices of :class:`DiscreteActions`: one motion, one head target and one camera per step, and
    with ``radio_symbols`` n > 0 a radio choice 0-n (0: no packet; k: the one-byte packet ``bytes([k])``).

    ``motions``: (motion, walk) pairs, walk (vx m/s, vy m/s, omega rad/s) used by
    ``Motion.WALK`` only (zeros otherwise); ``heads``: (yaw, pitch) targets, rad; ``cameras``:
    :class:`~match.protocol.spaces.CameraChoice` values. Re-sending the motion that plays
    continues it; another one interrupts it (as in the env's actions).
    """

    motions: tuple[tuple[Motion, Walk], ...] = DEFAULT_MOTIONS
    heads: tuple[tuple[float, float], ...] = DEFAULT_HEADS
    cameras: tuple[CameraChoice, ...] = DEFAULT_CAMERAS
    radio_symbols: int = 0

    def __post_init__(self) -> None:
        for name in ("motions", "heads", "cameras"):
            if not isinstance(getattr(self, name), tuple) or not getattr(self, name):
                raise MatchConfigError(f"ActionSet {name} = {shown(getattr(self, name))}; expected a non-empty tuple")
        for choice in self.motions:
            if (not isinstance(choice, tuple) or len(choice) != 2 or not isinstance(choice[0], Motion)
                    or not _within(choice[1], WALK_LOW, WALK_HIGH)
                    or (choice[0] is not Motion.WALK and tuple(choice[1]) != STILL)):
                raise MatchConfigError(
                    f"ActionSet motion {shown(choice)}; expected (Motion, (vx, vy, omega)) with the walk within "
                    f"{WALK_LOW} .. {WALK_HIGH} (zeros unless the motion is WALK)")
        for head in self.heads:
            if not _within(head, HEAD_LOW, HEAD_HIGH):
                raise MatchConfigError(f"ActionSet head {shown(head)}; expected (yaw, pitch) rad within "
                                       f"{HEAD_LOW} .. {HEAD_HIGH}")
        for camera in self.cameras:
            if not isinstance(camera, CameraChoice):
                raise MatchConfigError(f"ActionSet camera {shown(camera)}; expected a CameraChoice")
        if (isinstance(self.radio_symbols, bool) or not isinstance(self.radio_symbols, int)
                or not 0 <= self.radio_symbols <= MAX_RADIO_SYMBOLS):
            raise MatchConfigError(f"ActionSet radio_symbols = {shown(self.radio_symbols)}; expected an integer "
                                   f"0-{MAX_RADIO_SYMBOLS}")

    @property
    def nvec(self) -> tuple[int, ...]:
        """How many choices each dimension has: motions, heads, cameras (and radio: symbols + 1)."""
        sizes = (len(self.motions), len(self.heads), len(self.cameras))
        return sizes + ((self.radio_symbols + 1,) if self.radio_symbols else ())

    def action(self, choice: tuple[int, ...]) -> dict:
        """The env action of one choice per dimension (indices already checked)."""
        motion, walk = self.motions[choice[0]]
        radio = bytes([choice[3]]) if self.radio_symbols and choice[3] else b""
        return make_action(motion, walk=walk, head=self.heads[choice[1]], camera=self.cameras[choice[2]], radio=radio)


def _within(values: object, low: tuple[float, ...], high: tuple[float, ...]) -> bool:
    try:
        numbers = [float(v) for v in values]  # type: ignore[union-attr]
    except (TypeError, ValueError):
        return False
    return len(numbers) == len(low) and all(lo <= v <= hi for v, lo, hi in zip(numbers, low, high))


class DiscreteActions(BaseParallelWrapper):
    """Each agent acts by a choice per dimension of an :class:`ActionSet` instead of an action dict.

    The action space is ``MultiDiscrete(action_set.nvec)``: [motion, head, camera] (and
    [..., radio] with radio symbols), or with ``flat=True`` one ``Discrete`` over every
    combination (index = motion * (heads * cameras * ...) + head * (cameras * ...) + ...,
    C order). Action spaces are seeded as the env's (agent ``i`` with the env's
    ``space_seed(i)``: ``i`` for an env built directly, fresh entropy for a copy). An agent
    without an action, or with None, stands (as in the env). A choice outside its range, or
    not integers, is refused with an :class:`~match.errors.InvalidActionError` naming the agent
    and the value, before the env steps.
    """

    def __init__(self, env, action_set: ActionSet | None = None, flat: bool = False):
        if action_set is not None and not isinstance(action_set, ActionSet):
            raise MatchConfigError(f"action_set = {shown(action_set)}; expected an ActionSet or None")
        if not isinstance(flat, bool):
            raise MatchConfigError(f"flat = {shown(flat)}; expected True or False")
        super().__init__(env)
        self.action_set = action_set or ActionSet()
        self.flat = flat
        nvec = self.action_set.nvec
        self._spaces = {}
        for agent in env.possible_agents:
            self._spaces[agent] = spaces.Discrete(int(np.prod(nvec))) if flat else spaces.MultiDiscrete(nvec)
        self._seed_spaces()

    def __setstate__(self, state: dict) -> None:
        """A copy's spaces are seeded as its env's (apart from the original's)."""
        self.__dict__.update(state)
        self._seed_spaces()

    def _seed_spaces(self) -> None:
        space_seed = getattr(self.env.unwrapped, "space_seed", None)
        for i, agent in enumerate(self.env.possible_agents):
            self._spaces[agent].seed(i if space_seed is None else space_seed(i))

    def action_space(self, agent: str) -> spaces.Space:
        self.env.action_space(agent)  # refuses an unknown agent as the env does
        return self._spaces[agent]

    def step(self, actions: dict):
        if isinstance(actions, Mapping):
            actions = {agent: self._action(agent, raw) for agent, raw in actions.items()}
        return self.env.step(actions)  # the env refuses what is not a dict and unknown agents

    def _action(self, agent: object, raw: object) -> object:
        if raw is None or not isinstance(agent, str) or agent not in self._spaces:
            return raw
        nvec = self.action_set.nvec
        choice = _choices(raw, len(nvec), self.flat)
        if choice is not None and self.flat:
            choice = np.unravel_index(choice[0], nvec) if 0 <= choice[0] < int(np.prod(nvec)) else None
        if choice is None or not all(0 <= c < n for c, n in zip(choice, nvec)):
            expected = (f"an integer in [0, {int(np.prod(nvec)) - 1}]" if self.flat else
                        f"{len(nvec)} integers, each in [0, n) for n in {list(nvec)} (motion, head, camera"
                        f"{', radio' if self.action_set.radio_symbols else ''})")
            raise InvalidActionError(agent, "action", raw, expected)
        return self.action_set.action(tuple(int(c) for c in choice))


def _choices(raw: object, size: int, flat: bool) -> tuple[int, ...] | None:
    """Integers (not bools) as a tuple: one for ``flat``, else ``size``; None if ``raw`` is not that."""
    if flat:
        return None if (index := _integer(raw)) is None else (index,)
    if type(raw) is np.ndarray:
        if raw.dtype.kind not in "iu" or raw.shape != (size,):
            return None
        return tuple(int(v) for v in raw.tolist())
    if not isinstance(raw, (list, tuple)) or len(raw) != size:
        return None
    values = [_integer(v) for v in raw]
    return None if any(v is None for v in values) else tuple(values)  # type: ignore[misc]


def _integer(value: object) -> int | None:
    if isinstance(value, bool) or isinstance(value, np.bool_):
        return None
    if isinstance(value, int):
        return int(value)
    if isinstance(value, np.integer) or (type(value) is np.ndarray and value.dtype.kind in "iu" and value.shape == ()):
        return int(value)
    return None
