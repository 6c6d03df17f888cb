"""Debug overlays of one frame, like thesis figures 4.5, 4.7, 4.8 and 4.11.

Left: the camera image with the recognized landmarks labelled. Right: the segmented
image (Table 4.1 colours) with the field border in red, goal posts outlined in purple
(rejected candidates in red), scan-line runs coloured by the criterion that rejected them
(kept: black; 1 orange, 2 magenta, 3 cyan, 4 yellow, as in thesis Figure 4.7), formed lines
in blue and their least-squares curves in magenta; the ball, when given, circled in orange on
both halves with its distance. Both halves are enlarged ``scale`` times.
"""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

from agents.vision.ball import BallPercept
from agents.vision.colors import DISPLAY_RGB
from agents.vision.lines import LineTrace
from agents.vision.percepts import LandmarkPercept
from agents.vision.pipeline import FrameResult
from world.field import LandmarkKind

CRITERION_RGB = {0: (0, 0, 0), 1: (255, 140, 0), 2: (255, 0, 255), 3: (0, 255, 255), 4: (255, 255, 0)}
BORDER_RGB = (255, 0, 0)
POST_RGB = (160, 32, 240)
REJECTED_RGB = (255, 0, 0)
LINE_RGB = (0, 0, 255)
CURVE_RGB = (255, 0, 255)
LABEL_RGB = (255, 0, 0)
DROPPED_RGB = (128, 128, 128)  # corners and junctions the verification dropped
BALL_RGB = (255, 120, 0)
_PALETTE = np.array([DISPLAY_RGB[c] for c in sorted(DISPLAY_RGB)], np.uint8)


def segmented_rgb(labels: np.ndarray) -> np.ndarray:
    """The segmented image in the Table 4.1 colours (H, W, 3) uint8."""
    return _PALETTE[labels]


def _label(percept: LandmarkPercept) -> str:
    if percept.landmark_id is not None:
        text = percept.landmark_id.value.replace("_goal", "").replace("_post", "")
    elif percept.kind is LandmarkKind.GOAL_POST and percept.goal is not None:
        text = f"{percept.goal.value} post?"
    else:
        text = percept.kind.value
    if percept.corner is not None:
        text += f" ({percept.corner.value})"
    return f"{text} {percept.distance_m:.2f}m"


def _point(scale: int, u: float, v: float, offset: int = 0) -> tuple[int, int]:
    return int(round((u + 0.5) * scale)) + offset, int(round((v + 0.5) * scale))


def _draw_lines(canvas: np.ndarray, trace: LineTrace, scale: int, off: int) -> None:
    black = trace.black_lines
    for u, top, bottom, criterion in zip(black.column, black.top, black.bottom, black.rejected_by):
        color = CRITERION_RGB[int(criterion)]
        cv2.line(canvas, _point(scale, u, top, off), _point(scale, u, bottom, off), color, max(1, scale // 2))
    for line in trace.lines:
        points = [_point(scale, u, v, off) for u, v in zip(line.u, line.v)]
        cv2.polylines(canvas, [np.array(points, np.int32)], False, LINE_RGB, 1)
        a, b, c = line.coefficients
        u = np.linspace(line.u.min(), line.u.max(), 24)
        curve = [_point(scale, x, a * x * x + b * x + c, off) for x in u]
        cv2.polylines(canvas, [np.array(curve, np.int32)], False, CURVE_RGB, 1)
        cv2.putText(canvas, line.kind.value, (points[0][0], points[0][1] - 4), cv2.FONT_HERSHEY_SIMPLEX, 0.3, CURVE_RGB, 1)
    marks = [c.pixel for c in trace.corners] + [j.pixel for j in trace.junctions]
    if trace.circle is not None and trace.circle.accepted:
        marks += list(trace.circle.pixels)
    for u, v in marks:
        cv2.drawMarker(canvas, _point(scale, u, v, off), LABEL_RGB, cv2.MARKER_CROSS, 3 * scale, 2)
    for u, v in trace.rejected:
        cv2.drawMarker(canvas, _point(scale, u, v, off), DROPPED_RGB, cv2.MARKER_TILTED_CROSS, 3 * scale, 1)


def draw_overlay(result: FrameResult, image: np.ndarray, scale: int = 4, ball: BallPercept | None = None) -> np.ndarray:
    """The debug picture of ``result`` (from ``image``), RGB uint8 of (H*scale, 2*W*scale, 3);
    ``ball``: the ball found in the same image (:func:`agents.vision.ball.ball_in_mask`), if any."""
    h, w = result.segmented.shape
    left = cv2.resize(image, (w * scale, h * scale), interpolation=cv2.INTER_NEAREST)
    right = cv2.resize(segmented_rgb(result.segmented), (w * scale, h * scale), interpolation=cv2.INTER_NEAREST)
    canvas = np.ascontiguousarray(np.hstack([left, right]))
    off = w * scale
    if result.lines is not None:
        _draw_lines(canvas, result.lines, scale, off)
    kept = result.border.rows >= 0
    columns, rows = result.border.columns[kept], result.border.rows[kept]
    for (u0, v0), (u1, v1) in zip(zip(columns[:-1], rows[:-1]), zip(columns[1:], rows[1:])):
        cv2.line(canvas, _point(scale, u0, v0, off), _point(scale, u1, v1, off), BORDER_RGB, 2)
    for post in result.goals.posts:
        color = REJECTED_RGB if post.rejected else POST_RGB
        top_left = (off + post.first_column * scale, post.top_row * scale)
        bottom_right = (off + (post.last_column + 1) * scale - 1, (post.bottom_row + 1) * scale - 1)
        cv2.rectangle(canvas, top_left, bottom_right, color, 2)
    for percept in result.percepts:
        u, v = percept.pixel
        for x_offset in (0, off):
            cv2.circle(canvas, _point(scale, u, v, x_offset), 2 * scale, LABEL_RGB, 2)
        anchor = _point(scale, u, v)
        cv2.putText(canvas, _label(percept), (anchor[0] + 6, anchor[1] - 6), cv2.FONT_HERSHEY_SIMPLEX, 0.4, LABEL_RGB, 1)
    if ball is not None:
        radius = int(round((np.sqrt(ball.pixels / np.pi) + 1.5) * scale))
        for x_offset in (0, off):
            cv2.circle(canvas, _point(scale, ball.pixel_u, ball.pixel_v, x_offset), radius, BALL_RGB, 2)
        anchor = _point(scale, ball.pixel_u, ball.pixel_v)
        cv2.putText(canvas, f"ball {ball.distance_m:.2f}m", (anchor[0] + radius + 2, anchor[1] + 4),
                    cv2.FONT_HERSHEY_SIMPLEX, 0.4, BALL_RGB, 1)
    return canvas


def save_overlay(path: Path, result: FrameResult, image: np.ndarray, scale: int = 4) -> Path:
    """Write :func:`draw_overlay` as a PNG; return the path."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    if not cv2.imwrite(str(path), cv2.cvtColor(draw_overlay(result, image, scale), cv2.COLOR_RGB2BGR)):
        raise OSError(f"could not write the overlay {path}")
    return path
