"""The odometer of thesis 5.5: the pose integrated from the nominal displacements of finished motions.

A displacement is in the robot frame at the motion's start (forward, left, turn CCW), so
the pose moves by it rotated by the current heading, and the heading turns by its turn
angle, normalized into (-pi, pi]. For a pure forward motion this is the thesis' update
``x += cos(theta) d, y += sin(theta) d``; for a pure side step of ``d`` to the left it is
``x -= sin(theta) d, y += cos(theta) d`` (the thesis prints ``x += sin(theta) d`` there,
which holds for a step to the right with ``y`` then decreasing). The odometer is reset at
kick-off positions and by every accepted landmark localization.
"""

from __future__ import annotations

import math

from agents.localization.validation import checked_displacement, checked_pose
from match.protocol import Displacement
from world.field import Pose2D, normalize_angle


def compose(pose: Pose2D, displacement: Displacement) -> Pose2D:
    """``pose`` moved by ``displacement`` (robot frame at ``pose``); heading normalized."""
    c, s = math.cos(pose.theta), math.sin(pose.theta)
    return Pose2D(
        pose.x + c * displacement.forward_m - s * displacement.left_m,
        pose.y + s * displacement.forward_m + c * displacement.left_m,
        normalize_angle(pose.theta + displacement.turn_rad),
    )


class Odometer:
    """Integrates nominal displacements; ``pose`` is None until first reset."""

    def __init__(self, pose: Pose2D | None = None):
        self._pose = None if pose is None else checked_pose(pose)

    @property
    def pose(self) -> Pose2D | None:
        return self._pose

    def reset(self, pose: Pose2D) -> None:
        self._pose = checked_pose(pose)

    def move(self, displacement: Displacement) -> Pose2D | None:
        """Add one finished motion's nominal displacement; the new pose (None while unset)."""
        displacement = checked_displacement(displacement)
        if self._pose is not None:
            self._pose = compose(self._pose, displacement)
        return self._pose
