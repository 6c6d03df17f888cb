"""Compile the renderer's machine code (and the camera profiles' pass) into numba's cache once:
``python -m world.raster.compile``.

``make install`` runs it, so that no match, test or benchmark pays for the compilation (once
per install or change of these sources; later processes load the cached code).
"""

from __future__ import annotations

import logging
import time

log = logging.getLogger(__name__)


def compile_renderer() -> float:
    """Draw a frame of every kind (one camera, several on threads and on one, the broadcast view, a camera
    profile's frame) in a small world; return the seconds it took."""
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
    return time.perf_counter() - started


def main() -> None:
    seconds = compile_renderer()
    print(f"compiled renderer ready ({seconds:.1f} s)")


if __name__ == "__main__":
    main()
