"""The field-line stage (thesis section 4.5) built from the modules scan_lines, formation,
split_merge, classification and landmarks.

:func:`detect_line_landmarks` runs the stage on one segmented frame: black lines below the
field border (4.5.1), lines formed from them (4.5.2), split and merged (4.5.3), classified
by a least-squares parabola (4.5.4), and the L corners, T junctions and centre circle that
they show, located with a camera model (4.2).
"""

from __future__ import annotations

import logging

import numpy as np

from agents.vision.border import FieldBorder
from agents.vision.camera_models import CameraModel
from agents.vision.frame import CameraFrame
from agents.vision.lines.classification import ClassifiedLine, classify_line
from agents.vision.lines.formation import form_lines
from agents.vision.lines.landmarks import CircleSighting, detect_corners_and_junctions, locate_circle
from agents.vision.lines.scan_lines import DIST, BlackLines, scan_black_lines
from agents.vision.lines.split_merge import merge_lines, split_line
from agents.vision.lines.trace import LineTrace
from agents.vision.lines.verification import verify_sightings
from agents.vision.percepts import LandmarkPercept
from world.field import LandmarkId, LandmarkKind

LOG = logging.getLogger(__name__)


def find_lines(labels: np.ndarray, border: FieldBorder, dist: int = DIST) -> tuple[BlackLines, tuple[ClassifiedLine, ...]]:
    """Black lines and the classified lines of a segmented image (H, W) below ``border``."""
    black = scan_black_lines(labels, border, dist)
    kept = black.kept
    column = black.column[kept]
    middle = black.middle[kept]
    formed = form_lines(column, middle, black.length[kept], dist)
    w, h = column.tolist(), middle.tolist()
    pieces = [piece for line in formed for piece in split_line(line, h)]
    merged = merge_lines(pieces, w, h)
    lines = tuple(classify_line(column[idx], middle[idx], sequence) for idx, sequence in merged)
    return black, lines


def find_circle(lines: tuple[ClassifiedLine, ...], frame: CameraFrame, model: CameraModel) -> CircleSighting | None:
    """The first accepted half-circle, longest line first; else the last one located (for the trace), or None."""
    circle = None
    for line in sorted((line for line in lines if line.kind.is_curve), key=lambda line: -len(line.u)):
        circle = locate_circle(line, frame, model)
        if circle is not None and circle.accepted:
            return circle
        if circle is not None:
            LOG.debug("half-circle rejected: radius %.2f m, residual %.3f m", circle.radius_m, circle.residual_m)
    return circle


def detect_line_landmarks(
    labels: np.ndarray, border: FieldBorder, frame: CameraFrame, model: CameraModel
) -> tuple[tuple[LandmarkPercept, ...], LineTrace]:
    """L corners, T junctions and the centre circle seen in a segmented frame, and the trace.

    ``labels``: (H, W) uint8 colour classes of ``frame``'s image; ``model`` locates pixels.
    Corners and junctions are checked against the image around them
    (:mod:`~agents.vision.lines.verification`). Landmarks whose pixel is above the horizon
    are dropped. For the centre circle the bearing and distance are those of the fitted
    centre; its ``pixel`` is the middle point of the arc that was seen.
    """
    if not border.found:
        return (), LineTrace.empty()
    black, lines = find_lines(labels, border)
    circle = find_circle(lines, frame, model)
    accepted = circle if circle is not None and circle.accepted else None
    seen_corners, seen_junctions = detect_corners_and_junctions(lines)
    corners, junctions = verify_sightings(labels, border, frame, model, seen_corners, seen_junctions, accepted)
    kept = {s.pixel for s in corners + junctions}
    rejected = tuple(s.pixel for s in seen_corners + seen_junctions if s.pixel not in kept)
    percepts: list[LandmarkPercept] = []
    pixels = [c.pixel for c in corners] + [j.pixel for j in junctions]
    if pixels:
        u, v = np.array(pixels, float).T
        ground = model.locate(frame, u, v)
        kinds = [LandmarkKind.L_CORNER] * len(corners) + [LandmarkKind.T_JUNCTION] * len(junctions)
        shapes = [c.shape for c in corners] + [None] * len(junctions)
        for k, (kind, shape) in enumerate(zip(kinds, shapes)):
            if np.isfinite(ground.distance_m[k]):
                percepts.append(
                    LandmarkPercept(
                        kind, pixels[k], float(ground.bearing_rad[k]), float(ground.distance_m[k]), model.name, corner=shape
                    )
                )
    if accepted is not None:
        cx, cy = accepted.center_m
        percepts.append(
            LandmarkPercept(
                LandmarkKind.CENTER_CIRCLE,
                accepted.pixels[1],
                float(np.arctan2(cy, cx)),
                float(np.hypot(cx, cy)),
                model.name,
                landmark_id=LandmarkId.CENTER_CIRCLE,
            )
        )
    return tuple(percepts), LineTrace(black, lines, corners, junctions, rejected, circle)
