"""The same seeded match on any machine: each step's hash of the world's state against a recorded run.

The fixture was written by::

    robotstadium match --home scripted --away scripted --half-seconds 15 --seed 0 --no-shootout \\
        --no-replay --in-process --state-hashes --out DIR

(DIR/state_hashes.txt), with the default camera profile (``robotstadium``: the scripted players see
through it, so its noise and blur are part of what is checked). A change that alters what the simulator or the scripted policy does changes it too:
write it again with that command, and say why in the commit.
"""

from __future__ import annotations

import os
import platform
import subprocess
import sys
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


WITHOUT_AVX512 = "glibc.cpu.hwcaps=-AVX512F,-AVX512DQ,-AVX512BW,-AVX512VL,-AVX512CD"
"""The C library's settings of a processor without AVX-512: its maths and memory functions take the
variants such a processor runs (numpy's kernels are capped and its BLAS's pinned by ``world`` alike)."""


@pytest.mark.skipif(not (sys.platform.startswith("linux") and platform.machine() == "x86_64"),
                    reason="the C library's processor variants are chosen on x86-64 Linux")
def test_the_c_librarys_variants_for_a_processor_without_avx512_step_through_the_same_states(tmp_path: Path) -> None:
    command = [sys.executable, "-m", "scenarios.cli", "match", "--home", "scripted", "--away", "scripted",
               "--half-seconds", "15", "--seed", "0",
               "--no-shootout", "--no-replay", "--in-process", "--state-hashes", "--out", str(tmp_path / "run")]
    environment = {**os.environ, "GLIBC_TUNABLES": WITHOUT_AVX512}
    subprocess.run(command, env=environment, check=True, capture_output=True, timeout=600,
                   cwd=Path(__file__).parent.parent)
    played = (tmp_path / "run" / STATE_HASHES).read_text(encoding="ascii")
    assert played == FIXTURE.read_text(encoding="ascii")


def test_state_hashes_need_an_output_directory() -> None:
    with pytest.raises(ValueError, match="output directory"):
        run_lineup_match(None, Lineup("stand", "stand"), home=1, away=1, half_seconds=1.0, max_steps=1,
                         progress=False, state_hashes=True)
