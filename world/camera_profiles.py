"""Camera image profiles: what a robot's camera does to the rendered frame before the robot sees it.

The renderer draws a perfect pinhole image. A profile turns it into the image of a sensor: noise,
motion blur along the image motion of the control step, the shear of a rolling shutter, vignetting,
exposure and colour cast that depend on where the camera looks, YUV422 chroma subsampling and lost
frames. Profiles (:data:`CAMERA_PROFILES`):

- ``clean``: the rendered frame as it is, byte for byte (no work at all).
- ``robotstadium`` (the default): the thesis' simulator (thesis section 3: much less noise than the
  real camera, but "the image suffers by a bit of distortion when the simulated robot moves"): faint
  noise and motion blur.
- ``nao``: the Nao V3/V4 camera as SPL teams describe it: shot and read noise, YUV422, vignetting, an
  exposure and colour cast that vary with the direction in the hall, motion blur, rolling shutter and
  an occasional lost frame.

:class:`CameraEffects` holds a world's profile, its random stream and each robot's last frame and
camera pose; the world calls :meth:`CameraEffects.apply` for every frame it hands a robot.
"""

from __future__ import annotations

import functools
import math
import zlib
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from world.camera_model import NAO_CAMERA
from world.errors import UnknownCameraProfileError

NOMINAL_DEPTH_M = 2.0
"""Depth at which the camera's translation is turned into image motion: about the distance of the
field features a playing robot looks at (rotation's image motion does not depend on depth)."""

MAX_MOTION_GAP_S = 0.25
"""A previous frame older than this (the camera was off) gives no image motion."""


@dataclass(frozen=True)
class CameraProfile:
    """The parameters of a camera profile (levels are 8-bit grey levels, 0-255).

    - ``exposure_s``: the exposure time; the motion blur is the image motion during it.
    - ``readout_s``: the time the rolling shutter takes from the first row to the last; 0: global shutter.
    - ``shot_noise``: the variance of the shot noise per level of signal (levels^2 per level): a sensor
      collects photons, whose count's variance equals its mean.
    - ``read_noise``: the standard deviation of the signal-independent noise (levels).
    - ``chroma_noise``: the standard deviation of the noise on U and V (levels), with ``yuv422``.
    - ``yuv422``: U and V shared by each horizontal pair of pixels, as the YUV422 image a Nao reads.
    - ``corner_shading``: brightness in the image corners relative to the centre (1: no vignetting),
      falling off with the square of the distance from the centre.
    - ``exposure_swing``: the relative change of exposure with the camera's direction in the hall
      (amplitude).
    - ``cast_swing``: the relative change of red and blue gains with the direction (amplitude, red and
      blue in opposition: a white balance that drifts between warm and cold light).
    - ``lost_frame_probability``: the chance a frame is lost and the previous one is delivered again.
    """

    name: str
    exposure_s: float = 0.0
    readout_s: float = 0.0
    shot_noise: float = 0.0
    read_noise: float = 0.0
    chroma_noise: float = 0.0
    yuv422: bool = False
    corner_shading: float = 1.0
    exposure_swing: float = 0.0
    cast_swing: float = 0.0
    lost_frame_probability: float = 0.0

    def __post_init__(self) -> None:
        for key in ("exposure_s", "readout_s", "shot_noise", "read_noise", "chroma_noise", "exposure_swing",
                    "cast_swing"):
            value = getattr(self, key)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and 0.0 <= value):
                raise ValueError(f"CameraProfile.{key} = {value!r}; expected a finite number >= 0")
        for key in ("corner_shading", "lost_frame_probability"):
            value = getattr(self, key)
            if not (isinstance(value, (int, float)) and 0.0 <= value <= 1.0):
                raise ValueError(f"CameraProfile.{key} = {value!r}; expected a number in [0, 1]")
        if self.exposure_swing >= 1.0 or self.cast_swing >= 1.0:
            raise ValueError(f"CameraProfile swings ({self.exposure_swing}, {self.cast_swing}); expected below 1")

    @functools.cached_property
    def clean(self) -> bool:
        """True when the profile leaves every frame as rendered."""
        return self == CameraProfile(self.name)


