"""Monte Carlo localization: a particle filter over (x, y, theta) on the field.

- Motion: each finished motion's nominal displacement, with every particle's copy scaled
  and disturbed (:class:`MotionModel`, a little wider than the world's motion noise, which
  turns a nominal 40 degrees into 35-45, thesis 5.5).
- Measurement: :class:`~agents.localization.measurement.ScanLikelihood` -- ambiguous
  corners, junctions and posts of unknown side score as the best landmark of their kind,
  so no disambiguation is needed.
- Resampling: low-variance (systematic) after every scan, then a small roughening jitter
  against sample impoverishment.
- Sensor resetting (augmented MCL): short- and long-term averages of the scan likelihood
  per percept; when the short one drops below the long one (or below ``lost_likelihood``),
  up to ``max_injection`` of the particles are replaced by poses drawn from the scan itself
  (a landmark of a percept's kind, a point at the measured distance around it, the
  heading its bearing implies), kept in proportion to their likelihood of the whole scan.
  This recovers from kidnapping and from a start without a known pose. A scan of fewer than
  ``inject_min_percepts`` landmarks injects nothing unless it fits the cloud worse than
  ``inject_below_likelihood`` per percept (or the cloud is lost): one or two landmarks seen
  from a moving robot fit many poses, and particles drawn from them seed false clusters.
- Estimate: the weighted mean of the particles near one of the most likely few -- the one
  with the most weight around it, so a few particles in the field's mirror-image pose
  (a scan without goal colours fits both) do not win by chance -- polished by
  least squares on the scan (:mod:`agents.localization.refine`) when that succeeds, which
  is then combined, weighted by their covariances, with the cloud as it was before the scan
  (the particles around the estimate): the scan's least-squares pose carries its own
  residuals' uncertainty, so perfect percepts give the true pose while noisy ones are
  averaged with what earlier scans and the motions said.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from agents.localization.constraint import FIELD_MARGIN_M, wrap
from agents.localization.errors import LocalizationConfigError
from agents.localization.estimate import Covariance, EstimateSource, PoseEstimate
from agents.localization.kernels import moved_particles, near_seeds
from agents.localization.measurement import MeasurementConfig, ScanLikelihood
from agents.localization.odometry import compose
from agents.localization.refine import refine
from agents.localization.validation import checked_displacement, checked_pose, usable_percepts
from agents.vision.percepts import LandmarkPercept
from match.protocol import Displacement
from world.field import FIELD, FieldGeometry, Pose2D, normalize_angle

LOG = logging.getLogger(__name__)

DEFAULT_PARTICLES = 1000  # ours: one update costs well under 5 ms (median) on two cores
CLUSTER_SEEDS = 8  # ours: the estimate's cluster is centred on one of this many most likely particles
MIN_PRIOR_PARTICLES = 10  # ours: fewer particles near the estimate say nothing about it before the scan
REGULARIZATION = 1e-12  # m^2 / rad^2 added to covariances before inverting them
KIDNAP_MARGIN = 5.0  # ours: an extra sample this much more log-likely than every particle forces injection


@dataclass(frozen=True)
class MotionModel:
    """Noise added to each particle's copy of a nominal displacement (standard deviations).

    Every component is scaled by ``1 + N(0, scale_sigma)``; a moving robot's position also
    spreads by ``position_sigma_m`` and sideways by ``lateral_sigma_per_m`` per metre
    walked, its heading by ``heading_sigma_rad`` plus ``heading_sigma_rad_per_m`` per metre.
    """

    scale_sigma: float = 0.08
    position_sigma_m: float = 0.02
    lateral_sigma_per_m: float = 0.08
    heading_sigma_rad: float = math.radians(1.5)
    heading_sigma_rad_per_m: float = math.radians(6.0)


@dataclass(frozen=True)
class ParticleConfig:
    """Settings of :class:`ParticleLocalizer` (all ours; the thesis has no particle filter)."""

    particles: int = DEFAULT_PARTICLES
    measurement: MeasurementConfig = field(default_factory=MeasurementConfig)
    motion: MotionModel = field(default_factory=MotionModel)
    reset_sigma_m: float = 0.05  # spread of the cloud around a pose given by reset()
    reset_sigma_rad: float = math.radians(3.0)
    roughening_m: float = 0.005  # jitter after resampling
    roughening_rad: float = math.radians(0.5)
    alpha_slow: float = 0.1  # augmented MCL: long-term average of the per-percept likelihood ...
    alpha_fast: float = 0.6  # ... and short-term one (per scan; scans come every few seconds)
    max_injection: float = 0.5  # at most this fraction of particles drawn from the scan per update
    lost_likelihood: float = 0.15  # per-percept likelihood below which the cloud counts as lost
    injection_oversampling: int = 4  # raw scan samples drawn per injected particle
    field_margin_m: float = FIELD_MARGIN_M  # scan samples farther outside the lines are dropped
    # A sample drawn from the percepts replaces the cloud's estimate (a kidnapping) only when
    # they hold at least this many landmarks: one or two seen from a moving robot fit many poses.
    jump_min_percepts: int = 1
    # Particles are drawn from a scan of fewer landmarks than this only when it fits the cloud
    # worse than inject_below_likelihood per percept (the module docstring).
    inject_min_percepts: int = 1
    inject_below_likelihood: float = 1.0
    cluster_radius_m: float = 0.5  # the estimate averages particles this close to the most likely one
    cluster_angle_rad: float = 0.5
    refine: bool = True

    def __post_init__(self) -> None:
        if not (isinstance(self.particles, int) and not isinstance(self.particles, bool) and self.particles >= 1):
            raise LocalizationConfigError(f"particles must be an int >= 1; got {self.particles!r}")
        for name in ("max_injection", "alpha_slow", "alpha_fast", "lost_likelihood", "inject_below_likelihood"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and 0.0 <= value <= 1.0):
                raise LocalizationConfigError(f"{name} must be within [0, 1]; got {value!r}")
        for name in ("jump_min_percepts", "inject_min_percepts"):
            value = getattr(self, name)
            if not (isinstance(value, int) and not isinstance(value, bool) and value >= 1):
                raise LocalizationConfigError(f"{name} must be an int >= 1; got {value!r}")
        if not (isinstance(self.injection_oversampling, int) and self.injection_oversampling >= 1):
            raise LocalizationConfigError(f"injection_oversampling must be an int >= 1; got {self.injection_oversampling!r}")


def systematic_resample(weights: np.ndarray, count: int, rng: np.random.Generator) -> np.ndarray:
    """Low-variance resampling: ``count`` indices drawn with one random offset (weights sum to 1)."""
    if count <= 0:
        return np.zeros(0, dtype=int)
    positions = (rng.random() + np.arange(count)) / count
    cumulative = np.cumsum(weights)
    cumulative[-1] = 1.0
    return np.searchsorted(cumulative, positions, side="left")


def _weighted_pose(x: np.ndarray, y: np.ndarray, th: np.ndarray, w: np.ndarray) -> tuple[Pose2D, Covariance]:
    w = w / w.sum()
    mx, my = float(w @ x), float(w @ y)
    mt = math.atan2(float(w @ np.sin(th)), float(w @ np.cos(th)))
    dev = np.stack([x - mx, y - my, wrap(th - mt)])
    cov = (dev * w) @ dev.T
    return Pose2D(mx, my, mt), tuple(tuple(float(v) for v in row) for row in cov)  # type: ignore[return-value]


def fuse(a: tuple[Pose2D, Covariance], b: tuple[Pose2D, Covariance]) -> tuple[Pose2D, Covariance]:
    """The information-weighted combination of two Gaussian pose estimates (angles about ``b``'s)."""
    (pa, ca), (pb, cb) = a, b
    info_a = np.linalg.inv(np.asarray(ca) + REGULARIZATION * np.eye(3))
    info_b = np.linalg.inv(np.asarray(cb) + REGULARIZATION * np.eye(3))
    mean_a = np.array([pa.x, pa.y, pb.theta + normalize_angle(pa.theta - pb.theta)])
    mean_b = np.array([pb.x, pb.y, pb.theta])
    cov = np.linalg.inv(info_a + info_b)
    mean = cov @ (info_a @ mean_a + info_b @ mean_b)
    fused = Pose2D(float(mean[0]), float(mean[1]), normalize_angle(float(mean[2])))
    return fused, tuple(tuple(float(v) for v in row) for row in cov)  # type: ignore[return-value]


class ParticleLocalizer:
    """Monte Carlo localization (module docstring), seeded with a numpy Generator."""

    name = "particle"

    def __init__(
        self,
        config: ParticleConfig | None = None,
        seed: int | np.random.Generator | None = None,
        field: FieldGeometry = FIELD,
        initial_pose: Pose2D | None = None,
    ):
        self.config = config or ParticleConfig()
        self.field = field
        self.rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
        n = self.config.particles
        self.x = np.zeros(n)
        self.y = np.zeros(n)
        self.th = np.zeros(n)
        self._pose: Pose2D | None = None
        self._w_slow: float | None = None
        self._w_fast: float | None = None
        if initial_pose is None:
            self.spread_uniformly()
        else:
            self.reset(initial_pose)

    @property
    def pose(self) -> Pose2D | None:
        """The current belief: the last estimate moved by the nominal displacements since (None until known)."""
        return self._pose

    @property
    def particles(self) -> np.ndarray:
        """(N, 3) copy of the particles (x m, y m, theta rad)."""
        return np.stack([self.x, self.y, self.th], axis=1)

    def spread_uniformly(self) -> None:
        """Forget the pose: particles uniform over the field; the next scan re-seeds the cloud."""
        n = self.config.particles
        self.x = self.rng.uniform(-self.field.half_length, self.field.half_length, n)
        self.y = self.rng.uniform(-self.field.half_width, self.field.half_width, n)
        self.th = self.rng.uniform(-math.pi, math.pi, n)
        self._pose = None
        self._lost = True
        self._w_slow = self._w_fast = None

    def reset(self, pose: Pose2D) -> None:
        pose = checked_pose(pose)
        n, cfg = self.config.particles, self.config
        self.x = pose.x + self.rng.normal(0.0, cfg.reset_sigma_m, n)
        self.y = pose.y + self.rng.normal(0.0, cfg.reset_sigma_m, n)
        self.th = wrap(pose.theta + self.rng.normal(0.0, cfg.reset_sigma_rad, n))
        self._pose = pose
        self._lost = False
        self._w_slow = self._w_fast = None

    def widen(self, sigma_m: float, sigma_rad: float) -> None:
        """Spread the particles by a normal of ``sigma_m`` (m, each axis) and ``sigma_rad`` (heading):
        the robot fell or was pushed, and may be off by that much. The estimate stays until the next scan."""
        n = self.config.particles
        self.x = self.x + self.rng.normal(0.0, sigma_m, n)
        self.y = self.y + self.rng.normal(0.0, sigma_m, n)
        self.th = wrap(self.th + self.rng.normal(0.0, sigma_rad, n))
        self._clip_to_carpet()

    def move(self, displacement: Displacement) -> None:
        d = checked_displacement(displacement)
        m, n = self.config.motion, self.config.particles
        walked = math.hypot(d.forward_m, d.left_m)
        active = 0.0 if walked == 0.0 and d.turn_rad == 0.0 else 1.0
        noise = self.rng.normal(0.0, 1.0, (6, n))
        forward = d.forward_m * (1.0 + m.scale_sigma * noise[0]) + m.position_sigma_m * active * noise[1]
        left = (
            d.left_m * (1.0 + m.scale_sigma * noise[2])
            + (m.lateral_sigma_per_m * walked + m.position_sigma_m * active) * noise[3]
        )
        turn = (
            d.turn_rad * (1.0 + m.scale_sigma * noise[4])
            + (m.heading_sigma_rad_per_m * walked + m.heading_sigma_rad * active) * noise[5]
        )
        self.x, self.y, self.th = moved_particles(self.x, self.y, self.th, forward, left, turn,
                                                  self.field.carpet_half_length, self.field.carpet_half_width)
        if self._pose is not None:
            self._pose = compose(self._pose, d)

    def _clip_to_carpet(self) -> None:
        self.x = np.clip(self.x, -self.field.carpet_half_length, self.field.carpet_half_length)
        self.y = np.clip(self.y, -self.field.carpet_half_width, self.field.carpet_half_width)

    def localize(self, percepts: Sequence[LandmarkPercept]) -> PoseEstimate | None:
        percepts = usable_percepts(percepts)
        if not percepts:
            return None
        scan = ScanLikelihood(percepts, self.config.measurement, self.field)
        if not len(scan):
            return None
        return self._update(scan, percepts)

    # -- one scan ---------------------------------------------------------------------------

    def _injection_fraction(self, per_percept: float) -> float:
        cfg = self.config
        if self._lost:
            return 1.0
        if self._w_slow is None or self._w_fast is None:
            self._w_slow = self._w_fast = per_percept
        else:
            self._w_slow += cfg.alpha_slow * (per_percept - self._w_slow)
            self._w_fast += cfg.alpha_fast * (per_percept - self._w_fast)
        fraction = 1.0 - self._w_fast / max(self._w_slow, 1e-12)
        if per_percept < cfg.lost_likelihood:
            fraction = cfg.max_injection
        return float(np.clip(fraction, 0.0, cfg.max_injection))

    def _extra_samples(self, scan: ScanLikelihood, percepts: Sequence[LandmarkPercept]) -> np.ndarray:
        """(K, 3) further landmark-consistent poses to draw injected particles from (none here)."""
        return np.zeros((0, 3))

    def _sample_from_scan(
        self, scan: ScanLikelihood, count: int, extra: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """``count`` poses drawn from the scan (module docstring) and their scan log-likelihoods."""
        cfg, meas = self.config, self.config.measurement
        raw = max(count * cfg.injection_oversampling, 1)
        pair = self.rng.integers(0, len(scan.lx), raw)
        owner = scan.owner[pair]
        phi = self.rng.uniform(-math.pi, math.pi, raw)
        dist = scan.distance[owner] + scan.sigma_d[owner] * self.rng.normal(0.0, 1.0, raw)
        dist = np.maximum(dist, 0.0)
        x = scan.lx[pair] - dist * np.cos(phi)
        y = scan.ly[pair] - dist * np.sin(phi)
        th = wrap(phi - scan.bearing[owner] + meas.bearing_sigma_rad * self.rng.normal(0.0, 1.0, raw))
        if len(extra):
            x, y, th = np.concatenate([x, extra[:, 0]]), np.concatenate([y, extra[:, 1]]), np.concatenate([th, extra[:, 2]])
        margin = cfg.field_margin_m
        inside = (np.abs(x) <= self.field.half_length + margin) & (np.abs(y) <= self.field.half_width + margin)
        if inside.any():
            x, y, th = x[inside], y[inside], th[inside]
        else:  # the scan fits nowhere on the field: draw uniformly instead
            x = self.rng.uniform(-self.field.half_length, self.field.half_length, raw)
            y = self.rng.uniform(-self.field.half_width, self.field.half_width, raw)
            th = self.rng.uniform(-math.pi, math.pi, raw)
        ll = scan.log_likelihood(x, y, th)
        weights = np.exp(ll - ll.max())
        pick = systematic_resample(weights / weights.sum(), count, self.rng)
        return x[pick], y[pick], th[pick], ll[pick]

    def _update(self, scan: ScanLikelihood, percepts: Sequence[LandmarkPercept]) -> PoseEstimate:
        cfg, n = self.config, self.config.particles
        ll = scan.log_likelihood(self.x, self.y, self.th)
        per_percept = float(np.mean(np.exp(ll / len(scan))))
        lost = self._lost
        fraction = self._injection_fraction(per_percept)
        weights = np.exp(ll - ll.max())
        weights /= weights.sum()
        extra = self._extra_samples(scan, percepts)
        may_jump = len(scan) >= cfg.jump_min_percepts
        if (
            may_jump
            and len(extra)
            and float(scan.log_likelihood(extra[:, 0], extra[:, 1], extra[:, 2]).max()) > float(ll.max()) + KIDNAP_MARGIN
        ):
            fraction = max(fraction, cfg.max_injection)
        informative = lost or len(scan) >= cfg.inject_min_percepts or per_percept < cfg.inject_below_likelihood
        n_inject = round(fraction * n) if informative else 0
        ix, iy, ith, ill = self._sample_from_scan(scan, n_inject, extra) if n_inject else (np.zeros(0),) * 4

        best = int(np.argmax(ll))
        prior: tuple[Pose2D, Covariance] | None = None
        if n_inject and (lost or (may_jump and float(ill.max()) > float(ll[best]) + KIDNAP_MARGIN)):
            k = int(np.argmax(ill))
            seed_pose = Pose2D(float(ix[k]), float(iy[k]), float(ith[k]))
            near = (np.hypot(ix - ix[k], iy - iy[k]) <= cfg.cluster_radius_m) & (
                np.abs(wrap(ith - ith[k])) <= cfg.cluster_angle_rad
            )
            seed_pose, covariance = _weighted_pose(ix[near], iy[near], ith[near], np.exp(ill[near] - ill[k]))
        else:
            near = self._heaviest_cluster(weights)
            seed_pose, covariance = _weighted_pose(self.x[near], self.y[near], self.th[near], weights[near])
            if near.sum() >= MIN_PRIOR_PARTICLES:  # the cloud before this scan, around the estimate
                prior = _weighted_pose(self.x[near], self.y[near], self.th[near], np.ones(int(near.sum())))
        seed_pose = self._prefer(scan, percepts, seed_pose)

        keep = systematic_resample(weights, n - n_inject, self.rng)
        self.x = np.concatenate([self.x[keep], ix])
        self.y = np.concatenate([self.y[keep], iy])
        self.th = np.concatenate([self.th[keep], ith])
        self.x += self.rng.normal(0.0, cfg.roughening_m, n)
        self.y += self.rng.normal(0.0, cfg.roughening_m, n)
        self.th = wrap(self.th + self.rng.normal(0.0, cfg.roughening_rad, n))
        self._clip_to_carpet()
        self._lost = False

        pose, source, used = seed_pose, EstimateSource.PARTICLES, ()
        if cfg.refine:
            polished = refine(scan, seed_pose)
            if polished is not None:
                pose, covariance = polished.pose, polished.covariance
                if prior is not None:
                    pose, covariance = fuse(prior, (pose, covariance))
                source, used = EstimateSource.LANDMARKS, polished.landmarks
        self._pose = pose
        if n_inject:
            LOG.debug("injected %d of %d particles (per-percept likelihood %.3f)", n_inject, n, per_percept)
        return PoseEstimate(pose.x, pose.y, pose.theta, self.name, source, used, (), covariance)

    def _heaviest_cluster(self, weights: np.ndarray) -> np.ndarray:
        """Mask of the particles near whichever of the most likely few carries the most weight around it."""
        cfg = self.config
        seeds = np.argsort(weights)[-CLUSTER_SEEDS:]
        near = near_seeds(self.x, self.y, self.th, seeds, cfg.cluster_radius_m, cfg.cluster_angle_rad)
        return near[int(np.argmax(near @ weights))]

    def _prefer(self, scan: ScanLikelihood, percepts: Sequence[LandmarkPercept], seed: Pose2D) -> Pose2D:
        """Where to start the estimate's polish: the cloud's own seed here."""
        return seed
