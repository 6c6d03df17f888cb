"""Team colours: a public fact of the game (pure Python, no pybullet)."""

from __future__ import annotations

import enum


class TeamColor(enum.Enum):
    """A team, named by its colour; the blue team defends the blue goal (x = -3).

    The waistbands are the SPL 2011 team markers of the thesis' colour table: cyan for
    the blue team, magenta for the red team, so a robot does not look like a goal post.
    """

    BLUE = "blue"
    RED = "red"

    @property
    def rgba(self) -> tuple[float, float, float, float]:
        """Waistband colour (RGBA in [0, 1]): cyan for the blue team, magenta for the red team."""
        return (0.0, 0.75, 0.9, 1.0) if self is TeamColor.BLUE else (0.9, 0.1, 0.65, 1.0)

    @property
    def other(self) -> TeamColor:
        return TeamColor.RED if self is TeamColor.BLUE else TeamColor.BLUE
