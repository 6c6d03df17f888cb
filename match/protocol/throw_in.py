"""Where the referee puts the ball after it left the field: a rule of the game that every player
knows (SPL 2011 as run by RobotStadium). Field frame, metres (docs/design/index.md section 3)."""

from __future__ import annotations

from world.field import FIELD, FieldGeometry, GoalColor

THROW_IN_INSET_M = 0.4  # throw-in line: this far inside the side line
THROW_IN_BACK_M = 1.0  # ball moved back toward the goal of the team that touched it last
THROW_IN_MAX_X_M = 2.0  # the throw-in line's ends


def throw_in_spot(
    out_x: float, out_y: float, over_end_line: bool, toucher_defends: GoalColor | None, field: FieldGeometry = FIELD
) -> tuple[float, float]:
    """Where the ball goes after leaving the field at (``out_x``, ``out_y``), given the goal the
    last toucher defends (None: nobody touched it).

    Side line: on the throw-in line, 1 m back toward the toucher's own goal, |x| <= 2.
    End line: by the defending team -> the end of the throw-in line on that side; by the
    attacking team (or nobody) -> the halfway line. Always on the side where it went out.
    """
    side = 1.0 if out_y >= 0.0 else -1.0
    y = side * (field.half_width - THROW_IN_INSET_M)
    if not over_end_line:
        x = out_x
        if toucher_defends is not None:
            x += toucher_defends.sign * THROW_IN_BACK_M
        return min(max(x, -THROW_IN_MAX_X_M), THROW_IN_MAX_X_M), y
    crossed = GoalColor.YELLOW if out_x > 0 else GoalColor.BLUE
    if toucher_defends is crossed:
        return crossed.sign * THROW_IN_MAX_X_M, y
    return 0.0, y
