"""The team agent's behaviour: options with named states, and cards chosen in order, per game situation.

It reads only the step's :class:`~agents.team.modelling.representations.WorldModel` and writes
requests (:mod:`~agents.team.behavior.requests`): the motion and walk, the head and camera, and
what goes out over the radio (role, intention, time to the ball). The root
(:mod:`~agents.team.behavior.root`) plays the game state; in PLAYING the role chosen from the
registry (:mod:`~agents.team.behavior.roles`) plays, its cards and set plays each in a file.
"""
