"""What a scenario file describes (thesis chapter 6): the robots, who is measured, the methods.

Plain frozen data, built by :func:`scenarios.localization.file.load_scenario` from a TOML
file and used by the runner (:mod:`scenarios.localization.run`) and the report
(:mod:`scenarios.localization.statistics`). Units: metres, seconds, radians inside; the file
gives start headings in degrees (``theta_deg``) and the thesis' figures in cm and degrees.

Two ways of taking samples: at the measured robots' localization events (the thesis'
move-scan-localize cycle, policies of :data:`MEASURABLE_POLICIES`, every method side by
side), or periodically (``sample_period_s``): every so many seconds of PLAYING time, the
pose estimate of each measured robot that is up, from any policy that reports its pose
(:class:`match.protocol.PoseReporter`), while it plays.
"""

from __future__ import annotations

import dataclasses
import enum
import hashlib
import json
import math
from dataclasses import dataclass

import numpy as np

from world.camera_profiles import DEFAULT_CAMERA_PROFILE
from world.field import Pose2D


MEASURABLE_POLICIES = ("scan_localize",)  # policies that record localization events (``.events``)
# With periodic sampling any policy that reports its pose (PoseReporter) can be measured.


@dataclass(frozen=True)
class ThesisReference:
    """The thesis' Table 6.1 / 6.2 row for a scenario: means and 95% half-widths."""

    position_mean_cm: float
    position_ci95_cm: float
    orientation_mean_deg: float
    orientation_ci95_deg: float


@dataclass(frozen=True)
class RobotEntry:
    """One robot: its agent id (``home_0`` .. ``away_3``), its policy, whether it is measured.

    ``start``: the pose it is placed at without a referee (a fixed pose, or ``None`` for a
    random pose drawn from the run's seed); with a referee the kick-off positions apply.
    """

    id: str
    policy: str  # a policy name: built in (see agents.policies) or package.module:ClassName
    measured: bool = False
    start: Pose2D | None = None


@dataclass(frozen=True)
class ScenarioSpec:
    """A whole scenario.

    ``samples``: localization events of measured robots per method, over all runs;
    ``runs``: independent simulations the samples are split over (each with its own seed,
    drawn from ``seed``); ``referee``: a match with the referee (kick-offs, goals, robots
    replaced) or the bare world with no ball; ``half_seconds``: the length of a half with
    the referee; ``motion_noise_scale``: factor on every sigma of the world's motion noise
    (1: the default model, 0: motions land exactly); ``max_sim_seconds_per_run``: a run
    still short of its samples after this much simulated time ends with what it has;
    ``warmup_seconds``: localization events in a run's first seconds of simulated time are
    not samples (with the referee, the game has developed by then; the localizers run
    throughout); ``sample_period_s``: None, samples at the measured robots' localization
    events (one per method); a number of seconds, one sample of each measured robot's own
    pose estimate every ``sample_period_s`` of PLAYING time while it is up, labelled with
    its policy's name, and a run also ends, complete, with the match (``methods`` and
    ``camera_model`` are not used then); ``camera_profile``: what the robots' cameras do to the
    rendered frames (:mod:`world.camera_profiles`).
    """

    name: str
    description: str
    samples: int
    runs: int
    seed: int
    methods: tuple[str, ...]
    camera_model: str
    referee: bool
    robots: tuple[RobotEntry, ...]
    half_seconds: float = 600.0
    motion_noise_scale: float = 1.0
    max_sim_seconds_per_run: float = 1200.0
    thesis: ThesisReference | None = None
    warmup_seconds: float = 0.0
    sample_period_s: float | None = None
    camera_profile: str = DEFAULT_CAMERA_PROFILE

    @property
    def measured(self) -> tuple[str, ...]:
        return tuple(r.id for r in self.robots if r.measured)

    @property
    def periodic(self) -> bool:
        """Whether samples are taken every ``sample_period_s`` of PLAYING time (else at localization events)."""
        return self.sample_period_s is not None

    def expected_samples(self) -> int:
        """Samples a batch of this scenario expects: ``samples``; with periodic sampling at most what
        its matches give (a sample a period of each half, per measured robot and run)."""
        if self.sample_period_s is None:
            return self.samples
        per_match = len(self.measured) * math.floor(2.0 * self.half_seconds / self.sample_period_s)
        return min(self.samples, self.runs * per_match)

    def run_samples(self) -> tuple[int, ...]:
        """Samples per run: ``samples`` split as evenly as possible, earlier runs taking the rest."""
        base, extra = divmod(self.samples, self.runs)
        return tuple(base + (1 if run < extra else 0) for run in range(self.runs))

    def run_seeds(self) -> tuple[int, ...]:
        """One seed per run, drawn from ``seed``: a run's seed does not depend on how many run at once."""
        return tuple(int(s.generate_state(1)[0]) for s in np.random.SeedSequence(self.seed).spawn(self.runs))

    def fingerprint(self) -> str:
        """A hash of everything that changes the results (for ``--resume``): sha256 hex, 16 digits."""
        data = dataclasses.asdict(self)
        if data["sample_period_s"] is None:  # event sampling: the fingerprint of the scenarios before periodic sampling
            del data["sample_period_s"]
        if data["camera_profile"] == "clean":  # the fingerprint of the scenarios before camera profiles
            del data["camera_profile"]
        text = json.dumps(data, sort_keys=True, default=_plain)
        return hashlib.sha256(text.encode("utf-8")).hexdigest()[:16]


def _plain(value: object) -> object:
    if isinstance(value, enum.Enum):
        return value.value
    raise TypeError(f"cannot serialize {value!r}")
