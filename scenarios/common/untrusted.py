"""Reading files one does not trust (a match's logs, run records, scenario files): bounded before they are parsed.

Anything may sit under a name that should hold a log: a link to ``/dev/zero`` (it never ends), a
pipe (opening it waits for a writer), text nested 100,000 levels deep (the JSON parser recurses),
an archive whose array header claims terabytes (loading allocates them first). So every reader
here refuses before it parses or allocates:

- :func:`read_small_file`: a regular file only (``os.stat`` before it is opened, opened without
  waiting and checked again once open) of at most the bytes asked;
- :func:`load_json` and :func:`check_json_depth`: JSON nested at most :data:`MAX_JSON_DEPTH`
  levels, measured on the raw bytes (strings left out) before the parser sees them; an integer
  of more than :data:`MAX_NUMBER_DIGITS` digits is read as a :class:`LongNumber` (:func:`json_int`),
  which no field accepts, so that its refusal names the field;
- :class:`NpzArchive`: an ``.npz`` of at most :data:`MAX_NPZ_MEMBERS` arrays whose ``.npy``
  headers are read, and checked by the caller, before any array is loaded; no Python objects
  (pickles) and no array bigger than :data:`MAX_ARRAY_BYTES`.

Every refusal is a :class:`SmallFileError` whose ``reason`` is one line; the caller names the file.
"""

from __future__ import annotations

import errno
import json
import math
import os
import re
import stat
import struct
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

MAX_JSON_DEPTH = 64  # the project's files nest a few levels; the parser follows about a thousand
MAX_NUMBER_DIGITS = 400  # past float64's range, far past any count of the project's files
MAX_NPZ_MEMBERS = 64
MAX_ARRAY_BYTES = 4 << 30  # a backstop: the caller bounds each array by its layout first
_CHUNK = 1 << 20  # bytes of brackets counted at a time
_MISSING_ERRNOS = (errno.ENOENT, errno.ENOTDIR, errno.ELOOP, errno.EBADF)
_OPEN_FLAGS = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0) | getattr(os, "O_NOCTTY", 0)


class SmallFileError(ValueError):
    """A file that is not what a reader accepts: ``reason`` is what was found (one line, e.g. ``not an
    existing regular file``, ``2000 bytes``, ``nested deeper than 64 levels``); ``missing``: no regular
    file there; ``too_big``: one bigger than asked."""

    def __init__(self, reason: str, *, missing: bool = False, too_big: bool = False):
        super().__init__(reason)
        self.reason, self.missing, self.too_big = reason, missing, too_big


# ---- a regular file of a bounded size -----------------------------------------------------------


def open_regular_file(path: Path, max_bytes: int):
    """``path`` opened for reading in binary: a regular file of at most ``max_bytes`` by its size; a
    :class:`SmallFileError` otherwise (checked before it is opened, so that a pipe is never opened, and
    again on the open file, in case it was replaced in between)."""
    try:
        info = os.stat(path)
    except OSError as error:
        if error.errno in _MISSING_ERRNOS:
            raise SmallFileError("not an existing regular file", missing=True) from None
        raise SmallFileError(error.strerror or type(error).__name__) from None
    except ValueError:  # a NUL byte in the name
        raise SmallFileError("not an existing regular file", missing=True) from None
    _check_regular(info, max_bytes)
    try:
        descriptor = os.open(path, _OPEN_FLAGS)
    except OSError as error:
        raise SmallFileError(error.strerror or type(error).__name__) from None
    handle = open(descriptor, "rb")
    try:
        opened = os.fstat(descriptor)
        _check_regular(opened, max_bytes)
        if (opened.st_dev, opened.st_ino) != (info.st_dev, info.st_ino):
            raise SmallFileError("replaced while it was opened")
    except BaseException:
        handle.close()
        raise
    return handle


def _check_regular(info: os.stat_result, max_bytes: int) -> None:
    if not stat.S_ISREG(info.st_mode):
        raise SmallFileError("not an existing regular file", missing=True)
    if info.st_size > max_bytes:
        raise SmallFileError(f"{info.st_size} bytes", too_big=True)


