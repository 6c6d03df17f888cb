"""A process's resident memory, its peak and its processor time, as the system reports them (Linux's ``/proc``)."""

from __future__ import annotations

import os

PAGE_BYTES = os.sysconf("SC_PAGE_SIZE") if hasattr(os, "sysconf") else 4096


def resident_mb(pid: int) -> float | None:
    """Resident memory of process ``pid`` now, in MiB (Linux), None where the system does not say."""
    try:
        with open(f"/proc/{pid}/statm", encoding="ascii") as statm:
            pages = int(statm.read().split()[1])
    except (OSError, ValueError, IndexError):
        return None
    return pages * PAGE_BYTES / 2**20


def peak_resident_mb(pid: int) -> float | None:
    """Peak resident memory of process ``pid`` since it started, in MiB (Linux's ``VmHWM``), None where the
    system does not say."""
    try:
        with open(f"/proc/{pid}/status", encoding="ascii", errors="replace") as status:
            for line in status:
                if line.startswith("VmHWM:"):
                    value, unit = line.split()[1:3]
                    return int(value) / 1024 if unit == "kB" else None
    except (OSError, ValueError):
        return None
    return None


CLOCK_TICKS_PER_S = os.sysconf("SC_CLK_TCK") if hasattr(os, "sysconf") else 100


def cpu_seconds(pid: int) -> float | None:
    """The processor time process ``pid`` has used so far, in seconds (Linux): its main thread's to the
    nanosecond where the scheduler reports it, else all its threads' to the clock tick; None where the
    system does not say."""
    try:
        with open(f"/proc/{pid}/schedstat", "rb") as schedstat:
            return _schedstat_seconds(schedstat.read())
    except (OSError, ValueError, IndexError):
        pass
    fields = stat_fields(pid)
    try:
        return (int(fields[11]) + int(fields[12])) / CLOCK_TICKS_PER_S if fields else None
    except (ValueError, IndexError):
        return None


def _schedstat_seconds(schedstat: bytes) -> float:
    """The processor time (s) in the text of ``/proc/PID/schedstat`` (its first field, in nanoseconds)."""
    return int(schedstat.split()[0]) / 1e9


class ProcessorClock:
    """The processor time of process ``pid``'s main thread, as :func:`cpu_seconds` reads it, from a
    descriptor opened once: a read costs a system call instead of a path lookup, and a clock never reads
    another process that reused the pid (once the process is gone it reads None). Falls back to
    :func:`cpu_seconds` where ``schedstat`` cannot be opened; :meth:`close` releases the descriptor."""

    def __init__(self, pid: int):
        self.pid = pid
        try:
            self._fd: int | None = os.open(f"/proc/{pid}/schedstat", os.O_RDONLY | os.O_CLOEXEC)
        except (OSError, AttributeError):
            self._fd = None

    def seconds(self) -> float | None:
        """Processor time used so far, in seconds; None once the process is gone or where the system does
        not say."""
        if self._fd is None:
            return cpu_seconds(self.pid)
        try:
            return _schedstat_seconds(os.pread(self._fd, 128, 0))
        except (OSError, ValueError, IndexError):
            return None

    def close(self) -> None:
        if self._fd is not None:
            os.close(self._fd)
            self._fd = None


def stat_fields(pid: int) -> list[bytes] | None:
    """The fields of ``/proc/PID/stat`` after the command name (the first is the state, the second the
    parent's pid), None where the system does not say."""
    try:
        with open(f"/proc/{pid}/stat", "rb") as stat:
            return stat.read().rsplit(b")", 1)[1].split()
    except (OSError, IndexError):
        return None
