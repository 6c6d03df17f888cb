"""What the policies report for the match log each step, read so that no report can stop the match.

A :class:`~match.protocol.policy.PoseReporter` reports its pose estimate, an
:class:`~match.protocol.policy.AgentReporter` its :class:`~match.protocol.policy.AgentReport`.
Reports are for the log only: one that raises or does not fit its type
(:class:`~match.errors.InvalidReportError`) is not a fault of play. The robot gets None for
that step (the log records nothing for it, NaN) and the first such failure of each robot and
kind of report is logged as a warning; later ones are counted (:attr:`ReportReader.failures`).
"""

from __future__ import annotations

import logging
from collections import Counter
from collections.abc import Callable, Mapping
from typing import TypeVar

from match.protocol.policy import AgentReport, AgentReporter, Policy, PoseReporter, PoseTuple, check_pose

log = logging.getLogger(__name__)

T = TypeVar("T")


class ReportReader:
    """Reads the reports of ``policies`` (agent id -> policy); see the module docstring."""

    def __init__(self, policies: Mapping[str, Policy]):
        self.failures: Counter[tuple[str, str]] = Counter()  # (agent, "pose_estimate" or "report") -> count
        # Which policy reports what is decided once (a protocol check costs microseconds).
        self._poses = {agent: _pose_of(policy) for agent, policy in policies.items()}
        self._reports = {agent: _report_of(policy) for agent, policy in policies.items()}

    def estimates(self) -> dict[str, PoseTuple | None]:
        """Each robot's pose estimate (field frame), None where its policy reports none."""
        return {agent: self._read(agent, "pose_estimate", read) for agent, read in self._poses.items()}

    def reports(self) -> dict[str, AgentReport | None]:
        """Each robot's :class:`AgentReport`, None where its policy reports none."""
        return {agent: self._read(agent, "report", read) for agent, read in self._reports.items()}

    def _read(self, agent: str, kind: str, read: Callable[[], T | None] | None) -> T | None:
        if read is None:
            return None
        try:
            return read()
        except KeyboardInterrupt:
            raise
        except BaseException as error:  # noqa: B036 - a report is for the log only: it must not end the match
            self.failures[agent, kind] += 1
            if self.failures[agent, kind] == 1:
                log.warning("%s of %s failed (%s: %s); the log records nothing for it when it fails "
                            "(warned once per robot)", kind, agent, type(error).__name__, error)
            return None


def _pose_of(policy: Policy) -> Callable[[], PoseTuple | None] | None:
    if not isinstance(policy, PoseReporter):
        return None
    return lambda: check_pose(policy.pose_estimate())


def _report_of(policy: Policy) -> Callable[[], AgentReport | None] | None:
    if not isinstance(policy, AgentReporter):
        return None
    return lambda: AgentReport.check(policy.report())

