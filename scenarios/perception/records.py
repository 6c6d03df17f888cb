"""What a perception run is asked for and what each of its frames gave.

:class:`PerceptionConfig` (checked when made), :class:`FrameSetup` (where a frame is
taken) and :class:`FrameRecord` (a processed frame, scored per camera model): the types
that :mod:`scenarios.perception.run` produces and :mod:`scenarios.perception.report`
writes out.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from agents.vision.camera_models import CAMERA_MODELS
from scenarios.perception.scoring import FrameScore, TrueLandmark
from world.camera_profiles import CAMERA_PROFILES, DEFAULT_CAMERA_PROFILE
from world.field import Pose2D

CROWD_ORDER: tuple[str, ...] = ("away_0", "home_2", "away_1", "home_3", "away_2", "home_0", "away_3")
MAX_CROWD = len(CROWD_ORDER)
SETTLE_STEPS = (15, 40)  # control steps before the frame, drawn uniformly per frame. Measured: the head is
# on target after 1 step, the body tilt within ~8; the accelerometer of a robot standing still keeps
# jittering (up to ~7 deg of apparent tilt), so a random settle time samples that jitter fairly
MAX_HEAD_RATE_RADPS = 5.0  # rad/s: beyond a Nao's fastest head turn (its yaw joint's speed limit is about 8 rad/s
# unloaded, head scans run at 1-2 rad/s)
FALSE_TILT_DEG = 2.0  # a frame whose accelerometer tilt differs from the true tilt by more is counted


class PerceptionConfigError(ValueError):
    """A perception run asked for something impossible (the message names the value)."""


@dataclass(frozen=True)
class PerceptionConfig:
    frames: int
    seed: int = 0
    crowd: int = 0
    models: tuple[str, ...] = ("exact", "thesis")
    max_range_m: float = 4.0
    progress: bool = True
    examples: int = 6  # annotated PNGs of frames where the first model erred (false positives first)
    command: str = ""  # the command line, quoted in table.md
    camera_profile: str = DEFAULT_CAMERA_PROFILE  # the camera's image profile (world.camera_profiles)
    head_rate_radps: float = 0.0  # the head turns at this rate through each frame's control step (0: still)

    def __post_init__(self) -> None:
        if not isinstance(self.frames, int) or self.frames < 1:
            raise PerceptionConfigError(f"frames must be an integer >= 1; got {self.frames!r}")
        if not isinstance(self.crowd, int) or not 0 <= self.crowd <= MAX_CROWD:
            raise PerceptionConfigError(f"crowd must be an integer in 0..{MAX_CROWD}; got {self.crowd!r}")
        unknown = [m for m in self.models if m not in CAMERA_MODELS]
        if not self.models or unknown or len(set(self.models)) != len(self.models):
            raise PerceptionConfigError(
                f"models must be distinct names among {sorted(CAMERA_MODELS)}; got {list(self.models)}"
            )
        if not (isinstance(self.max_range_m, (int, float)) and 0 < self.max_range_m < math.inf):
            raise PerceptionConfigError(f"max_range_m must be a positive finite number; got {self.max_range_m!r}")
        if not isinstance(self.examples, int) or self.examples < 0:
            raise PerceptionConfigError(f"examples must be an integer >= 0; got {self.examples!r}")
        if not isinstance(self.camera_profile, str) or self.camera_profile not in CAMERA_PROFILES:
            raise PerceptionConfigError(f"camera_profile must be one of {', '.join(CAMERA_PROFILES)}; "
                                        f"got {self.camera_profile!r}")
        if not (isinstance(self.head_rate_radps, (int, float)) and 0.0 <= self.head_rate_radps <= MAX_HEAD_RATE_RADPS):
            raise PerceptionConfigError(f"head_rate_radps must be a number in [0, {MAX_HEAD_RATE_RADPS:g}]; "
                                        f"got {self.head_rate_radps!r}")


@dataclass(frozen=True)
class FrameSetup:
    """Where one frame is taken: the measured robot's pose and head yaw, the crowd's poses."""

    pose: Pose2D
    head_yaw_rad: float
    crowd: tuple[Pose2D, ...] = ()
    settle_steps: int = SETTLE_STEPS[0]


@dataclass(frozen=True)
class FrameRecord:
    """One processed frame: its setup, its truth and, per model, its score and pipeline time."""

    index: int
    setup: FrameSetup
    robot_pose: Pose2D  # true pose after settling
    truths: tuple[TrueLandmark, ...]
    scores: dict[str, FrameScore] = field(default_factory=dict)
    process_ms: dict[str, float] = field(default_factory=dict)
    fallen: bool = False
    true_tilt_deg: float = 0.0
    applied_tilt_deg: float = 0.0  # the body tilt the exact camera model took from the accelerometer

    @property
    def false_tilt(self) -> bool:
        return abs(self.applied_tilt_deg - self.true_tilt_deg) > FALSE_TILT_DEG
