"""What a match record says of who played and how: enough to tell two matches apart and to play one again.

Per robot, the policy as it was named (a built-in name, ``package.module:ClassName``, or a
built-in with a parameter file ``team:FILE.toml``) and, where the name leads to a file, that
file's path and content hash (the parameter file of ``team:FILE.toml``; the module's source of
a user's policy): a rerun can then tell whether the same code and parameters would play.
"""

from __future__ import annotations

import hashlib
import importlib.util
import sys
from collections.abc import Mapping
from dataclasses import asdict
from pathlib import Path

from agents.policies import PARAMETER_SUFFIX
from match.controllers import ControllerLimits

HASH_BYTES = 16  # blake2b digest size of a file's content hash


def file_hash(path: Path) -> str | None:
    """The blake2b hash (hex) of a file's content, None if it cannot be read."""
    try:
        return hashlib.blake2b(Path(path).read_bytes(), digest_size=HASH_BYTES).hexdigest()
    except OSError:
        return None


def policy_record(name: str) -> dict:
    """A policy name as given, and the file it leads to with its hash (``file``, ``file_hash``; absent for a
    built-in name, whose code is the package's, recorded by its version)."""
    record: dict = {"policy": name}
    base, _, rest = name.partition(":")
    if not rest:
        return record
    if rest.endswith(PARAMETER_SUFFIX):  # a built-in with a parameter file
        path = Path(rest)
    else:  # package.module:ClassName
        spec = importlib.util.find_spec(base) if base not in sys.modules else sys.modules[base].__spec__
        origin = getattr(spec, "origin", None)
        if origin is None or not Path(origin).is_file():
            return record
        path = Path(origin)
    record.update(file=str(path.resolve()), file_hash=file_hash(path))
    return record


def controllers_record(limits: ControllerLimits | None) -> dict:
    """Where the policies ran: in the simulator's process, or in controller processes held to these limits."""
    if limits is None:
        return {"in_process": True}
    return {"in_process": False, **asdict(limits)}


def lineup_record(policy_names: Mapping[str, str], limits: ControllerLimits | None) -> dict:
    """The ``played_by`` part of a match's summary: every robot's policy and the controllers' settings."""
    return {"policies": {agent: policy_record(name) for agent, name in policy_names.items()},
            "controllers": controllers_record(limits)}
