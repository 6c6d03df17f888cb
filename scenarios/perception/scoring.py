"""Scoring landmark percepts against ground truth (pure: no pybullet, no world).

One frame's percepts are matched to the true landmarks, both in the robot's torso frame
(x forward, y left, metres, on the ground below the torso):

- a percept is *compatible* with a landmark of the same kind, of the same goal colour when
  the percept has one, and the same id when the percept has one;
- all compatible (percept, landmark) pairs within the gate are taken greedily, nearest
  ground-position pair first, each percept and landmark at most once (so every percept
  matches its nearest compatible landmark that no nearer percept took);
- the gate is ``clip(GATE_FRACTION * true distance, MIN_GATE_M, MAX_GATE_M)`` on the ground
  distance between the estimated and the true point. The 1.0 m cap is below the 1.08 m
  between a field corner and its goal-area corner and the 1.5 m between two posts, so a
  percept that names the wrong post never matches.

A matched percept is a true positive, an unmatched one a false positive; every percept
counts, whatever its distance. Recall counts only the landmarks marked visible. Errors are
taken over matches whose true distance is at most ``max_range_m``.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np

from agents.vision.percepts import LandmarkPercept
from world.field import Landmark, LandmarkKind, normalize_angle

MIN_GATE_M = 0.5
GATE_FRACTION = 0.3
MAX_GATE_M = 1.0

KINDS: tuple[LandmarkKind, ...] = tuple(LandmarkKind)
STAT_KEYS: tuple[str, ...] = (
    "precision",
    "recall",
    "distance_error_median_m",
    "distance_error_p90_m",
    "distance_error_rel_median",
    "distance_error_rel_p90",
    "bearing_error_median_deg",
    "bearing_error_p90_deg",
    "detections",
    "visible",
    "matched",
)


@dataclass(frozen=True)
class TrueLandmark:
    """A field landmark where it truly is in one frame: torso frame, metres; ``visible`` per the truth module."""

    landmark: Landmark
    x_m: float
    y_m: float
    visible: bool

    @property
    def distance_m(self) -> float:
        return math.hypot(self.x_m, self.y_m)

    @property
    def bearing_rad(self) -> float:
        return math.atan2(self.y_m, self.x_m)


@dataclass(frozen=True)
class ScoredPercept:
    """One percept and the true landmark it matched (``None``: a false positive)."""

    percept: LandmarkPercept
    truth: TrueLandmark | None

    @property
    def matched(self) -> bool:
        return self.truth is not None

    @property
    def distance_error_m(self) -> float:
        """|estimated - true distance| in metres; NaN when unmatched."""
        return abs(self.percept.distance_m - self.truth.distance_m) if self.truth else math.nan

    @property
    def distance_error_rel(self) -> float:
        """Distance error over the true distance; NaN when unmatched."""
        return self.distance_error_m / max(self.truth.distance_m, 1e-9) if self.truth else math.nan

    @property
    def bearing_error_rad(self) -> float:
        """|wrapped estimated - true bearing| in radians; NaN when unmatched."""
        return abs(normalize_angle(self.percept.bearing_rad - self.truth.bearing_rad)) if self.truth else math.nan


@dataclass(frozen=True)
class FrameScore:
    """The scored percepts of one frame (one camera model) and the truth they were scored against."""

    percepts: tuple[ScoredPercept, ...]
    truths: tuple[TrueLandmark, ...]

    def matched_ids(self) -> frozenset:
        return frozenset(s.truth.landmark.id for s in self.percepts if s.truth is not None)


def gate_m(true_distance_m: float) -> float:
    """How far (m) an estimated point may lie from a true landmark at ``true_distance_m`` and still match."""
    return min(MAX_GATE_M, max(MIN_GATE_M, GATE_FRACTION * true_distance_m))


def compatible(percept: LandmarkPercept, landmark: Landmark) -> bool:
    """Whether ``percept`` may be a sighting of ``landmark`` (kind, goal colour, id)."""
    if percept.kind is not landmark.kind:
        return False
    if percept.goal is not None and percept.goal is not landmark.goal:
        return False
    return percept.landmark_id is None or percept.landmark_id is landmark.id


def match_frame(percepts: Sequence[LandmarkPercept], truths: Sequence[TrueLandmark]) -> FrameScore:
    """Match the percepts of one frame to the true landmarks (see the module docstring)."""
    pairs = []
    for i, percept in enumerate(percepts):
        for j, truth in enumerate(truths):
            if not compatible(percept, truth.landmark):
                continue
            gap = math.hypot(percept.x_m - truth.x_m, percept.y_m - truth.y_m)
            if gap <= gate_m(truth.distance_m):
                pairs.append((gap, i, j))
    pairs.sort()
    assigned: dict[int, int] = {}
    taken: set[int] = set()
    for _, i, j in pairs:
        if i not in assigned and j not in taken:
            assigned[i] = j
            taken.add(j)
    scored = tuple(
        ScoredPercept(p, truths[assigned[i]] if i in assigned else None) for i, p in enumerate(percepts)
    )
    return FrameScore(scored, tuple(truths))


def has_error(score: FrameScore) -> bool:
    """Whether a frame has a false positive or a visible landmark nobody matched."""
    matched = score.matched_ids()
    return any(not s.matched for s in score.percepts) or any(
        t.visible and t.landmark.id not in matched for t in score.truths
    )


def _finite(value: float) -> float | None:
    return float(value) if value is not None and math.isfinite(value) else None


def _quantiles(values: list[float]) -> tuple[float | None, float | None]:
    if not values:
        return None, None
    arr = np.asarray(values, float)
    return _finite(float(np.median(arr))), _finite(float(np.percentile(arr, 90)))


def kind_statistics(scores: Iterable[FrameScore], max_range_m: float) -> dict[str, dict[str, float | int | None]]:
    """Per-kind statistics (keys :data:`STAT_KEYS`, ``None`` where undefined) keyed by kind value."""
    detections = {k: 0 for k in KINDS}
    true_positives = {k: 0 for k in KINDS}
    visible = {k: 0 for k in KINDS}
    visible_matched = {k: 0 for k in KINDS}
    dist: dict[LandmarkKind, list[float]] = {k: [] for k in KINDS}
    rel: dict[LandmarkKind, list[float]] = {k: [] for k in KINDS}
    bearing: dict[LandmarkKind, list[float]] = {k: [] for k in KINDS}
    for score in scores:
        matched_ids = score.matched_ids()
        for truth in score.truths:
            if truth.visible:
                visible[truth.landmark.kind] += 1
                visible_matched[truth.landmark.kind] += truth.landmark.id in matched_ids
        for s in score.percepts:
            kind = s.percept.kind
            detections[kind] += 1
            if s.truth is None:
                continue
            true_positives[kind] += 1
            if s.truth.distance_m <= max_range_m:
                dist[kind].append(s.distance_error_m)
                rel[kind].append(s.distance_error_rel)
                bearing[kind].append(math.degrees(s.bearing_error_rad))
    stats = {}
    for kind in KINDS:
        d_med, d_p90 = _quantiles(dist[kind])
        r_med, r_p90 = _quantiles(rel[kind])
        b_med, b_p90 = _quantiles(bearing[kind])
        stats[kind.value] = {
            "precision": true_positives[kind] / detections[kind] if detections[kind] else None,
            "recall": visible_matched[kind] / visible[kind] if visible[kind] else None,
            "distance_error_median_m": d_med,
            "distance_error_p90_m": d_p90,
            "distance_error_rel_median": r_med,
            "distance_error_rel_p90": r_p90,
            "bearing_error_median_deg": b_med,
            "bearing_error_p90_deg": b_p90,
            "detections": detections[kind],
            "visible": visible[kind],
            "matched": visible_matched[kind],
            "true_positives": true_positives[kind],
            "errors_within_range": len(dist[kind]),
        }
    return stats
