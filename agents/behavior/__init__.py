"""Behaviours: what a robot does with what it sees and believes.

Three layers, each importing only the ones below it: :mod:`.skills` (motion units: walk to a pose,
chase and kick, look at the ball, step around obstacles), :mod:`.tactics` (decisions a player makes
about the ball and its team: where to aim, the shot window, roles and their spots, a ball at a goal
line, a stalled ball, a lock with another robot) and :mod:`.policies` (whole built-in players other
than the team agent, :mod:`agents.team`).
"""