CLEAN = CameraProfile("clean")
"""The rendered frames as they are."""

ROBOTSTADIUM = CameraProfile("robotstadium", read_noise=1.5, exposure_s=0.02)
"""The thesis' simulator (RobotStadium, thesis section 3):

- ``read_noise`` 1.5 levels, Gaussian, independent of the signal and of the channel: the thesis
  describes the simulated camera as having much less noise than the real one; faint grain, no shot noise.
- ``exposure_s`` 0.02 (half a 40 ms control step): "the image suffers by a bit of distortion when the
  simulated robot moves ... in an attempt to resemble the distortion of the real camera": a head turning
  at 1 rad/s (about 190 px/s at the 188 px focal length) smears the image by about 4 px, a standing robot
  not at all.
"""

NAO = CameraProfile(
    "nao",
    exposure_s=0.016,
    readout_s=0.03,
    shot_noise=0.06,
    read_noise=1.5,
    chroma_noise=2.0,
    yuv422=True,
    corner_shading=0.75,
    exposure_swing=0.08,
    cast_swing=0.05,
    lost_frame_probability=0.01,
)
"""The Nao V3/V4 camera (OV7670 in the V3, Aptina MT9M114 in the V4: small-pixel CMOS sensors with an
electronic rolling shutter, 30 frames per second, YUV422 output), as SPL teams describe it in their team
reports and code releases:

- ``exposure_s`` 0.016: teams fix the exposure by hand under hall lighting and keep it short (of the order
  of 10-20 ms) to limit motion blur.
- ``readout_s`` 0.03: a rolling shutter reads the rows one after another over most of the 1/30 s frame
  (the sensors' data sheets), so a turning head shears the image.
- ``shot_noise`` 0.06 levels^2 per level and ``read_noise`` 1.5 levels: photon shot noise (variance
  proportional to the signal) plus signal-independent read noise; about 3 levels of luma noise at mid grey
  and 1.5 in the dark, an estimate of the visible grain of a small-pixel sensor at indoor gain.
- ``chroma_noise`` 2 levels on U and V, after the pair averaging: colour noise that makes single pixels
  of the carpet and lines change colour class (an estimate).
- ``yuv422`` True: the Nao's image is YUYV, each horizontal pair of pixels sharing one U and one V.
- ``corner_shading`` 0.75: the lens shading of the wide-angle Nao lens, corners about a quarter darker
  than the centre, which teams correct for in their colour calibration (an estimate).
- ``exposure_swing`` 0.08 and ``cast_swing`` 0.05: automatic exposure and white balance that react to what
  the camera looks at in the hall (windows, banners, lights): +-8 % brightness and +-5 % red against blue,
  smooth in the direction (an estimate).
- ``lost_frame_probability`` 0.01: a frame the software misses (a cognition cycle that overruns a 30 fps
  camera reads the previous buffer again): one in a hundred (an estimate).
"""

CAMERA_PROFILES: dict[str, CameraProfile] = {p.name: p for p in (CLEAN, ROBOTSTADIUM, NAO)}

DEFAULT_CAMERA_PROFILE = "robotstadium"
"""The profile of a world, a match, a perception run or a scenario that names none: the camera of the
thesis' simulator, so that every figure is measured on images as imperfect as the thesis had."""


def camera_profile(name: object) -> CameraProfile:
    """The profile called ``name``; :class:`UnknownCameraProfileError` for another name."""
    if not isinstance(name, str) or name not in CAMERA_PROFILES:
        raise UnknownCameraProfileError(name, tuple(CAMERA_PROFILES))
    return CAMERA_PROFILES[name]


# ---- per frame ---------------------------------------------------------------------------------


