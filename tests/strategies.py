"""Hypothesis strategies shared by the tests."""

from __future__ import annotations

import math

from hypothesis import strategies as st

from world.field import FIELD, Pose2D

field_pose = st.builds(
    Pose2D,
    st.floats(-FIELD.half_length, FIELD.half_length),
    st.floats(-FIELD.half_width, FIELD.half_width),
    st.floats(-math.pi, math.pi),
)
"""A pose anywhere on the field (within the lines), any heading."""