def read_small_file(path: Path, max_bytes: int) -> bytes:
    """The bytes of ``path``, a regular file of at most ``max_bytes``; :class:`SmallFileError` otherwise:
    not an existing regular file, an error of the system (a name too long, a permission), or bigger
    (by its size, or while it is read: a file that grows)."""
    with open_regular_file(Path(path), max_bytes) as handle:
        try:
            raw = handle.read(max_bytes + 1)
        except OSError as error:
            raise SmallFileError(error.strerror or type(error).__name__) from None
    if len(raw) > max_bytes:
        raise SmallFileError(f"more than {max_bytes} bytes", too_big=True)
    return raw


# ---- JSON of a bounded depth ---------------------------------------------------------------------

_STRING = re.compile(rb'"(?<!\\")[^"\\\n]*+(?:\\.[^"\\\n]*+)*+"')  # a JSON string (one line): no nesting in it
_NOT_BRACKETS = bytes(b for b in range(256) if b not in b"[]{}\n")


def check_json_depth(raw: bytes, max_depth: int = MAX_JSON_DEPTH, *, lines: bool = False) -> None:
    """A :class:`SmallFileError` when the JSON text ``raw`` (with ``lines``: each line a document, as in
    JSON Lines) opens more than ``max_depth`` arrays or objects inside each other. Counted on the raw bytes,
    strings left out, in chunks: the cost is linear in the size and stops at the first line too deep."""
    brackets = _STRING.sub(b"", raw).translate(None, _NOT_BRACKETS)
    depth = 0  # at the start of the chunk, within its line
    line = 1
    for start in range(0, len(brackets), _CHUNK):
        chunk = np.frombuffer(brackets, np.uint8, min(_CHUNK, len(brackets) - start), start)
        step = ((chunk == ord("[")) | (chunk == ord("{"))).astype(np.int32)
        step -= (chunk == ord("]")) | (chunk == ord("}"))
        levels = depth + np.cumsum(step, dtype=np.int64)
        newline = chunk == ord("\n")
        if lines and newline.any():  # depth counts again from 0 after each newline
            positions = np.arange(len(chunk))
            last = np.maximum.accumulate(np.where(newline, positions, -1))
            levels -= np.where(last >= 0, levels[np.maximum(last, 0)], 0)
        deepest = int(np.argmax(levels))
        if levels[deepest] > max_depth:
            where = f" (line {line + int(np.count_nonzero(newline[:deepest]))})" if lines else ""
            raise SmallFileError(f"nested deeper than {max_depth} levels{where}")
        depth = int(levels[-1])
        line += int(np.count_nonzero(newline))


class LongNumber:
    """A JSON integer of more than :data:`MAX_NUMBER_DIGITS` digits, kept as its length only."""

    def __init__(self, digits: int):
        self.digits = digits

    def __repr__(self) -> str:
        return f"<an integer of {self.digits} digits>"


def json_int(text: str) -> int | LongNumber:
    """``parse_int`` of :func:`json.loads`: the integer, or a :class:`LongNumber` for a long one (whose
    conversion would cost time growing with the square of its digits)."""
    return int(text) if len(text) <= MAX_NUMBER_DIGITS else LongNumber(len(text))


def load_json(raw: bytes, max_depth: int = MAX_JSON_DEPTH) -> object:
    """The JSON document ``raw`` (UTF-8), once its depth is checked; :class:`SmallFileError` with the parser's
    reason (one line) when it is not one."""
    check_json_depth(raw, max_depth)
    return parse_json(raw)


def parse_json(raw: bytes | str) -> object:
    """``json.loads`` with every failure (not UTF-8, not JSON, a number of thousands of digits, nesting the
    parser cannot follow) as a :class:`SmallFileError` of one line."""
    try:
        text = raw.decode("utf-8") if isinstance(raw, bytes) else raw
        return json.loads(text, parse_int=json_int)
    except RecursionError:
        raise SmallFileError("nested deeper than the JSON parser follows") from None
    except ValueError as error:  # UnicodeDecodeError and JSONDecodeError are ValueErrors
        raise SmallFileError(" ".join(str(error).split())[:200] or type(error).__name__) from None


# ---- npz archives whose headers are checked before their arrays are loaded --------------------------


@dataclass(frozen=True)
class ArrayHeader:
    """What an ``.npy`` header says of its array: its shape and its dtype (never an object dtype)."""

    shape: tuple[int, ...]
    dtype: np.dtype

    @property
    def nbytes(self) -> int:
        return math.prod(self.shape) * self.dtype.itemsize