@dataclass(frozen=True)
class CameraPose:
    """A camera's pose when a frame was taken: simulated time (s), which camera (any hashable tag),
    rotation camera->world (3x3) and position (3,) m."""

    time_s: float
    camera: object
    rotation: np.ndarray
    position: np.ndarray


def image_motion_px(previous: CameraPose, current: CameraPose, focal_px: float = NAO_CAMERA.focal_px,
                    depth_m: float = NOMINAL_DEPTH_M) -> tuple[float, float]:
    """Where the point seen at the image centre in ``previous`` (at ``depth_m`` along the optical axis)
    lies in ``current``, relative to the centre: (du, dv) px, u right, v down. It holds the rotation of
    the head and body (exact at the centre) and their translation (at the nominal depth)."""
    point = previous.position + depth_m * previous.rotation[:, 2]
    seen = current.rotation.T @ (point - current.position)
    z = max(float(seen[2]), 0.1 * depth_m)
    return focal_px * float(seen[0]) / z, focal_px * float(seen[1]) / z


def image_velocity_pxps(previous: CameraPose | None, current: CameraPose) -> tuple[float, float]:
    """The image motion per second (px/s) between two frames of the same camera at most
    :data:`MAX_MOTION_GAP_S` apart; zero without such a previous frame."""
    if previous is None or previous.camera != current.camera:
        return 0.0, 0.0
    dt = current.time_s - previous.time_s
    if not 0.0 < dt <= MAX_MOTION_GAP_S:
        return 0.0, 0.0
    du, dv = image_motion_px(previous, current)
    return du / dt, dv / dt


def direction_gains(profile: CameraProfile, rotation: np.ndarray) -> np.ndarray:
    """Per-channel gains (R, G, B) for a camera looking along ``rotation[:, 2]``: exposure and colour cast,
    smooth functions of the optical axis' azimuth and elevation in the hall (one period around it)."""
    axis = rotation[:, 2]
    azimuth = math.atan2(float(axis[1]), float(axis[0]))
    down = float(np.clip(-axis[2], -1.0, 1.0))
    exposure = 1.0 + profile.exposure_swing * (0.7 * math.sin(azimuth + 0.6) + 0.3 * down)
    cast = profile.cast_swing * math.cos(azimuth - 0.4)
    return np.array([exposure * (1.0 + cast), exposure, exposure * (1.0 - cast)], np.float32)


@functools.lru_cache(maxsize=16)
def noise_sigmas(profile: CameraProfile) -> np.ndarray:
    """The noise's standard deviation at each signal level 0-255 (levels, float32):
    sqrt(``shot_noise`` * level + ``read_noise`` ** 2). Shared: not to be written to."""
    levels = np.arange(256, dtype=np.float64)
    return np.sqrt(profile.shot_noise * levels + profile.read_noise**2).astype(np.float32)


@functools.lru_cache(maxsize=16)
def shading_map(profile: CameraProfile, height: int = NAO_CAMERA.height_px,
                width: int = NAO_CAMERA.width_px) -> np.ndarray:
    """Vignetting, (height, width) float32: 1 at the centre, ``corner_shading`` at the pixel centres of the
    corners, quadratic in the distance from the centre. Shared: not to be written to."""
    v, u = np.mgrid[0:height, 0:width].astype(np.float64)
    r2 = (u - (width - 1) / 2.0) ** 2 + (v - (height - 1) / 2.0) ** 2
    r2_corner = ((width - 1) / 2.0) ** 2 + ((height - 1) / 2.0) ** 2
    return (1.0 - (1.0 - profile.corner_shading) * r2 / r2_corner).astype(np.float32)


@dataclass(frozen=True)
class FrameEffects:
    """What a profile does to one frame: blur vector (px over the exposure), rolling-shutter shift (px per
    row), per-channel gains, the noise key and whether the frame is lost."""

    blur_px: tuple[float, float]
    shear_px_per_row: tuple[float, float]
    gains: np.ndarray
    key: int
    lost: bool

    @property
    def taps(self) -> int:
        """Samples along the blur, at most a pixel apart (at most :data:`MAX_BLUR_TAPS`); one below a quarter
        of a pixel."""
        length = math.hypot(*self.blur_px)
        return 1 if length < 0.25 else min(MAX_BLUR_TAPS, max(2, math.ceil(length)))


