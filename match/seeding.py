"""Seeds of an env and of its copies: streams that keep vector envs' sub-envs apart.

Every env lies on a *stream*, a tuple of non-negative integers. A standalone env's stream is
``()``: ``reset(seed=s)`` plays match seed ``s``. A copy (pickle, deepcopy, a vector env's
sub-env) lies on its original's stream plus the copy's index (the n-th copy made of that
original gets ``n``), and ``reset(seed=s)`` on a stream ``k != ()`` plays the match seed
:func:`match_seed` draws from ``(s, k)``. Vector envs hand their sub-envs overlapping seeds
(SuperSuit's and RLlib's give sub-env ``j`` of worker ``i`` the seed ``s + i + j``); with
streams the pairs (seed, stream) still differ, so no two sub-envs play the same match, and the
same seed replays the same matches.

A reset without a seed continues the sequence of the last seed given
(:func:`continued_seeds`); a copy that was not seeded yet draws its sequence from the
operating system's entropy, as its action spaces do (:func:`fresh_space_seeds`).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from match.errors import MatchConfigError, shown

Stream = tuple[int, ...]
SEED_LIMIT = 2**64  # seeds are integers 0 .. 2**64 - 1
STREAM_PART_LIMIT = 2**32  # every part of a stream is an integer 0 .. 2**32 - 1
MAX_STREAM_LENGTH = 32  # copies of copies nest at most this deep
STREAM_SALT = 0x5354524D  # mixed into a stream's seeds: they never meet a standalone env's


def check_seed(seed: object) -> int:
    """``seed`` as an int in [0, 2**64); a :class:`MatchConfigError` naming it otherwise (bools, floats,
    negative numbers)."""
    if isinstance(seed, (bool, np.bool_)) or not isinstance(seed, (int, np.integer)) or not 0 <= seed < SEED_LIMIT:
        raise MatchConfigError(f"seed = {shown(seed)} is invalid; expected None or an integer 0 .. 2**64 - 1")
    return int(seed)


def check_stream(stream: object) -> Stream:
    """``stream`` as a tuple of ints in [0, 2**32), at most :data:`MAX_STREAM_LENGTH` long; a
    :class:`MatchConfigError` naming it otherwise."""
    parts = tuple(stream) if isinstance(stream, (tuple, list)) else None
    if (parts is None or len(parts) > MAX_STREAM_LENGTH
            or any(isinstance(p, (bool, np.bool_)) or not isinstance(p, (int, np.integer))
                   or not 0 <= p < STREAM_PART_LIMIT for p in parts)):
        raise MatchConfigError(f"stream = {shown(stream)} is invalid; expected a tuple of at most "
                               f"{MAX_STREAM_LENGTH} integers 0 .. 2**32 - 1")
    return tuple(int(p) for p in parts)


def seeded(seed: int, stream: Stream) -> tuple[int, np.random.SeedSequence]:
    """The match seed of ``reset(seed=seed)`` on ``stream``, and the sequence later unseeded resets continue."""
    if not stream:
        return seed, np.random.SeedSequence(seed)
    sequence = np.random.SeedSequence([seed, STREAM_SALT], spawn_key=stream)
    return match_seed(sequence), sequence


def continued_seeds(sequence: np.random.SeedSequence | None) -> tuple[int, np.random.SeedSequence]:
    """The match seed of a reset without a seed, and the sequence the next one continues: the next child of
    ``sequence`` (None: a new sequence from the operating system's entropy)."""
    child = (sequence or np.random.SeedSequence()).spawn(1)[0]
    return match_seed(child), child


def match_seed(sequence: np.random.SeedSequence) -> int:
    """The match seed a sequence stands for (an int 0 .. 2**32 - 1)."""
    return int(sequence.generate_state(1)[0])


def fresh_space_seeds(count: int) -> list[int]:
    """``count`` seeds for a copy's action spaces, from the operating system's entropy."""
    return [match_seed(child) for child in np.random.SeedSequence().spawn(count)]


def copy_stream(stream: Sequence[int], index: int) -> Stream:
    """The stream of the ``index``-th copy of an env on ``stream``."""
    return check_stream((*stream, index))
