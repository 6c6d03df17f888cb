"""The guide pages' Python: every ```python block of a page runs, in order, in one namespace.

A page's blocks build on each other (a tutorial's later blocks use the earlier ones' names), so
they run as one module, top to bottom. Only blocks fenced ```python run: a shell command is
fenced ```sh and a command's synopsis or output ```text. docs/team_agent.md has its own test
(tests/test_team_agent_guide.py), which runs each of its blocks alone.
"""

from __future__ import annotations

import re
import sys
import time
import types
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parents[1] / "docs"
BLOCK = re.compile(r"^```python\n(.*?)^```$", re.DOTALL | re.MULTILINE)
OWN_TEST = {"team_agent.md"}
MAX_SECONDS = 20.0  # a page's blocks together


def guide_pages() -> list[Path]:
    """Every page of the site outside the API reference, with at least one Python block."""
    pages = [p for p in sorted(DOCS.rglob("*.md")) if "api" not in p.relative_to(DOCS).parts]
    return [p for p in pages if p.name not in OWN_TEST and BLOCK.search(p.read_text(encoding="utf-8"))]


def test_the_tutorial_and_the_environment_have_snippets() -> None:
    names = {p.name for p in guide_pages()}
    assert {"policy-tutorial.md", "environment.md"} <= names


@pytest.mark.parametrize("page", guide_pages(), ids=lambda p: str(p.relative_to(DOCS)))
def test_the_blocks_of_a_page_run(page: Path, monkeypatch, tmp_path) -> None:
    monkeypatch.chdir(tmp_path)  # a block that writes files writes them here
    name = "docs_" + re.sub(r"\W", "_", str(page.relative_to(DOCS)))
    module = types.ModuleType(name)
    sys.modules[name] = module  # dataclasses and pickling look their module up while it runs
    started = time.perf_counter()
    try:
        for index, source in enumerate(BLOCK.findall(page.read_text(encoding="utf-8")), start=1):
            exec(compile(source, f"{page.name}, python block {index}", "exec"), module.__dict__)
    finally:
        del sys.modules[name]
    assert time.perf_counter() - started < MAX_SECONDS
