"""Configuration of a world, as frozen dataclasses with factory defaults."""

from __future__ import annotations

import math
from dataclasses import dataclass
from dataclasses import field as default

from world.camera_profiles import DEFAULT_CAMERA_PROFILE, camera_profile
from world.field import FIELD, FieldGeometry
from world.locomotion import BalanceConfig
from world.motions import MotionNoise, WalkLimits
from world.robot_model import TeamColor


@dataclass(frozen=True)
class RobotSpec:
    """One robot of the world: its id (any string) and its waistband colour."""

    robot_id: str
    team: TeamColor


@dataclass(frozen=True)
class PhysicsConfig:
    control_step_s: float = 0.04  # one RobotStadium step
    substeps: int = 5
    solver_iterations: int = 10

    @property
    def substep_s(self) -> float:
        return self.control_step_s / self.substeps


@dataclass(frozen=True)
class BallConfig:
    """Ball contact parameters, tuned so a 1.5 m/s ball rolls about 3 m on the carpet."""

    rolling_friction: float = 0.0021
    spinning_friction: float = 0.001
    lateral_friction: float = 0.5
    restitution: float = 0.5
    linear_damping: float = 0.0


RENDERERS = ("numba", "tiny")


@dataclass(frozen=True)
class RenderConfig:
    """Which renderer draws the cameras, and TinyRenderer's lighting (flat-ish light keeps colours stable for
    segmentation).

    ``renderer``: ``numba``, the compiled renderer (:mod:`world.raster`), or ``tiny``, pybullet's
    TinyRenderer with the analytic hall (:mod:`world.rendering`), the reference it is tested against.
    """

    light_direction: tuple[float, float, float] = (0.4, -0.3, 1.0)
    ambient: float = 0.65
    diffuse: float = 0.35
    specular: float = 0.0
    near_m: float = 0.01
    far_m: float = 20.0
    # Draw the static scene (ground, walls, banners, roof) in numpy (world.ground); False: all by TinyRenderer.
    analytic_ground: bool = True
    renderer: str = "numba"

    def __post_init__(self) -> None:
        if self.renderer not in RENDERERS:
            raise ValueError(f"RenderConfig.renderer = {self.renderer!r}; expected one of {', '.join(RENDERERS)}")
        if self.renderer == "numba" and not self.analytic_ground:
            raise ValueError("RenderConfig(analytic_ground=False) draws the hall with TinyRenderer; "
                             "expected renderer='tiny' with it")


@dataclass(frozen=True)
class ImuNoise:
    """Noise of the inertial sensors, Nao-like (one standard deviation per axis, torso frame).

    Each robot's gyro and accelerometer get a constant bias, drawn when the world is reset,
    and every reading a white noise on top. Integrating the gyro of a standing robot then
    drifts by the bias: ``gyro_bias_sigma_radps`` of 0.005 rad/s is about 3 degrees in
    10 s. All zero: exact readings.
    """

    gyro_bias_sigma_radps: float = 0.005
    gyro_noise_sigma_radps: float = 0.01
    accelerometer_bias_sigma_mps2: float = 0.1
    accelerometer_noise_sigma_mps2: float = 0.05

    def __post_init__(self) -> None:
        for name, value in vars(self).items():
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value >= 0.0):
                raise ValueError(f"ImuNoise.{name} = {value!r}; expected a finite number >= 0")


@dataclass(frozen=True)
class SonarConfig:
    """Four sonars (Nao: 0.25-2.55 m); upper pair at the chest, lower pair at the hips.

    Each sonar looks ``yaw_rad`` to its side and covers a cone, sampled by rays at
    ``cone_offsets_rad`` around its axis.
    """

    min_range_m: float = 0.25
    max_range_m: float = 2.55
    yaw_rad: float = math.radians(20.0)
    cone_offsets_rad: tuple[float, ...] = (math.radians(-25.0), 0.0, math.radians(25.0))
    upper_height_m: float = 0.40
    lower_height_m: float = 0.20


@dataclass(frozen=True)
class WorldConfig:
    """A world's settings. ``camera_profile``: what the robots' cameras do to the rendered frames
    (:mod:`world.camera_profiles`: ``clean``, ``robotstadium`` or ``nao``)."""

    field: FieldGeometry = FIELD
    physics: PhysicsConfig = default(default_factory=PhysicsConfig)
    ball: BallConfig = default(default_factory=BallConfig)
    balance: BalanceConfig = default(default_factory=BalanceConfig)
    motion_noise: MotionNoise = default(default_factory=MotionNoise)
    walk_limits: WalkLimits = default(default_factory=WalkLimits)
    render: RenderConfig = default(default_factory=RenderConfig)
    sonar: SonarConfig = default(default_factory=SonarConfig)
    imu_noise: ImuNoise = default(default_factory=ImuNoise)
    off_world_margin_m: float = 1.0  # placements may reach this far beyond the carpet
    camera_profile: str = DEFAULT_CAMERA_PROFILE

    def __post_init__(self) -> None:
        camera_profile(self.camera_profile)  # UnknownCameraProfileError names the value and the profiles
