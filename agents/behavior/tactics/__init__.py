"""Tactics: the decisions a player makes about the ball and its team, from beliefs to targets (aims,
windows, spots, roles), shared by the built-in policies; they move the robot through :mod:`..skills`."""