MAX_BLUR_TAPS = 12
"""At most this many samples along the blur; a longer blur spaces them more than a pixel apart."""


def frame_effects(profile: CameraProfile, velocity_pxps: tuple[float, float], rotation: np.ndarray,
                  raw: tuple[int, int], height: int = NAO_CAMERA.height_px) -> FrameEffects:
    """The effects of one frame from the image velocity (px/s), the camera's rotation and two raw 64-bit
    draws of the camera stream (noise key, lost-frame draw)."""
    du, dv = velocity_pxps
    row_s = profile.readout_s / max(height - 1, 1)
    return FrameEffects(
        blur_px=(du * profile.exposure_s, dv * profile.exposure_s),
        shear_px_per_row=(du * row_s, dv * row_s),
        gains=direction_gains(profile, rotation),
        key=int(raw[0]),
        lost=raw[1] < profile.lost_frame_probability * 2.0**64,
    )


def apply_frame_effects(profile: CameraProfile, image: np.ndarray, effects: FrameEffects) -> np.ndarray:
    """A new (H, W, 3) uint8 image: ``image`` through ``effects`` (lost frames are the caller's)."""
    if (not isinstance(image, np.ndarray) or image.dtype != np.uint8 or image.ndim != 3 or image.shape[2] != 3
            or image.shape[1] % 2):
        raise ValueError(f"image of {getattr(image, 'dtype', type(image))} {getattr(image, 'shape', '')}; "
                         "expected uint8 (H, W, 3) with W even")
    return apply_frames_effects(profile, image[np.newaxis], [effects])[0]


def apply_frames_effects(profile: CameraProfile, images: np.ndarray, effects: Sequence[FrameEffects],
                         parallel: bool = False) -> np.ndarray:
    """New images (n, H, W, 3) uint8: frame ``i`` of ``images`` through ``effects[i]`` (lost frames are the
    caller's), in one compiled call; with ``parallel``, on numba's threads where they can be had
    (:func:`world.raster.threads.parallel_cameras`). The same images either way."""
    if (not isinstance(images, np.ndarray) or images.dtype != np.uint8 or images.ndim != 4 or images.shape[3] != 3
            or images.shape[2] % 2):
        raise ValueError(f"images of {getattr(images, 'dtype', type(images))} {getattr(images, 'shape', '')}; "
                         "expected uint8 (n, H, W, 3) with W even")
    if len(effects) != images.shape[0]:
        raise ValueError(f"{len(effects)} frame effects for {images.shape[0]} images; expected one per image")
    from world.camera_kernel import NORMAL_BANK, apply_effects_parallel, apply_effects_serial  # numba, loaded late
    from world.raster.threads import parallel_cameras

    height, width = images.shape[1], images.shape[2]
    out = np.empty_like(images)
    kernel = apply_effects_parallel if parallel and len(effects) > 1 and parallel_cameras() else apply_effects_serial
    kernel(np.ascontiguousarray(images), out,
           np.array([e.blur_px for e in effects], np.float64).reshape(-1, 2),
           np.array([e.taps for e in effects], np.int64),
           np.array([e.shear_px_per_row for e in effects], np.float64).reshape(-1, 2),
           shading_map(profile, height, width), profile.corner_shading != 1.0,
           np.array([e.gains for e in effects], np.float32).reshape(-1, 3),
           noise_sigmas(profile), float(profile.chroma_noise), bool(profile.yuv422),
           np.array([e.key for e in effects], np.uint64), NORMAL_BANK)
    return out


# ---- a world's cameras ---------------------------------------------------------------------------


