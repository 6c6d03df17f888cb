"""The agents' percepts as a learner's observation: landmarks and the ball, no pixels.

:class:`PerceptObservations` wraps the PettingZoo env (or one of :mod:`match.wrappers`' action
wrappers) and replaces each agent's observation by a fixed-size float32 vector of what the
agent side sees in that observation: the landmark percepts of the vision pipeline (thesis
chapter 4, :class:`agents.vision.pipeline.VisionPipeline`) and the ball
(:func:`agents.vision.ball.ball_in_mask`), with the head angles they were seen at. It lives
in ``agents`` because it runs the agents' vision, which ``match`` may not import
(docs/design/index.md section 2); like every agent it reads nothing but the observation.

Layout (:data:`PERCEPT_LABELS` names every entry), bearings CCW positive in the torso frame
(rad, 0 straight ahead of the torso), distances on the ground from the point below the torso
(m), everything 0 where nothing was seen::

    0      head yaw rad, CCW positive        1  head pitch rad, positive looking down
    2      camera: 0 off, 1 top, 2 bottom
    3..5   ball: seen (0 or 1), bearing rad, distance m
    6..56  the 17 landmarks of world.field.FIELD.landmarks in order, 3 each: seen, bearing, distance
           (percepts the image identifies: goal posts of known side, goal centres, the circle)
    57..84 7 slots of percepts the image does not identify, 4 each: seen, bearing, distance,
           goal (-1 blue, +1 yellow, 0 none): 2 goal posts, 3 L corners, 2 T junctions, nearest first

A step whose camera is off sees nothing. 85 entries.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np
from gymnasium import spaces
from pettingzoo.utils.wrappers import BaseParallelWrapper

from agents.observation import Observation
from agents.vision.ball import MAX_DISTANCE_M, ball_in_mask, plausible
from agents.vision.camera_models import DEFAULT_CAMERA_MODEL, camera_model
from agents.vision.colors import ColorClass
from agents.vision.frame import CameraFrame
from agents.vision.percepts import LandmarkPercept
from agents.vision.pipeline import VisionPipeline
from match.protocol import CameraChoice
from world.camera_model import NAO_HEAD
from world.field import FIELD, GoalColor, LandmarkKind

PERCEPT_DISTANCE_LIMIT_M = 10.0  # longer than the hall's diagonal; farther percepts are clipped to it
UNIDENTIFIED_SLOTS: tuple[tuple[LandmarkKind, int], ...] = (
    (LandmarkKind.GOAL_POST, 2),
    (LandmarkKind.L_CORNER, 3),
    (LandmarkKind.T_JUNCTION, 2),
)
LANDMARK_INDEX = {landmark.id: i for i, landmark in enumerate(FIELD.landmarks)}
_GOAL_SIGN = {GoalColor.BLUE: -1.0, GoalColor.YELLOW: 1.0, None: 0.0}


def _labels() -> tuple[str, ...]:
    labels = ["head_yaw", "head_pitch", "camera", "ball/seen", "ball/bearing", "ball/distance"]
    for landmark in FIELD.landmarks:
        labels += [f"{landmark.id.value}/{name}" for name in ("seen", "bearing", "distance")]
    for kind, count in UNIDENTIFIED_SLOTS:
        for slot in range(count):
            labels += [f"{kind.value}_{slot}/{name}" for name in ("seen", "bearing", "distance", "goal")]
    return tuple(labels)


PERCEPT_LABELS = _labels()
HEAD = slice(0, 3)
BALL = slice(3, 6)
IDENTIFIED = 6
UNIDENTIFIED = IDENTIFIED + 3 * len(FIELD.landmarks)


def percept_space() -> spaces.Box:
    """The float32 Box of the percept vector (bounds per entry, see the module docstring)."""
    low = np.zeros(len(PERCEPT_LABELS), np.float32)
    high = np.zeros(len(PERCEPT_LABELS), np.float32)
    (yaw_low, yaw_high), (pitch_low, pitch_high) = NAO_HEAD.yaw_limits_rad, NAO_HEAD.pitch_limits_rad
    low[HEAD], high[HEAD] = (yaw_low, pitch_low, 0.0), (yaw_high, pitch_high, len(CameraChoice) - 1)
    for i, label in enumerate(PERCEPT_LABELS[3:], start=3):
        name = label.rsplit("/", 1)[1]
        low[i], high[i] = {"seen": (0.0, 1.0), "bearing": (-math.pi, math.pi), "goal": (-1.0, 1.0),
                           "distance": (0.0, PERCEPT_DISTANCE_LIMIT_M)}[name]
    return spaces.Box(low, high, dtype=np.float32)


class PerceptObservations(BaseParallelWrapper):
    """Each agent's observation is the percept vector of its own observation (see the module docstring).

    ``camera_model``: the vision pipeline's camera model (``exact`` or ``thesis``). Actions are
    the wrapped env's. The vision runs every step the camera is on, 1-3 ms a frame. A copy
    (pickle, deepcopy, a SuperSuit worker) builds its own pipeline and its own world.
    """

    def __init__(self, env, camera_model_name: str = DEFAULT_CAMERA_MODEL):
        camera_model(camera_model_name)  # refuses an unknown name now, naming the known ones
        super().__init__(env)
        self.camera_model_name = camera_model_name
        self._space = percept_space()
        self._pipeline: VisionPipeline | None = None

    def __getstate__(self) -> dict:
        """The wrapped env and the settings; a copy builds its own pipeline."""
        return {"env": self.env, "camera_model_name": self.camera_model_name}

    def __setstate__(self, state: dict) -> None:
        self.__init__(state["env"], state["camera_model_name"])

    def observation_space(self, agent: str) -> spaces.Box:
        self.env.observation_space(agent)  # refuses an unknown agent as the env does
        return self._space

    def reset(self, seed: int | None = None, options: dict | None = None):
        observations, infos = self.env.reset(seed=seed, options=options)
        return {a: self.percepts(o) for a, o in observations.items()}, infos

    def step(self, actions: dict):
        observations, rewards, terminations, truncations, infos = self.env.step(actions)
        return {a: self.percepts(o) for a, o in observations.items()}, rewards, terminations, truncations, infos

    def percepts(self, observation: Mapping) -> np.ndarray:
        """The percept vector (float32, :data:`PERCEPT_LABELS`) of one observation dict."""
        if self._pipeline is None:
            self._pipeline = VisionPipeline(self.camera_model_name)
        return percept_vector(self._pipeline, observation)


def percept_vector(pipeline: VisionPipeline, observation: Mapping) -> np.ndarray:
    """The percept vector (float32, :data:`PERCEPT_LABELS`) of one observation dict, seen by ``pipeline``
    (a policy that plays a learned percept policy in a match builds one and calls this every step)."""
    obs = Observation.of(observation)
    vector = np.zeros(len(PERCEPT_LABELS), np.float32)
    vector[HEAD] = (obs.head_yaw_rad, obs.head_pitch_rad, float(obs.camera))
    if obs.image is None:
        return vector
    frame = CameraFrame.from_observation(obs)
    result = pipeline.process(frame)
    mask = result.segmented == int(ColorClass.ORANGE)
    ball = ball_in_mask(mask, frame.head_yaw_rad, frame.head_pitch_rad, frame.camera)
    if ball is not None and plausible(ball):
        vector[BALL] = (1.0, ball.bearing_rad, min(ball.distance_m, MAX_DISTANCE_M))
    _place_landmarks(vector, result.percepts)
    return vector


def _place_landmarks(vector: np.ndarray, percepts: tuple[LandmarkPercept, ...]) -> None:
    """Identified percepts into their landmark's slot, the others into their kind's slots, nearest first."""
    unidentified: dict[LandmarkKind, list[LandmarkPercept]] = {kind: [] for kind, _ in UNIDENTIFIED_SLOTS}
    for percept in sorted(percepts, key=lambda p: p.distance_m):
        distance = min(max(percept.distance_m, 0.0), PERCEPT_DISTANCE_LIMIT_M)
        bearing = math.remainder(percept.bearing_rad, math.tau)
        if percept.landmark_id is not None:
            start = IDENTIFIED + 3 * LANDMARK_INDEX[percept.landmark_id]
            if vector[start] == 0.0:  # two percepts of one landmark: the nearer one
                vector[start:start + 3] = (1.0, bearing, distance)
        elif percept.kind in unidentified:
            unidentified[percept.kind].append(percept)
    start = UNIDENTIFIED
    for kind, count in UNIDENTIFIED_SLOTS:
        for slot, percept in enumerate(unidentified[kind][:count]):
            distance = min(max(percept.distance_m, 0.0), PERCEPT_DISTANCE_LIMIT_M)
            bearing = math.remainder(percept.bearing_rad, math.tau)
            vector[start + 4 * slot:start + 4 * slot + 4] = (1.0, bearing, distance, _GOAL_SIGN[percept.goal])
        start += 4 * count
