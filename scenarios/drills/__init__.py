"""Drills: one situation of a match played many times, each trial a short match cut off once its
question is answered, and what the trials came to with 95% intervals.

:mod:`~scenarios.drills.base` is what a drill is, :mod:`~scenarios.drills.ball_drill` the base of
the free-play drills that end by where the ball is; :mod:`~scenarios.drills.registry` names the
drills (throw-in, shooting, duel, goal-line); :mod:`~scenarios.drills.run` plays a batch of trials
on the batch engine and writes its report (:mod:`~scenarios.drills.report`).
"""
