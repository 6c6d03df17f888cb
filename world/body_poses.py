"""Where every body of a world is: enough to put another world's bodies in the same places."""

from __future__ import annotations

from dataclasses import dataclass

from world.teams import TeamColor


@dataclass(frozen=True)
class BodyPoses:
    """Where every body of a world is (world frame; m, quaternions x, y, z, w).

    ``robots``: per robot of the roster, in order, its base position, base orientation and the
    angles (rad) of its movable joints in joint order; ``ball``: its position and
    orientation; ``teams``: each robot's waistband colour.
    """

    robots: tuple[tuple[tuple[float, ...], tuple[float, ...], tuple[float, ...]], ...]
    ball: tuple[tuple[float, ...], tuple[float, ...]]
    teams: tuple[TeamColor, ...]
