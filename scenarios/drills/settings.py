"""What a drill batch plays: the drill with its parameters, a policy per role, the trials and their seeds.

Trial ``k`` has the seed ``seed + k``: a trial is the same whatever the trial count, the worker
count or the backend. The fingerprint covers everything that changes a result (``--resume``
refuses a directory of another).
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Mapping
from dataclasses import dataclass

from scenarios.drills.base import Drill, DrillError

SEED_MAX = 2**32 - 1  # a match seed
MAX_TRIALS = 10_000
DEFAULT_TRIALS = 40


@dataclass(frozen=True)
class DrillSettings:
    """``drill``: the drill and its parameters; ``policies``: (role, policy name) for every role of the drill,
    in its order; ``trials``: how many; ``seed``: the first trial's."""

    drill: Drill
    policies: tuple[tuple[str, str], ...]
    trials: int = DEFAULT_TRIALS
    seed: int = 0

    def __post_init__(self) -> None:
        object.__setattr__(self, "policies", tuple((str(r), str(n)) for r, n in dict(self.policies).items()))
        roles = tuple(role.name for role in self.drill.ROLES)
        if tuple(role for role, _ in self.policies) != roles:
            given = ", ".join(role for role, _ in self.policies) or "none"
            raise DrillError(f"policies for {given}; the {self.drill.NAME} drill expects one for each of "
                             f"{', '.join(roles)}")
        if not _is_int(self.trials) or not 1 <= self.trials <= MAX_TRIALS:
            raise DrillError(f"--trials {self.trials!r:.40}: expected an integer from 1 to {MAX_TRIALS}")
        if not _is_int(self.seed) or not 0 <= self.seed <= SEED_MAX:
            raise DrillError(f"--seed {self.seed!r:.40}: expected an integer from 0 to {SEED_MAX}")
        if self.seed + self.trials - 1 > SEED_MAX:
            raise DrillError(f"--seed {self.seed} with --trials {self.trials}: the last trial's seed would be "
                             f"{self.seed + self.trials - 1}; expected seed + trials - 1 <= {SEED_MAX}")

    def policy_names(self) -> Mapping[str, str]:
        """Role -> policy name."""
        return dict(self.policies)

    def seeds(self) -> range:
        return range(self.seed, self.seed + self.trials)

    def tasks(self) -> tuple[TrialTask, ...]:
        return tuple(TrialTask(k, seed, self) for k, seed in enumerate(self.seeds()))

    def to_json(self) -> dict:
        return {"drill": self.drill.NAME, "parameters": self.drill.to_json(), "policies": dict(self.policies),
                "trials": self.trials, "seed": self.seed}

    def fingerprint(self) -> str:
        """A hash of everything that changes the results (for ``--resume``): sha256 hex, 16 digits."""
        return hashlib.sha256(json.dumps(self.to_json(), sort_keys=True).encode("utf-8")).hexdigest()[:16]


@dataclass(frozen=True)
class TrialTask:
    """One trial of a batch: its index, its seed and the batch's settings."""

    index: int
    seed: int
    settings: DrillSettings

    @property
    def label(self) -> str:
        return f"{self.settings.drill.NAME} trial {self.index} (seed {self.seed})"


def _is_int(value: object) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)
