"""What keeps a controller process to its own robots, and ends everything a policy started.

On Linux (``prctl``):

- the simulator and every controller are not *dumpable*: another process of the same user
  cannot open their ``/proc/PID/fd``, ``map_files`` or ``mem`` (where the other team's camera
  images and pipes are), nor attach a debugger to them;
- the simulator is a *child subreaper*: a process a policy starts that outlives its controller
  (a daemon that left the controller's session included) becomes the simulator's child instead
  of init's, so :func:`end_orphans` can end it;
- a controller leads a session of its own (every process its policy starts joins it unless it
  leaves) and dies with its parent, the server process that forked it.

Elsewhere only the sessions are used: each function does what the system allows and nothing else.
Everywhere a controller runs at a lower priority than the simulator (:data:`CONTROLLER_NICENESS`).
"""

from __future__ import annotations

import contextlib
import ctypes
import logging
import os
import signal
import sys

from world.process_memory import stat_fields

log = logging.getLogger(__name__)

PR_SET_PDEATHSIG = 1
PR_SET_DUMPABLE = 4
PR_SET_CHILD_SUBREAPER = 36
CONTROLLER_NICENESS = 5
"""How much lower a controller's scheduling priority is than the simulator's (inherited by every process
and thread a policy starts). Busy work a policy leaves running (threads, children) then takes the
processor time the simulator leaves instead of slowing every robot's step; a policy that only answers
its observations loses nothing, as it waits for them anyway."""


def _prctl(option: int, value: int) -> bool:
    """``prctl(option, value)``; whether it took effect (False where there is no prctl)."""
    if not sys.platform.startswith("linux"):
        return False
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        return libc.prctl(option, value, 0, 0, 0) == 0
    except (OSError, AttributeError):
        return False


def guard_simulator() -> None:
    """In the simulator, before its controllers start: not dumpable, and the reaper of their orphans."""
    _prctl(PR_SET_DUMPABLE, 0)
    _prctl(PR_SET_CHILD_SUBREAPER, 1)


def confine_controller() -> None:
    """In a controller process, before its policies are built: a session of its own, not dumpable, killed
    when its parent ends, and :data:`CONTROLLER_NICENESS` below the simulator's priority."""
    with contextlib.suppress(OSError):
        os.setsid()
    with contextlib.suppress(OSError):
        os.nice(CONTROLLER_NICENESS)
    _prctl(PR_SET_DUMPABLE, 0)
    _prctl(PR_SET_PDEATHSIG, int(signal.SIGKILL))


def end_session(leader: int) -> None:
    """Kill what is left of the session (and process group) a controller ``leader`` (its pid) led."""
    with contextlib.suppress(OSError):
        os.killpg(leader, signal.SIGKILL)


def end_orphans(spared: frozenset[int] = frozenset()) -> int:
    """Kill and reap this process's children that live in another session than its own, but those in
    ``spared`` (the children it had before its controllers started, see :func:`children`): processes a
    policy started that outlived their controller (reparented here, see :func:`guard_simulator`). The
    server processes of :mod:`multiprocessing` share this process's session and are left alone.
    Returns how many were ended (Linux only; 0 elsewhere)."""
    own_session = os.getsid(0)
    ended = 0
    for pid in children():
        try:
            if pid in spared or os.getsid(pid) == own_session:
                continue
            os.kill(pid, signal.SIGKILL)
        except OSError:
            continue
        with contextlib.suppress(ChildProcessError, OSError):
            os.waitpid(pid, 0)
        ended += 1
    if ended:
        log.warning("ended %d process(es) that policies left running", ended)
    return ended


def children() -> list[int]:
    """The pids of this process's children (from ``/proc``; none where it is missing)."""
    own = os.getpid()
    children = []
    try:
        entries = os.listdir("/proc")
    except OSError:
        return []
    for entry in entries:
        if not entry.isdigit():
            continue
        fields = stat_fields(int(entry))
        if fields is not None and len(fields) > 1 and int(fields[1]) == own:
            children.append(int(entry))
    return children
