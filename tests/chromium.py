"""The system's chromium for the browser tests, driven by Playwright.

The browser is ``/usr/bin/chromium`` (or ``$ROBOTSTADIUM_CHROMIUM``; ``.ci/run`` installs it);
Playwright's own browser download is never used. Without a browser or without the
``playwright`` package (the ``browser`` extra) a test that asks for one is skipped, with the reason.
"""

from __future__ import annotations

import os
import shutil
from collections.abc import Iterator
from pathlib import Path

import pytest


def executable() -> str | None:
    """The chromium to drive, or None when there is none."""
    for candidate in (os.environ.get("ROBOTSTADIUM_CHROMIUM"), "/usr/bin/chromium", shutil.which("chromium")):
        if candidate and Path(candidate).is_file() and os.access(candidate, os.X_OK):
            return candidate
    return None


def launched() -> Iterator:
    """A headless chromium for the length of a fixture (skips the test when there is none)."""
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        pytest.skip("playwright is not installed (pip install -e '.[browser]')")
    path = executable()
    if path is None:
        pytest.skip("no chromium at /usr/bin/chromium (apt-get install -y chromium; .ci/run installs it)")
    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=path)
        yield browser
        browser.close()
