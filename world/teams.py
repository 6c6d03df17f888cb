"""Team colours: a public fact of the game (pure Python, no pybullet)."""

from __future__ import annotations

import enum


class TeamColor(enum.Enum):
    """Colour of a robot's waistband; the blue team defends the blue goal (x = -3)."""

    BLUE = "blue"
    RED = "red"

    @property
    def rgba(self) -> tuple[float, float, float, float]:
        return (0.12, 0.22, 0.85, 1.0) if self is TeamColor.BLUE else (0.85, 0.1, 0.1, 1.0)

    @property
    def other(self) -> TeamColor:
        return TeamColor.RED if self is TeamColor.BLUE else TeamColor.BLUE