@dataclass(frozen=True)
class _Seen:
    pose: CameraPose
    frame: np.ndarray


@dataclass
class CameraEffects:
    """A world's camera profile at work: the key of its random draws and, per robot, the number of frames
    drawn, the last frame delivered and the camera pose it was taken from (for the image motion and lost
    frames).

    The n-th frame of robot ``r`` draws its two raw 64-bit numbers from the key, ``r`` and ``n`` alone
    (:meth:`frame_draws`), so what one robot's camera sees never depends on how many frames another robot
    took (a robot whose controller died, a camera switched off). The key is the first draw of ``rng``, the
    world's camera stream, and nothing else draws from it: the physics never depends on the profile.
    """

    profile: CameraProfile
    rng: np.random.Generator
    _key: int = field(init=False, default=0)
    _frames: dict[str, int] = field(default_factory=dict)
    _seen: dict[str, _Seen] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.reseed(self.rng)

    def reseed(self, rng: np.random.Generator) -> None:
        """Draw every later frame from ``rng``'s stream (a world reseeded); each robot starts again at frame 0."""
        self.rng = rng
        self._key = int(rng.bit_generator.random_raw())
        self._frames.clear()

    def frame_draws(self, robot_id: str, frame: int) -> tuple[int, int]:
        """The two raw 64-bit draws of frame number ``frame`` (from 0) of robot ``robot_id``."""
        entropy = [self._key, zlib.crc32(robot_id.encode("utf-8")), frame]
        raw = np.random.SeedSequence(entropy).generate_state(2, np.uint64)
        return int(raw[0]), int(raw[1])

    def apply(self, robot_id: str, image: np.ndarray, pose: CameraPose) -> np.ndarray:
        """The frame robot ``robot_id`` gets for ``image``, rendered from ``pose``."""
        if self.profile.clean:
            return image
        return self.apply_many([(robot_id, image, pose)])[0]

    def apply_many(self, frames: Sequence[tuple[str, np.ndarray, CameraPose]], parallel: bool = False
                   ) -> list[np.ndarray]:
        """The frames robots get for images ``(robot_id, image, pose)`` of one moment, in order: the same
        as :meth:`apply` of each in turn, the images drawn through the profile in one call (on numba's
        threads with ``parallel``)."""
        if self.profile.clean or not frames:
            return [image for _, image, _ in frames]
        ids = [robot_id for robot_id, _, _ in frames]
        if len(set(ids)) < len(ids):  # a robot's second frame follows from its first
            return [self.apply_many([one], parallel)[0] for one in frames]
        seen = [self._seen.get(robot_id) for robot_id in ids]
        effects = []
        for (robot_id, image, pose), before in zip(frames, seen):
            frame = self._frames.get(robot_id, 0)
            self._frames[robot_id] = frame + 1
            effects.append(frame_effects(self.profile, image_velocity_pxps(before.pose if before else None, pose),
                                         pose.rotation, self.frame_draws(robot_id, frame), image.shape[0]))
        drawn = apply_frames_effects(self.profile, np.stack([image for _, image, _ in frames]), effects, parallel)
        delivered = []
        for k, ((robot_id, _, pose), before, effect) in enumerate(zip(frames, seen, effects)):
            out = before.frame if effect.lost and before is not None else drawn[k]
            self._seen[robot_id] = _Seen(pose, out)
            delivered.append(out.copy())
        return delivered

    def forget(self, robot_id: str | None = None) -> None:
        """Drop the memory of one robot's camera (placed elsewhere), or of every robot's."""
        if robot_id is None:
            self._seen.clear()
        else:
            self._seen.pop(robot_id, None)

    def save(self) -> tuple[int, dict, dict]:
        """The state to :meth:`restore`: the key, the robots' frame counts and their last frames."""
        return self._key, dict(self._frames), dict(self._seen)

    def restore(self, state: tuple[int, dict, dict]) -> None:
        self._key, frames, seen = state
        self._frames, self._seen = dict(frames), dict(seen)
