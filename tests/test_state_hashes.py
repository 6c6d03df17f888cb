"""The same seeded match on any machine: each step's hash of the world's state against a recorded run.

The fixture was written by::

    robotstadium match --home scripted --away scripted --half-seconds 15 --seed 0 --no-shootout \\
        --no-replay --in-process --state-hashes --out DIR

(DIR/state_hashes.txt), with the default camera profile (``robotstadium``: the scripted players see
through it, so its noise and blur are part of what is checked). A change that alters what the simulator or the scripted policy does changes it too:
write it again with that command, and say why in the commit.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from match.runner import STATE_HASHES
from scenarios.matches.play import Lineup, run_lineup_match

pytestmark = pytest.mark.render

FIXTURE = Path(__file__).parent / "fixtures" / "state_hashes_scripted_seed0.txt"


def test_a_seeded_match_steps_through_the_recorded_states(tmp_path: Path) -> None:
    run_lineup_match(tmp_path, Lineup("scripted", "scripted"), half_seconds=15.0, seed=0, shootout=False,
                     progress=False, state_hashes=True)
    played = (tmp_path / STATE_HASHES).read_text(encoding="ascii").splitlines()
    recorded = FIXTURE.read_text(encoding="ascii").splitlines()
    first = next((i for i, (a, b) in enumerate(zip(played, recorded)) if a != b), None)
    assert first is None, f"the world first differs before step {played[first].split()[0]} (see {FIXTURE.name})"
    assert len(played) == len(recorded)


def test_state_hashes_need_an_output_directory() -> None:
    with pytest.raises(ValueError, match="output directory"):
        run_lineup_match(None, Lineup("stand", "stand"), home=1, away=1, half_seconds=1.0, max_steps=1,
                         progress=False, state_hashes=True)
