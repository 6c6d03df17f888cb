"""The documentation site: mkdocs builds it strictly, and a headless chromium reads and searches it.

The site is built once, with ``mkdocs build --strict`` into a temporary directory, as
``make docs`` builds it into ``out/docs``: a warning (a broken link or anchor, a reference the
API reference cannot resolve, a docstring it cannot parse) fails the build. Without mkdocs (the
``docs`` extra) these tests are skipped, with the reason; the browser tests also need the
system's chromium (``tests/chromium.py``). The built pages are served over loopback HTTP: the
search runs in a web worker, which browsers do not start from ``file:`` pages.
"""

from __future__ import annotations

import functools
import http.server
import importlib.util
import json
import os
import subprocess
import sys
import threading
from pathlib import Path

import pytest

from tests import chromium

REPO = Path(__file__).resolve().parents[1]
BUILD_SECONDS = 120


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, str]:
    """The built site's directory and what the build printed."""
    if importlib.util.find_spec("mkdocs") is None:
        pytest.skip("mkdocs is not installed (pip install -e '.[docs]')")
    out = tmp_path_factory.mktemp("site")
    result = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(out)],
        cwd=REPO, env={**os.environ, "NO_MKDOCS_2_WARNING": "1"},
        capture_output=True, text=True, timeout=BUILD_SECONDS,
    )
    assert result.returncode == 0, result.stderr[-3000:]
    return out, result.stdout + result.stderr


def test_the_site_builds_strict_without_a_warning(site) -> None:
    directory, printed = site
    assert "WARNING" not in printed, printed
    assert (directory / "index.html").is_file()
    assert (directory / "policy-tutorial.html").is_file()


def test_the_search_index_holds_the_guide_and_the_api(site) -> None:
    index = json.loads((site[0] / "search" / "search_index.json").read_text(encoding="utf-8"))
    locations = {doc["location"].partition("#")[0] for doc in index["docs"]}
    assert {"index.html", "policy-tutorial.html", "environment.html", "results.html", "design/index.html"} <= locations
    text = " ".join(doc["text"] for doc in index["docs"])
    for name in ("RobotStadiumEnv", "make_action", "policy_factory", "ImageObservations", "VisionPipeline", "SelfLocator"):
        assert name in text, name


def test_the_api_reference_renders_the_docstrings(site) -> None:
    page = (site[0] / "api" / "protocol.html").read_text(encoding="utf-8")
    assert "StepRefusedError" in page and "make_action" in page
    assert ":func:" not in page and ":class:" not in page  # Sphinx roles read as code (docs_tools/sphinx_roles.py)


class Handler(http.server.SimpleHTTPRequestHandler):
    def log_message(self, format: str, *args) -> None:  # noqa: A002 - the base class's name
        pass


@pytest.fixture(scope="module")
def served(site):
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(Handler, directory=str(site[0])))
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    yield f"http://127.0.0.1:{server.server_address[1]}"
    server.shutdown()
    server.server_close()


@pytest.fixture(scope="module")
def browser():
    yield from chromium.launched()


@pytest.fixture
def page(browser, served):
    """A browser page with its console errors collected in ``page.errors``."""
    opened = browser.new_page(viewport={"width": 1200, "height": 800})
    opened.errors = []
    opened.on("console", lambda m: opened.errors.append(m.text) if m.type == "error" else None)
    opened.on("pageerror", lambda e: opened.errors.append(str(e)))
    opened.base = served
    yield opened
    opened.close()


@pytest.mark.parametrize(("path", "heading"), [("index.html", "robotstadium"),
                                                ("policy-tutorial.html", "Writing a policy")])
def test_a_page_opens_with_its_heading_and_no_console_error(page, path: str, heading: str) -> None:
    page.goto(f"{page.base}/{path}")
    assert page.inner_text("article h1").strip().removesuffix("¶") == heading  # ¶: the permalink
    assert page.locator("article h2").count() >= 2
    assert page.errors == []


def test_the_search_box_finds_the_tutorial(page) -> None:
    from playwright.sync_api import TimeoutError as PlaywrightTimeout  # the browser extra, there when page is

    page.goto(f"{page.base}/index.html")
    page.click("input.md-search__input")  # in the header at this width
    page.keyboard.type("SelfLocator")
    # The list is redrawn after each key; wait for the results of the whole word.
    results = page.locator(".md-search-result__list", has_text="Writing a policy")
    try:
        results.wait_for(timeout=15_000)
    except PlaywrightTimeout:
        pass  # the assertion below shows what was found instead
    found = page.inner_text(".md-search-result__list")
    assert "SelfLocator" in found and "Writing a policy" in found, found[:500]
    assert page.errors == []
