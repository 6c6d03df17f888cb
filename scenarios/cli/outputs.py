"""Output paths checked before anything is written: a directory to write into, or a file to write.

:func:`output_problem` says why a path cannot take the output (or None): an empty path, a
name or path too long, a place under ``/proc`` or ``/sys``, an existing path of the wrong
kind, a path under a regular file or a broken symbolic link, or a directory that cannot be
written. Writability is tried in the nearest existing directory with an anonymous temporary
file, so nothing is created and nothing is left behind.
"""

from __future__ import annotations

import os
import stat
import tempfile
from pathlib import Path

NOT_FOR_OUTPUT = (Path("/proc"), Path("/sys"))  # kernel interfaces, not places for result files
NAME_MAX = 255  # bytes in one name (Linux file systems)
PATH_MAX = 4096  # bytes in a whole path, with its terminating NUL (Linux)


def output_problem(text: str, *, directory: bool) -> str | None:
    """Why ``text`` cannot be written (as a directory to create or fill, or else as a file), or None."""
    if not text.strip() or "\0" in text:
        return f"expected a path, got {_shown(text)!r}"
    path = Path(text).absolute()
    if len(os.fsencode(str(path))) >= PATH_MAX:
        return f"{_shown(text)}: expected a path shorter than {PATH_MAX} bytes"
    if any(len(os.fsencode(part)) > NAME_MAX for part in path.parts):
        return f"{_shown(text)}: expected names of at most {NAME_MAX} bytes"
    real = Path(os.path.realpath(path))
    for forbidden in NOT_FOR_OUTPUT:
        if real == forbidden or forbidden in real.parents:
            return f"{text} is under {forbidden}, not a place for output files"
    try:
        mode = os.stat(path).st_mode
    except (FileNotFoundError, NotADirectoryError):
        mode = None
    except OSError as error:  # a loop of symbolic links, a permission
        return f"{text}: {error.strerror}"
    if mode is None:
        if os.path.lexists(path):
            return f"{text} is a broken symbolic link"
        base, problem = _nearest_directory(path.parent)
        return problem or _unwritable(base, text)
    if directory and not stat.S_ISDIR(mode):
        return f"{text} exists and is not a directory"
    if not directory and stat.S_ISDIR(mode):
        return f"{text} is a directory"
    if not directory and not stat.S_ISREG(mode):
        return f"{text} exists and is not a regular file"
    if not directory and not os.access(path, os.W_OK):
        return f"{text} is not writable"
    return _unwritable(path if directory else path.parent, text)


def _shown(text: str) -> str:
    return text if len(text) <= 60 else text[:57] + "..."


def _nearest_directory(path: Path) -> tuple[Path, str | None]:
    """The nearest existing directory at or above ``path``, or why there is none to create ``path`` in."""
    for candidate in (path, *path.parents):
        if os.path.exists(candidate):
            if not os.path.isdir(candidate):
                return candidate, f"{candidate} is not a directory"
            return candidate, None
        if os.path.lexists(candidate):
            return candidate, f"{candidate} is a broken symbolic link"
    return path, f"no directory above {path}"  # only when even the root cannot be seen


def _unwritable(base: Path, text: str) -> str | None:
    """Why nothing can be written in the directory ``base`` (for the path ``text``), or None."""
    if not os.access(base, os.W_OK | os.X_OK):
        return f"{text}: cannot write in {base} (permission denied)"
    try:
        with tempfile.TemporaryFile(dir=base):
            pass
    except OSError as error:
        return f"{text}: cannot write in {base} ({error.strerror or error})"
    return None
