"""TOML text parsed with bounds checked first: every TOML file of the project is read through :func:`load_toml`.

Python's TOML parser takes time that grows with the square of a dotted key's parts (``a.b.c...``,
in a key or a table header), and follows nested arrays and inline tables by recursion. So the
raw text is searched for a dotted key of more than :data:`MAX_KEY_PARTS` parts before it is
parsed (one regular-expression pass, linear in the text), and nesting the parser cannot follow
is refused as a :class:`TomlBoundsError`. It is a ``tomllib.TOMLDecodeError``, so a reader that
refuses bad TOML refuses these the same way. Scenario files and the team agent's parameter
files are both read here, so the bounds are the same everywhere. :func:`read_toml_file` reads a
file for it: a regular file of at most :data:`MAX_TOML_BYTES` (a device or a pipe named as a
file would never end).
"""

from __future__ import annotations

import errno
import os
import re
import stat
import tomllib
from pathlib import Path

MAX_TOML_BYTES = 1_000_000
MAX_KEY_PARTS = 64  # far more than any key of the project's files has; the parser's cost stays negligible

_PART = r"""(?:[A-Za-z0-9_-]+|"(?:[^"\\\n]|\\.)*"|'[^'\n]*')"""  # a bare, basic-string or literal-string key
_DOT = r"[ \t]*\.[ \t]*"
_START = r"""(?<![A-Za-z0-9_.'"\\-])"""  # a key starts after none of its own characters: each chain is tried once
_LONG_KEY = re.compile(rf"{_START}{_PART}(?:{_DOT}{_PART}){{{MAX_KEY_PARTS}}}")  # one part more than allowed


class TomlBoundsError(tomllib.TOMLDecodeError):
    """TOML text past the bounds checked before parsing: a dotted key of too many parts, or nesting too deep."""

    def __init__(self, message: str):
        ValueError.__init__(self, message)  # a plain message: the parser's own (msg, doc, pos) does not apply


def load_toml(text: str) -> dict:
    """``text`` parsed by ``tomllib`` once its keys are known to have at most :data:`MAX_KEY_PARTS` parts;
    ``tomllib.TOMLDecodeError`` (a :class:`TomlBoundsError` for the bounds) when it is not valid TOML."""
    found = _LONG_KEY.search(text)
    if found is not None:
        line = text.count("\n", 0, found.start()) + 1
        raise TomlBoundsError(f"a dotted key of more than {MAX_KEY_PARTS} parts (line {line})")
    try:
        return tomllib.loads(text)
    except RecursionError:
        raise TomlBoundsError("arrays or inline tables nested deeper than the parser can follow") from None


def read_toml_file(path: str | Path) -> dict:
    """The TOML of the file at ``path`` through :func:`load_toml`. ``OSError`` (its ``strerror`` one line)
    when it is not a regular file of at most :data:`MAX_TOML_BYTES`, checked before it is opened and again
    on the opened file; ``UnicodeDecodeError`` or ``tomllib.TOMLDecodeError`` for its text."""
    if not stat.S_ISREG(os.stat(path).st_mode):
        raise OSError(errno.EINVAL, "not a regular file")
    descriptor = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    with open(descriptor, "rb") as handle:
        if not stat.S_ISREG(os.fstat(descriptor).st_mode):  # replaced between the two looks
            raise OSError(errno.EINVAL, "not a regular file")
        raw = handle.read(MAX_TOML_BYTES + 1)
    if len(raw) > MAX_TOML_BYTES:
        raise OSError(errno.EFBIG, f"more than {MAX_TOML_BYTES} bytes")
    return load_toml(raw.decode("utf-8"))
