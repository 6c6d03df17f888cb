"""What the vision pipeline reads: one camera image and the robot state it was taken in."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from agents.observation import Observation, ObservationError
from agents.vision.errors import VisionInputError
from world.camera_model import NAO_CAMERA, CameraPosition

IMAGE_SHAPE = (NAO_CAMERA.height_px, NAO_CAMERA.width_px, 3)


@dataclass(frozen=True, eq=False)
class CameraFrame:
    """One 160x120 RGB uint8 image with the head angles (rad), camera and accelerometer (m/s^2).

    Head yaw is CCW positive, head pitch positive looks down (torso frame). The
    accelerometer (specific force, torso frame; about (0, 0, 9.81) upright) gives the body
    tilt to the exact camera model; ``None`` means upright.
    """

    image: np.ndarray
    head_yaw_rad: float
    head_pitch_rad: float
    camera: CameraPosition = CameraPosition.TOP
    accelerometer_mps2: tuple[float, float, float] | None = None

    def __post_init__(self) -> None:
        image = self.image
        if not isinstance(image, np.ndarray):
            raise VisionInputError(f"image must be a numpy array of shape {IMAGE_SHAPE}; got {type(image).__name__}")
        if image.shape != IMAGE_SHAPE or image.dtype != np.uint8:
            raise VisionInputError(f"image must be uint8 of shape {IMAGE_SHAPE}; got {image.dtype} {image.shape}")
        for name in ("head_yaw_rad", "head_pitch_rad"):
            value = getattr(self, name)
            if not isinstance(value, (int, float, np.floating)) or not math.isfinite(value):
                raise VisionInputError(f"{name} must be a finite number of radians; got {value!r}")
        if not isinstance(self.camera, CameraPosition):
            raise VisionInputError(f"camera must be one of {[c.value for c in CameraPosition]}; got {self.camera!r}")
        accel = self.accelerometer_mps2
        if accel is not None:
            values = np.asarray(accel, float).reshape(-1)
            if values.shape != (3,) or not np.isfinite(values).all():
                raise VisionInputError(f"accelerometer_mps2 must be three finite numbers or None; got {accel!r}")

    @classmethod
    def from_observation(cls, observation: Observation | Mapping[str, Any]) -> CameraFrame:
        """The frame of an agent observation (:class:`agents.observation.Observation`); its camera must be on."""
        try:
            obs = Observation.of(observation)
        except ObservationError as error:
            raise VisionInputError(f"observation lacks a usable image, head, camera or accelerometer: {error}") from None
        if obs.image is None or obs.camera_position is None:
            raise VisionInputError("the observation's camera is off: there is no image to process")
        return cls(obs.image, obs.head_yaw_rad, obs.head_pitch_rad, obs.camera_position, obs.accelerometer_mps2)
