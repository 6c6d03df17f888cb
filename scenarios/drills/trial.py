"""One trial, as a worker plays it: the drill's setup, a policy per robot, the match with the drill's
observer, and the record of what it came to.

:func:`play_trial` is the batch engine's work function (a local worker process, this process, or
a Ray task): it returns the record and writes nothing. The policies run in the match's process,
as the referee's observer does; the world's ground truth decides the outcome, the policies see
only their observations.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable
from typing import Any

from agents.policies import make_policy
from match.protocol import Policy, Pose2D
from match.runner import run_match
from scenarios.drills.base import DrillError, rounded
from scenarios.drills.records import TrialRecord
from scenarios.drills.settings import TrialTask

log = logging.getLogger(__name__)

SIM_DECIMALS = 3
WALL_DECIMALS = 3


class Placed:
    """A policy told where the drill put its robot: a team agent's pose estimate is set there at its reset
    (as at a kick-off); any other policy plays as it is."""

    def __init__(self, policy: Any, pose: Pose2D):
        self.policy, self.pose = policy, pose

    def reset(self, agent_id: str, seed: int) -> None:
        self.policy.reset(agent_id, seed)
        world = getattr(self.policy, "world", None)
        if world is not None:
            world.locator.reset(self.pose)

    def act(self, observation: Any) -> dict:
        return self.policy.act(observation)

    def think(self) -> None:
        think = getattr(self.policy, "think", None)
        if think is not None:
            think()


def play_trial(task: TrialTask, tick: Callable[..., None] | None = None) -> TrialRecord:
    """Play ``task``'s trial and return its record. ``tick``: the batch's progress counter, unused (the
    batch counts whole trials)."""
    started = time.perf_counter()
    drill = task.settings.drill
    setup = drill.trial_setup(task.seed)
    names = task.settings.policy_names()
    policies: dict[str, Policy] = {}
    for robot, role in setup.roles.items():
        policy = make_policy(names[role])
        policies[robot] = Placed(policy, setup.placed[robot]) if robot in setup.placed else policy
    observer = drill.observe(setup)
    summary = run_match(setup.config, policies, seed=task.seed, progress=False, observer=observer)
    score = drill.score(setup, observer)
    values = {**rounded(setup.facts), **score.figures}
    if score.outcome not in drill.OUTCOMES:
        raise DrillError(f"the {drill.NAME} drill's trial came to {score.outcome!r}; its OUTCOMES are "
                         f"{', '.join(drill.OUTCOMES)}")
    if list(values) != list(drill.COLUMNS):
        raise DrillError(f"the {drill.NAME} drill's trial gave {', '.join(values)}; its COLUMNS are "
                         f"{', '.join(drill.COLUMNS)}")
    record = TrialRecord(task.index, task.seed, "ok", score.outcome, values, round(summary.sim_seconds, SIM_DECIMALS),
                         round(time.perf_counter() - started, WALL_DECIMALS))
    log.debug("%s: %s %s", task.label, record.outcome, values)
    return record
