"""Figures: matplotlib on the Agg backend (files only, no display), the field, saving.

Importing this module selects the Agg backend before :mod:`matplotlib.pyplot` is loaded;
import ``plt`` from here.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # after choosing the backend
from matplotlib.patches import Circle, Rectangle

from world.field import FIELD

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["FIELD_GREEN", "draw_field", "plt", "save_figure"]

FIELD_GREEN = "#4c9a4c"


def draw_field(ax: Axes) -> None:
    """The field in ``ax``: green carpet, white lines, blue (x < 0) and yellow (x > 0) goals, metres."""
    hl, hw = FIELD.half_length, FIELD.half_width
    line = {"color": "white", "linewidth": 1.5, "zorder": 1}
    ax.set_facecolor(FIELD_GREEN)
    ax.add_patch(Rectangle((-hl, -hw), 2 * hl, 2 * hw, fill=False, **line))
    ax.plot([0.0, 0.0], [-hw, hw], **line)
    ax.add_patch(Circle((0.0, 0.0), FIELD.center_circle_radius, fill=False, **line))
    for sign in (-1.0, 1.0):
        x0 = min(sign * hl, sign * FIELD.goal_area_x)
        ax.add_patch(Rectangle((x0, -FIELD.goal_area_half_width), FIELD.goal_area_depth, FIELD.goal_area_width,
                               fill=False, **line))
    for sign, color in ((-1.0, "blue"), (1.0, "gold")):
        ax.plot([sign * hl, sign * hl], [-FIELD.goal_post_y, FIELD.goal_post_y], color=color, linewidth=6,
                solid_capstyle="butt", zorder=2)
    ax.set_xlim(-hl - 0.4, hl + 0.4)
    ax.set_ylim(-hw - 0.4, hw + 0.4)
    ax.set_aspect("equal")


def save_figure(fig: Figure, path: Path, dpi: int) -> Path:
    """Write ``fig`` to ``path`` (format from the suffix) and close it."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    return path