class NpzArchive:
    """An ``.npz`` file opened as untrusted: ``headers`` (array name -> :class:`ArrayHeader`) are read when it is
    opened, :meth:`array` loads one array. A :class:`SmallFileError` when it is not a regular file of at most
    ``max_bytes``, not a zip archive, has more than :data:`MAX_NPZ_MEMBERS` members, a header that does not
    read, an object dtype (a pickle) or an array over :data:`MAX_ARRAY_BYTES`."""

    def __init__(self, path: Path, max_bytes: int):
        self._handle = open_regular_file(Path(path), max_bytes)
        try:
            _check_member_count(self._handle)
            self._zip = zipfile.ZipFile(self._handle)
            self.headers = {name: self._header(name) for name in self._names()}
        except SmallFileError:
            self._handle.close()
            raise
        except (zipfile.BadZipFile, EOFError, OSError, ValueError, KeyError, struct.error) as error:
            self._handle.close()
            raise SmallFileError(f"not a readable .npz archive ({type(error).__name__}: "
                                 f"{' '.join(str(error).split())[:120]})") from None
        except BaseException:
            self._handle.close()
            raise

    def _names(self) -> list[str]:
        return [info.filename[:-4] for info in self._zip.infolist() if info.filename.endswith(".npy")]

    def _header(self, name: str) -> ArrayHeader:
        try:
            with self._zip.open(f"{name}.npy") as member:
                version = np.lib.format.read_magic(member)
                if version == (1, 0):
                    shape, _, dtype = np.lib.format.read_array_header_1_0(member)
                elif version == (2, 0):
                    shape, _, dtype = np.lib.format.read_array_header_2_0(member)
                else:
                    raise SmallFileError(f"array {name}: .npy format {version}, expected 1.0 or 2.0")
        except (zipfile.BadZipFile, EOFError, OSError, ValueError, KeyError) as error:
            if isinstance(error, SmallFileError):
                raise
            raise SmallFileError(f"array {name}: a header that does not read ({type(error).__name__})") from None
        if dtype.hasobject:
            raise SmallFileError(f"array {name}: Python objects (dtype {dtype}), which are not loaded")
        header = ArrayHeader(tuple(int(n) for n in shape), dtype)
        if header.nbytes > MAX_ARRAY_BYTES:
            raise SmallFileError(f"array {name}: shape {header.shape} of {dtype}, {header.nbytes} bytes, "
                                 f"over {MAX_ARRAY_BYTES}")
        return header

    def array(self, name: str) -> np.ndarray:
        """The array ``name`` (one of :attr:`headers`), as its header said; :class:`SmallFileError` when its data
        does not read (a truncated or damaged member)."""
        try:
            with self._zip.open(f"{name}.npy") as member:
                return np.lib.format.read_array(member, allow_pickle=False)
        except (zipfile.BadZipFile, EOFError, OSError, ValueError, KeyError) as error:
            raise SmallFileError(f"array {name}: data that does not read ({type(error).__name__}: "
                                 f"{' '.join(str(error).split())[:120]})") from None

    def close(self) -> None:
        self._zip.close()
        self._handle.close()

    def __enter__(self) -> NpzArchive:
        return self

    def __exit__(self, *exc_info) -> None:
        self.close()


_END_OF_DIRECTORY = b"PK\x05\x06"


def _check_member_count(handle) -> None:
    """Refuse a zip whose central directory lists more than :data:`MAX_NPZ_MEMBERS` members, read from its end
    record before ``zipfile`` builds an object for each."""
    size = handle.seek(0, os.SEEK_END)
    tail_start = max(0, size - (1 << 16) - 22)  # the end record, after a comment of at most 64 KiB
    handle.seek(tail_start)
    tail = handle.read()
    at = tail.rfind(_END_OF_DIRECTORY)
    if at < 0 or len(tail) - at < 22:
        raise SmallFileError("not a zip archive (no end of central directory)")
    entries, directory_bytes = struct.unpack("<HI", tail[at + 10:at + 16])
    if entries == 0xFFFF or directory_bytes == 0xFFFFFFFF:
        raise SmallFileError("a zip64 archive, larger than a match log can be")
    if entries > MAX_NPZ_MEMBERS:
        raise SmallFileError(f"{entries} arrays, more than {MAX_NPZ_MEMBERS}")
    handle.seek(0)
