"""A process's peak resident memory, as the system reports it (Linux's ``/proc``)."""

from __future__ import annotations


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
