"""Modelling: what the robot believes about itself, the ball and the others, with uncertainty and age.

Inputs are the percepts of :mod:`agents.vision` (robot-relative) and the robot's odometry;
outputs are estimates in the robot frame and the field frame (docs/design/index.md section 3).
"""
