"""Outputs of ``robotstadium perception``: summary.json, table.md, CSVs, plot and example frames.

Units are SI in the JSON and CSVs (metres, plus degrees where the name says ``_deg``);
the Markdown table shows centimetres and degrees.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

from scenarios.common.io import write_csv, write_json, write_text
from scenarios.common.plotting import plt, save_figure
from scenarios.perception.records import FrameRecord, PerceptionConfig
from scenarios.perception.scoring import GATE_FRACTION, KINDS, MAX_GATE_M, MIN_GATE_M
from scenarios.perception.truth import CIRCLE_MIN_FRACTION, CIRCLE_SAMPLES, RAY_TARGET_HEIGHT_M

log = logging.getLogger(__name__)

DEFINITIONS = {
    "visible": "the landmark's ground point (a post: its base point facing the camera) projects into the image of the "
    f"true camera pose, lies within max_range_m of the robot, and the ray from the camera to {RAY_TARGET_HEIGHT_M} m "
    "above it hits no robot; a goal centre when both its posts are",
    "center_circle_visible": f"centre spot within max_range_m and at least {CIRCLE_MIN_FRACTION:.0%} of "
    f"{CIRCLE_SAMPLES} points along the painted circle in the image and unoccluded",
    "gate": f"ground distance between estimated and true point <= clip({GATE_FRACTION} * true distance, "
    f"{MIN_GATE_M} m, {MAX_GATE_M} m); compatible = same kind, goal colour and id when the percept has them; "
    "greedy, nearest pair first, one-to-one",
    "precision": "matched percepts / all percepts (any distance)",
    "recall": "visible landmarks matched / visible landmarks",
    "matched": "visible landmarks matched by a percept (the recall numerator)",
    "false_tilt_frames": "frames whose accelerometer made the exact model tilt the body by more than 2 deg "
    "away from its true tilt",
    "errors": "over matches whose true distance <= max_range_m: |d_est - d_true|, that over d_true, "
    "|wrap(b_est - b_true)|; positions are landmark centres (post centres), torso frame",
}


@dataclass(frozen=True)
class Mark:
    """Something to draw on an example frame: a pixel, what it is, and a label."""

    pixel: tuple[float, float]
    state: str  # truth-found, truth-missed, percept-tp, percept-fp
    label: str


@dataclass(frozen=True, eq=False)
class Example:
    """A camera frame worth looking at, with its marks."""

    frame: int
    model: str
    image: np.ndarray
    marks: tuple[Mark, ...] | list[Mark]


MARK_BGR = {
    "truth-found": (0, 200, 0),
    "truth-missed": (255, 0, 255),
    "percept-tp": (255, 255, 0),
    "percept-fp": (0, 0, 255),
}
EXAMPLE_SCALE = 4


def write_outputs(
    out_dir: Path, summary: dict, records: Sequence[FrameRecord], config: PerceptionConfig, examples: Sequence[Example]
) -> list[Path]:
    """Write every output file into ``out_dir``; return their paths."""
    paths = [
        write_json(out_dir / "summary.json", summary),
        write_text(out_dir / "table.md", format_tables(summary, config.command)),
        write_detections_csv(out_dir / "detections.csv", records, config.models),
        write_visible_csv(out_dir / "visible.csv", records, config.models),
        plot_errors(out_dir / "errors_vs_distance.png", records, config.models, config.max_range_m),
    ]
    for example in examples:
        paths.append(write_example(out_dir / "examples" / f"frame_{example.frame:04d}_{example.model}.png", example))
    return paths


def _fmt(value: float | None, scale: float = 1.0, digits: int = 1) -> str:
    return "-" if value is None else f"{value * scale:.{digits}f}"


def format_tables(summary: dict, command: str = "") -> str:
    """One Markdown table per camera model, rows = landmark kinds, plus the command line."""
    lines = [f"# Landmark percepts against ground truth ({summary['frames']} frames)", ""]
    if command:
        lines += ["```", command, "```", ""]
    lines += [
        f"Errors over matches within {summary['max_range_m']} m; pipeline median "
        f"{summary['ms_per_frame_median']:.2f} ms per frame ({summary.get('timed_model', 'exact')} model).",
        "",
    ]
    header = (
        "| kind | detections | visible | matched | precision | recall | dist. err. median / p90 (cm) "
        "| rel. err. median / p90 (%) | bearing err. median / p90 (deg) |"
    )
    for model, stats in summary["models"].items():
        lines += [f"## {model}", "", header, "|" + "---|" * 9]
        for kind in KINDS:
            s = stats[kind.value]
            lines.append(
                f"| {kind.value} | {s['detections']} | {s['visible']} | {s['matched']} | {_fmt(s['precision'], 1, 2)} "
                f"| {_fmt(s['recall'], 1, 2)} | {_fmt(s['distance_error_median_m'], 100)} / "
                f"{_fmt(s['distance_error_p90_m'], 100)} | {_fmt(s['distance_error_rel_median'], 100)} / "
                f"{_fmt(s['distance_error_rel_p90'], 100)} | {_fmt(s['bearing_error_median_deg'])} / "
                f"{_fmt(s['bearing_error_p90_deg'])} |"
            )
        lines.append("")
    return "\n".join(lines)


def _num(value: float) -> str:
    return "" if value is None or not math.isfinite(value) else f"{value:.4f}"


DETECTION_COLUMNS = (
    "frame", "model", "kind", "landmark_id", "goal", "post_side", "matched", "true_id", "pixel_u", "pixel_v",
    "distance_est_m", "true_distance_m", "distance_error_m", "distance_error_rel",
    "bearing_est_deg", "true_bearing_deg", "bearing_error_deg",
    "robot_x_m", "robot_y_m", "robot_theta_deg", "head_yaw_deg", "true_tilt_deg", "applied_tilt_deg",
)


def _detection_rows(records: Sequence[FrameRecord], models: Sequence[str]) -> Iterator[list]:
    for record in records:
        pose = record.robot_pose
        for model in models:
            for s in record.scores[model].percepts:
                p, t = s.percept, s.truth
                yield [
                    record.index, model, p.kind.value, p.landmark_id.value if p.landmark_id else "",
                    p.goal.value if p.goal else "", p.post_side.value if p.post_side else "", int(s.matched),
                    t.landmark.id.value if t else "", _num(p.pixel[0]), _num(p.pixel[1]),
                    _num(p.distance_m), _num(t.distance_m if t else math.nan), _num(s.distance_error_m),
                    _num(s.distance_error_rel), _num(math.degrees(p.bearing_rad)),
                    _num(math.degrees(t.bearing_rad) if t else math.nan), _num(math.degrees(s.bearing_error_rad)),
                    _num(pose.x), _num(pose.y), _num(math.degrees(pose.theta)),
                    _num(math.degrees(record.setup.head_yaw_rad)), _num(record.true_tilt_deg),
                    _num(record.applied_tilt_deg),
                ]


def write_detections_csv(path: Path, records: Sequence[FrameRecord], models: Sequence[str]) -> Path:
    """One row per percept, per frame and model, with its match and errors."""
    return write_csv(path, DETECTION_COLUMNS, _detection_rows(records, models))


def _visible_rows(records: Sequence[FrameRecord], models: Sequence[str]) -> Iterator[list]:
    for record in records:
        matched = {m: record.scores[m].matched_ids() for m in models}
        for t in record.truths:
            if t.visible:
                yield [record.index, t.landmark.id.value, t.landmark.kind.value, _num(t.distance_m),
                       _num(math.degrees(t.bearing_rad)), *(int(t.landmark.id in matched[m]) for m in models)]


def write_visible_csv(path: Path, records: Sequence[FrameRecord], models: Sequence[str]) -> Path:
    """One row per visible landmark per frame, with whether each model found it (for recall by distance)."""
    header = ["frame", "landmark_id", "kind", "true_distance_m", "true_bearing_deg", *(f"found_{m}" for m in models)]
    return write_csv(path, header, _visible_rows(records, models))


def plot_errors(path: Path, records: Sequence[FrameRecord], models: Sequence[str], max_range_m: float) -> Path:
    """Relative distance error and bearing error against true distance, per kind (colour) and model (column)."""
    fig, axes = plt.subplots(2, len(models), figsize=(5.5 * len(models), 7), squeeze=False, sharex=True,
                             sharey="row")
    for col, model in enumerate(models):
        for kind in KINDS:
            matches = [s for r in records for s in r.scores[model].percepts if s.matched and s.percept.kind is kind]
            if not matches:
                continue
            d = [s.truth.distance_m for s in matches]
            axes[0, col].scatter(d, [100 * s.distance_error_rel for s in matches], s=8, alpha=0.6, label=kind.value)
            axes[1, col].scatter(d, [math.degrees(s.bearing_error_rad) for s in matches], s=8, alpha=0.6)
        axes[0, col].set_title(f"{model} camera model")
        axes[0, col].set_ylabel("|distance error| / true distance (%)")
        axes[1, col].set_ylabel("|bearing error| (deg)")
        axes[1, col].set_xlabel("true distance (m)")
        for row in range(2):
            axes[row, col].axvline(max_range_m, color="grey", linestyle="--", linewidth=0.8)
            axes[row, col].grid(alpha=0.3)
        if axes[0, col].get_legend_handles_labels()[0]:
            axes[0, col].legend(fontsize=8, markerscale=2)
    fig.tight_layout()
    return save_figure(fig, path, 100)


def write_example(path: Path, example: Example) -> Path:
    """The camera frame enlarged, true visible landmarks as circles, percepts as crosses, labelled."""
    path.parent.mkdir(parents=True, exist_ok=True)
    k = EXAMPLE_SCALE
    image = cv2.cvtColor(np.repeat(np.repeat(example.image, k, axis=0), k, axis=1), cv2.COLOR_RGB2BGR)
    for i, mark in enumerate(example.marks):
        centre = (int(round((mark.pixel[0] + 0.5) * k)), int(round((mark.pixel[1] + 0.5) * k)))
        colour = MARK_BGR[mark.state]
        if mark.state.startswith("truth"):
            cv2.circle(image, centre, 9, colour, 2)
        else:
            cv2.drawMarker(image, centre, colour, cv2.MARKER_CROSS, 16, 2)
        offset = 14 + 12 * (i % 3)
        cv2.putText(image, mark.label, (centre[0] + 6, centre[1] - offset), cv2.FONT_HERSHEY_SIMPLEX, 0.35, colour, 1)
    if not cv2.imwrite(str(path), image):
        raise OSError(f"could not write {path}")
    return path
