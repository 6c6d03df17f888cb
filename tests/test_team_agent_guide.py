"""docs/team_agent.md: every ```python block on the page runs as shown, alone, in well under a second."""

from __future__ import annotations

import re
import sys
import time
import types
from pathlib import Path

import pytest

from agents import radio
from agents.team.behavior.roles import registry

GUIDE = Path(__file__).resolve().parents[1] / "docs" / "team_agent.md"
BLOCK = re.compile(r"^```python\n(.*?)^```$", re.DOTALL | re.MULTILINE)
BLOCKS = BLOCK.findall(GUIDE.read_text(encoding="utf-8"))
MAX_SECONDS = 1.0


def test_the_guide_has_its_snippets() -> None:
    assert len(BLOCKS) >= 5


@pytest.fixture
def registries():
    """The role registry and the radio's role codes as they were: a snippet that adds a role leaves them so."""
    roles, codes, names = dict(registry.REGISTRY), dict(radio.ROLE_CODES), dict(radio._ROLE_NAMES)
    yield
    for live, saved in ((registry.REGISTRY, roles), (radio.ROLE_CODES, codes), (radio._ROLE_NAMES, names)):
        live.clear()
        live.update(saved)


def run_as_module(code, name: str) -> None:
    """Run ``code`` as the module ``name`` (dataclasses look their module up while it runs)."""
    module = types.ModuleType(name)
    sys.modules[name] = module
    try:
        exec(code, module.__dict__)
    finally:
        del sys.modules[name]


@pytest.mark.parametrize("index", range(len(BLOCKS)), ids=lambda i: f"block{i + 1}")
def test_a_snippet_runs(index: int, registries, capsys) -> None:
    name = f"team_agent_guide_block_{index + 1}"
    code = compile(BLOCKS[index], f"{GUIDE.name}, python block {index + 1}", "exec")
    run_as_module(code, name)  # once to warm up: a module's first import is not the snippet's time
    started = time.perf_counter()
    run_as_module(code, name)
    assert time.perf_counter() - started < MAX_SECONDS
