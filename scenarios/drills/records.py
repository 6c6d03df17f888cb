"""A trial's record: what the batch keeps of one trial (``runs/trial_NNNN.json``) and what a report row shows.

A record is flat JSON: ``trial``, ``seed``, ``status`` (``ok`` or ``failed``), ``outcome``, the
drill's ``COLUMNS`` (its seeded facts, then its figures), ``sim_seconds``, ``wall_seconds``,
``error`` and ``attempts``. A record read back for ``--resume`` is checked as untrusted: a
:class:`ValueError` names the first key that is not what this batch's trial would hold.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from scenarios.common.batch import check_bounds, check_fields
from scenarios.drills.base import Drill, Value
from scenarios.drills.settings import TrialTask

STATUSES = ("ok", "failed")
MAX_SECONDS = 1e7  # a trial's simulated or wall time
MAX_FIGURE = 1e9  # a fact or figure of a trial: metres, seconds or a count
MAX_TEXT = 200  # characters of a text figure (a robot's id)
MAX_ATTEMPTS = 100


@dataclass(frozen=True)
class TrialRecord:
    """One trial: its index and seed, ``ok`` with its outcome and ``values`` (the drill's columns; None:
    none) or ``failed`` with its ``error``; simulated and wall time (s); the attempts it took."""

    trial: int
    seed: int
    status: str
    outcome: str | None
    values: Mapping[str, Value]
    sim_seconds: float | None = None
    wall_seconds: float | None = None
    error: str | None = None
    attempts: int = 1

    @property
    def ok(self) -> bool:
        return self.status == "ok"

    @classmethod
    def failure(cls, task: TrialTask, error: str, attempts: int) -> TrialRecord:
        """A trial whose worker raised or died: no outcome, no values."""
        columns = task.settings.drill.COLUMNS
        return cls(task.index, task.seed, "failed", None, dict.fromkeys(columns), error=error, attempts=attempts)

    def to_json(self) -> dict:
        return {"trial": self.trial, "seed": self.seed, "status": self.status, "outcome": self.outcome,
                **self.values, "sim_seconds": self.sim_seconds, "wall_seconds": self.wall_seconds,
                "error": self.error, "attempts": self.attempts}


def header(drill: Drill) -> tuple[str, ...]:
    """The columns of ``results.csv``: a record's keys in order."""
    return ("trial", "seed", "status", "outcome", *drill.COLUMNS, "sim_seconds", "wall_seconds", "error", "attempts")


def stored_record(tasks: Sequence[TrialTask], index: int, data: Mapping) -> TrialRecord:
    """The record of trial ``index`` read back; a ``ValueError`` naming the key when it is not this batch's
    trial (another seed) or a key is missing, of another type or out of bounds."""
    if index >= len(tasks):
        raise ValueError(f"trial {index} is not one of the batch's {len(tasks)} trials")
    task = tasks[index]
    drill = task.settings.drill
    check_fields(data, {"seed": int, "status": str, "attempts": int})
    if data["seed"] != task.seed:
        raise ValueError(f"seed = {data['seed']}; trial {index} of this batch has seed {task.seed}")
    if data["status"] not in STATUSES:
        raise ValueError(f"status = {data['status'][:40]!r}; expected 'ok' or 'failed'")
    check_bounds(data, {"attempts": (1, MAX_ATTEMPTS)})
    if data["status"] == "failed":
        check_fields(data, {"error": str})
        return TrialRecord.failure(task, data["error"], data["attempts"])
    check_fields(data, {"outcome": str, "sim_seconds": float, "wall_seconds": float})
    if data["outcome"] not in drill.OUTCOMES:
        raise ValueError(f"outcome = {data['outcome'][:40]!r}; expected one of {', '.join(drill.OUTCOMES)}")
    check_bounds(data, {"sim_seconds": (0.0, MAX_SECONDS), "wall_seconds": (0.0, MAX_SECONDS)})
    check_fields(data, {column: (kind, type(None)) for column, kind in drill.COLUMNS.items()})
    numbers = [column for column, kind in drill.COLUMNS.items() if kind is not str]
    check_bounds(data, dict.fromkeys(numbers, (-MAX_FIGURE, MAX_FIGURE)))
    for column in drill.COLUMNS:
        if isinstance(data[column], str) and len(data[column]) > MAX_TEXT:
            raise ValueError(f"{column} = a text of {len(data[column])} characters; expected at most {MAX_TEXT}")
    values = {column: data[column] for column in drill.COLUMNS}
    return TrialRecord(index, task.seed, "ok", data["outcome"], values, data["sim_seconds"], data["wall_seconds"],
                       None, data["attempts"])
