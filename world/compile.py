"""Compile the world's machine code (the renderer, the camera profiles' pass, the locomotion
controller's arithmetic) into numba's cache once: ``python -m world.compile``.

``make install`` runs it, so that no match, test or benchmark pays for the compilation (once
per install or change of these sources; later processes load the cached code).
"""

from __future__ import annotations

import time

import numpy as np


def compile_world() -> float:
    """Draw a frame of every kind (one camera, several on threads and on one, the broadcast view, a camera
    profile's frame) in a small world and play every kind of motion (:func:`compile_locomotion`); return the
    seconds it took."""
    from world.config import RobotSpec, WorldConfig
    from world.teams import TeamColor
    from world.world import World

    started = time.perf_counter()
    with World([RobotSpec("a", TeamColor.BLUE), RobotSpec("b", TeamColor.RED)]) as world:
        renderer = world.compiled_renderer
        world.render_camera("a")
        world.camera_labels("a")
        for parallel in {False, renderer.parallel}:
            renderer.parallel = parallel
            dict(world.render_cameras(world.robot_ids))
        world.render_overview()
    with World([RobotSpec("a", TeamColor.BLUE)], WorldConfig(camera_profile="nao")) as profiled:
        profiled.render_camera("a")
    compile_locomotion()
    return time.perf_counter() - started


def compile_locomotion() -> None:
    """Run each of :mod:`world.locomotion_kernels` with the argument types the controller gives them."""
    from world import locomotion_kernels as kernels
    from world.locomotion import BalanceConfig, control_gains

    kernels.control(*([0.0] * 18), control_gains(BalanceConfig()))
    setpoints = np.zeros(kernels.SLOTS)
    for mode in (kernels.STANDING, kernels.WALKING, kernels.KICK_LEFT, kernels.KICK_RIGHT, kernels.STAND_UP):
        for known in (False, True):
            kernels.drive_joints(mode, 0.1, 1.0, 0.0, 0.0, 0.035, 0.02, setpoints, known)


def main() -> None:
    seconds = compile_world()
    print(f"compiled world ready ({seconds:.1f} s)")


if __name__ == "__main__":
    main()
