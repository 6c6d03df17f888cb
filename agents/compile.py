"""Compile the agents' machine code (:mod:`agents.vision.kernels`, :mod:`agents.localization.kernels`)
into numba's cache once: ``python -m agents.compile``.

``make install`` runs it, so that no controller process, test or benchmark pays for the
compilation (once per install or change of the kernels; later processes load the cached code).
"""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np


def compile_agents() -> float:
    """Run every kernel of the vision and the localization once, on a frame of field, line and post, pixels
    located on the ground and scans of corners; return the seconds it took."""
    from agents.localization.kernels import pose_residuals
    from agents.localization.measurement import MeasurementConfig, ScanLikelihood
    from agents.localization.particle import ParticleLocalizer
    from agents.vision.border import find_border
    from agents.vision.camera_models import ExactCameraModel
    from agents.vision.colors import ColorClass
    from agents.vision.frame import CameraFrame
    from agents.vision.goals import GoalRims, find_posts
    from agents.vision.lines.formation import form_lines
    from agents.vision.lines.scan_lines import scan_black_lines
    from agents.vision.percepts import LandmarkPercept
    from agents.vision.segmentation import ColorTable, load_thresholds
    from match.protocol import Displacement
    from world.field import GoalColor, LandmarkKind, Pose2D

    started = time.perf_counter()
    table = ColorTable(load_thresholds())
    image = np.zeros((120, 160, 3), np.uint8)
    labels = table.segment(image)
    labels[:] = int(ColorClass.GREEN)
    labels[60:63, :] = int(ColorClass.WHITE)
    labels[70:73, :] = int(ColorClass.WHITE)  # a second line: the chains of criterion 4
    black = scan_black_lines(labels, find_border(labels))
    form_lines(black.column, black.middle, black.length)
    labels[10:30, 20:23] = int(ColorClass.BLUE)
    rims = GoalRims.from_thresholds(table.thresholds)
    find_posts(labels, GoalColor.BLUE, rims.goal_pixels(labels, image, GoalColor.BLUE))
    model = ExactCameraModel()
    for accelerometer in (None, (3.0, 0.0, 9.0)):  # upright, and tilted (another rotation)
        model.locate(CameraFrame(image, 0.0, 0.3, accelerometer_mps2=accelerometer), np.arange(3.0), np.arange(3.0))
    localizer = ParticleLocalizer(seed=0, initial_pose=Pose2D(0.0, 0.0, 0.0))
    localizer.move(Displacement(0.1, 0.0, 0.1))
    corner = LandmarkPercept(LandmarkKind.L_CORNER, (80.0, 90.0), 0.3, 1.5, "exact")
    for _ in range(2):  # the first scan of a cloud that knows its pose, then one more: every path of an update
        localizer.localize([corner, replace(corner, bearing_rad=-0.4)])
    scan = ScanLikelihood([corner], MeasurementConfig())
    scan.associate(0.0, 0.0, 0.0)
    pose_residuals(0.0, 0.0, 0.0, scan.lx, scan.ly, scan.distance[scan.owner], scan.bearing[scan.owner],
                   scan.sigma_d[scan.owner], float(scan.sigma_b))
    return time.perf_counter() - started


def main() -> None:
    seconds = compile_agents()
    print(f"compiled agents ready ({seconds:.1f} s)")


if __name__ == "__main__":
    main()
