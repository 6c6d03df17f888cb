"""The replay page in a real headless browser: Debian's chromium driven by Playwright.

The browser is the system's (``/usr/bin/chromium``, or ``$ROBOTSTADIUM_CHROMIUM``; ``.ci/run``
installs it); Playwright's own browser download is never used. Without a browser or without
the ``playwright`` package (the ``browser`` extra) these tests are skipped, with the reason.

``ROBOTSTADIUM_SCREENSHOT=PATH`` saves the screenshot of the real match's page to PATH
(``docs/replay.png`` was made so).
"""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

import pytest

from scenarios import cli
from scenarios.replay import write_replay
from scenarios.replay.data import COLORS
from scenarios.replay.synthetic import Fall, Goal, synthetic_match
from tests import chromium

VIEWPORT = {"width": 1000, "height": 700}

PIXELS = """(colors) => {
  const c = document.getElementById("field");
  const d = c.getContext("2d").getImageData(0, 0, c.width, c.height).data;
  const near = colors.map(() => 0);
  const seen = new Set();
  let green = 0, white = 0;
  for (let i = 0; i < d.length; i += 4) {
    const r = d[i], g = d[i + 1], b = d[i + 2];
    if (g > r + 30 && g > b + 30) green++;
    if (r > 235 && g > 235 && b > 235) white++;
    if (i % 64 === 0) seen.add((r << 16) | (g << 8) | b);
    colors.forEach((k, j) => { if (Math.abs(r - k[0]) + Math.abs(g - k[1]) + Math.abs(b - k[2]) < 30) near[j]++; });
  }
  const n = d.length / 4;
  return {width: c.width, height: c.height, green: green / n, white: white / n, distinct: seen.size, near: near};
}"""


CHANGED = """(keep) => {
  const c = document.getElementById("field");
  const d = c.getContext("2d").getImageData(0, 0, c.width, c.height).data;
  let changed = 0;
  const kept = window.__kept;
  if (kept) {
    for (let i = 0; i < d.length; i += 4) if (d[i] !== kept[i] || d[i + 1] !== kept[i + 1] || d[i + 2] !== kept[i + 2]) changed++;
  }
  if (keep) window.__kept = d;
  return changed;
}"""


def _rgb(hex_color: str) -> list[int]:
    return [int(hex_color[i:i + 2], 16) for i in (1, 3, 5)]


@pytest.fixture(scope="module")
def browser():
    yield from chromium.launched()


class Page:
    """One page of the browser, opened on a replay file, with its console errors collected."""

    def __init__(self, browser, path: Path):
        self.page = browser.new_page(viewport=VIEWPORT)
        self.errors: list[str] = []
        self.page.on("console", lambda m: self.errors.append(m.text) if m.type == "error" else None)
        self.page.on("pageerror", lambda e: self.errors.append(str(e)))
        self.page.on("request", lambda r: None if r.url.startswith(("file:", "data:", "about:")) else
                     self.errors.append(f"network request: {r.url}"))
        self.page.goto(path.resolve().as_uri())
        self.page.wait_for_function("window.replay && window.replay.ready")

    def js(self, code: str, arg=None):
        return self.page.evaluate(code, arg) if arg is not None else self.page.evaluate(code)

    def pixels(self, *colors: str) -> dict:
        return self.js(PIXELS, [_rgb(c) for c in colors])

    def keep(self) -> None:
        """Remember the canvas as it is now, for :meth:`changed`."""
        self.js(CHANGED, True)

    def changed(self) -> int:
        """Pixels of the canvas that differ from the kept one."""
        return self.js(CHANGED, False)

    def text(self, selector: str) -> str:
        return self.page.inner_text(selector).strip()

    def stats(self) -> dict:
        return self.js("window.replay.stats")

    def close(self) -> None:
        self.page.close()


@pytest.fixture(scope="module")
def synthetic_page(tmp_path_factory: pytest.TempPathFactory) -> Path:
    directory = synthetic_match(tmp_path_factory.mktemp("browser"), half_seconds=30.0,
                                goals=(Goal(1, 10.0, "home"), Goal(2, 12.0, "away")), falls=(Fall("away_1", 1, 4.0),))
    return write_replay(directory)[0]


@pytest.fixture
def page(browser, synthetic_page: Path):
    opened = Page(browser, synthetic_page)
    yield opened
    opened.close()


def test_the_page_loads_without_errors_and_draws_the_field(page: Page) -> None:
    drawn = page.pixels(COLORS["blue"], COLORS["red"], COLORS["ball"])
    assert page.errors == []
    assert drawn["width"] > 500 and 1.2 < drawn["width"] / drawn["height"] < 1.5  # 7.7 x 5.7 m drawn
    assert drawn["green"] > 0.5, drawn  # the carpet
    assert drawn["white"] > 0.02, drawn  # the lines
    assert drawn["distinct"] > 20, drawn
    blue, red, ball = drawn["near"]
    assert blue > 50 and red > 50 and ball > 5, drawn  # two robots of each team, and the ball
    assert page.stats()["robots"] == 4
    assert page.text("#score") == "0 - 0" and page.text("#state") == "INITIAL" and page.text("#clock") == "0:30"


def test_clicking_a_goal_mark_shows_the_score_after_it(page: Page) -> None:
    marks = page.page.locator(".mark.goal")
    assert marks.count() == 2
    marks.nth(0).click()
    assert page.text("#score") == "1 - 0"
    assert page.text("#state") == "READY" and page.text("#half") == "1st half" and page.text("#clock") == "0:20"
    goal_ms = int(marks.nth(0).get_attribute("data-t"))
    assert page.js("window.replay.time()") == goal_ms
    page.js(f"window.replay.seek({goal_ms - 40})")
    assert page.text("#score") == "0 - 0"
    marks.nth(1).click()
    assert page.text("#score") == "1 - 1" and page.text("#half") == "2nd half"
    # The teams swapped colours at half-time: home is red now.
    home_chip = page.js("getComputedStyle(document.querySelector('#team-home .chip')).backgroundColor")
    assert home_chip == "rgb({}, {}, {})".format(*_rgb(COLORS["red"]))
    page.page.locator("#events li[data-kind=goal]").nth(0).click()
    assert page.text("#score") == "1 - 0"
    assert page.errors == []


def test_toggling_estimates_draws_them(page: Page) -> None:
    page.js("window.replay.seek(40000)")  # estimates exist from 2 s on
    assert page.page.locator("input.toggle[data-channel=estimate]").count() == 2  # home robots only
    assert page.page.locator("#all-ball_estimate").count() == 0  # a hook: no data, no toggle
    page.keep()
    assert page.stats()["estimates"] == 0
    page.page.locator("#all-estimate").check()
    assert page.stats()["estimates"] == 2
    drawn = page.changed()
    assert drawn > 300, drawn  # two rings, headings and error lines
    page.keep()
    page.page.locator("input.toggle[data-robot=home_1][data-channel=estimate]").uncheck()
    assert page.stats()["estimates"] == 1
    assert 0.2 * drawn < page.changed() < 0.8 * drawn
    assert not page.page.locator("#all-estimate").is_checked()
    assert page.errors == []


def test_fallen_robots_are_shown(page: Page) -> None:
    page.page.locator(".mark.fall").first.click()
    assert page.stats()["fallen"] == 1
    assert page.page.locator("#toggles tr.fallen").get_attribute("data-robot") == "away_1"
    page.page.keyboard.press("Shift+ArrowRight")  # 5 s on: it lay 4 s, and is up again
    assert page.stats()["fallen"] == 0 and page.page.locator("#toggles tr.fallen").count() == 0


def test_playback_and_keys(page: Page) -> None:
    keyboard = page.page.keyboard
    frame = page.js("window.replay.frame()")
    keyboard.press("ArrowRight")
    assert page.js("window.replay.frame()") == frame + 1
    keyboard.press("ArrowLeft")
    assert page.js("window.replay.frame()") == frame
    keyboard.press("ArrowUp")
    keyboard.press("ArrowUp")
    assert page.js("window.replay.speed()") == 4
    assert page.page.locator("#speed").input_value() == "4"
    start = page.js("window.replay.time()")
    keyboard.press(" ")
    assert page.js("window.replay.playing()")
    page.page.wait_for_timeout(400)
    keyboard.press(" ")
    assert not page.js("window.replay.playing()")
    moved = page.js("window.replay.time()") - start
    assert 400 < moved < 4 * 1500, moved  # about 4x the wall time
    page.page.select_option("#speed", "16")
    assert page.js("window.replay.speed()") == 16
    page.page.click("#play")
    page.page.wait_for_timeout(200)
    page.page.click("#play")
    assert page.js("window.replay.time()") - start > moved
    keyboard.press("End")
    assert page.js("window.replay.time()") == page.js("window.replay.data.frames.t.at(-1)")
    assert page.text("#state") == "FINISHED"
    keyboard.press("Home")
    keyboard.press("]")
    first_mark = page.js("Math.min(...[...document.querySelectorAll('.mark')].map(m => +m.dataset.t))")
    assert page.js("window.replay.time()") == first_mark
    # A click on the timeline seeks there.
    box = page.page.locator("#timeline").bounding_box()
    page.page.mouse.click(box["x"] + box["width"] * 0.75, box["y"] + box["height"] - 3)
    share = (page.js("window.replay.time()") - page.js("window.replay.data.frames.t[0]")) / page.js(
        "window.replay.data.frames.t.at(-1) - window.replay.data.frames.t[0]")
    assert share == pytest.approx(0.75, abs=0.02)
    assert page.errors == []


def test_extras_appear_only_with_their_data(browser, tmp_path: Path) -> None:
    directory = synthetic_match(tmp_path / "extras", half_seconds=10.0, goals=(), extras=True)
    opened = Page(browser, write_replay(directory)[0])
    try:
        for channel in ("estimate", "ball_estimate", "team_ball", "role", "landmarks"):
            assert opened.page.locator(f"#all-{channel}").count() == 1, channel
        opened.js("window.replay.seek(25000)")
        for channel in ("ball_estimate", "team_ball", "role", "landmarks"):
            opened.keep()
            opened.page.locator(f"#all-{channel}").check()
            assert opened.changed() > 50, channel
        assert opened.stats()["extras"] == 2 + 2 + 4 + 4  # ball and team ball: the home robots; roles, landmarks: all
        assert opened.errors == []
    finally:
        opened.close()
    bare = synthetic_match(tmp_path / "bare", half_seconds=10.0, goals=(), estimators=())
    opened = Page(browser, write_replay(bare)[0])
    try:
        assert opened.page.locator("#toggles input").count() == 0
        assert opened.page.locator("#no-extras").is_visible()
        assert opened.errors == []
    finally:
        opened.close()


# ---- a real match ------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def real_match(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The default team agents, 1 v 1, 10 s halves (about 20 s here); 2 v 2 with 30 s halves when making the
    screenshot of the docs."""
    out = tmp_path_factory.mktemp("real-match")
    players, half_s = ("2", "30") if os.environ.get("ROBOTSTADIUM_SCREENSHOT") else ("1", "10")
    code = cli.main(["match", "--home-players", players, "--away-players", players, "--half-seconds", half_s,
                     "--no-shootout", "--no-progress", "--seed", "3", "--out", str(out)])
    assert code == 0
    return out


@pytest.mark.slow
@pytest.mark.render
def test_a_real_match_writes_its_replay(real_match: Path) -> None:
    names = {p.name for p in real_match.iterdir()}
    assert {"replay.html", "traces.png", "localization.png", "match_log.npz", "events.jsonl", "summary.json"} <= names
    assert (real_match / "replay.html").stat().st_size < 2_000_000


@pytest.mark.slow
@pytest.mark.render
def test_a_real_match_plays_in_the_browser(browser, real_match: Path, tmp_path: Path) -> None:
    opened = Page(browser, real_match / "replay.html")
    try:
        assert "team vs team" in opened.page.locator("#title").inner_text()  # who played, from the summary
        opened.page.locator("#settings-panel summary").click()  # the settings, from the summary too
        settings = opened.page.locator("#settings").inner_text()
        assert all(word in settings for word in ("home_0", "away_0", "team", "seed", "camera profile", "robotstadium",
                                                 "versions", "command"))
        opened.page.locator("#settings-panel summary").click()
        robots = len(opened.js("window.replay.data.robots.map(r => r.id)"))
        assert opened.page.locator("input.toggle[data-channel=estimate]").count() == robots  # team agents report
        opened.page.locator(".mark.kickoff").first.click()
        for _ in range(2):
            opened.page.keyboard.press("Shift+ArrowRight")
        opened.page.locator("#all-estimate").check()
        assert opened.stats()["estimates"] == robots
        goals = opened.page.locator(".mark.goal")
        if goals.count():  # the screenshot: just after the first goal, if there is one
            goals.first.click()
            opened.page.keyboard.press("ArrowRight")
        assert opened.stats()["robots"] == robots
        assert opened.pixels()["green"] > 0.5
        shot = tmp_path / "replay.png"
        opened.page.screenshot(path=str(shot))
        assert shot.stat().st_size > 10_000
        target = os.environ.get("ROBOTSTADIUM_SCREENSHOT")
        if target:
            Path(target).parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(shot, target)
        assert opened.errors == []
    finally:
        opened.close()


def test_forged_policy_names_and_settings_show_as_text_and_run_nothing(browser, tmp_path: Path) -> None:
    """A summary whose policy names, command line and machine hold markup and script: the header and the settings
    panel show that text as it is; no element of it is made and none of it runs."""
    directory = synthetic_match(tmp_path / "forged", half_seconds=10.0, goals=())
    summary_path = directory / "summary.json"
    summary = json.loads(summary_path.read_text(encoding="utf-8"))
    forged_policy = '<img src=x onerror="window.pwned = 1">'
    forged_command = '</script><script>window.pwned = 2</script>'
    summary["played_by"] = {"policies": {"home_0": {"policy": forged_policy}, "away_0": {"policy": "scripted"}},
                            "controllers": {"in_process": True}}
    summary["command_line"] = ["robotstadium", "match", forged_command]
    summary["machine"] = {"cpu": "<b onmouseover=alert(3)>x</b>"}
    summary_path.write_text(json.dumps(summary), encoding="utf-8")
    opened = Page(browser, write_replay(directory)[0])
    try:
        assert f"{forged_policy} vs scripted" in opened.page.locator("#title").inner_text()
        opened.page.locator("#settings-panel summary").click()
        settings = opened.page.locator("#settings").inner_text()
        assert forged_policy in settings and forged_command in settings and "<b onmouseover" in settings
        assert opened.page.locator("#title img, #settings img, #settings b, #settings script").count() == 0
        assert opened.js("typeof window.pwned") == "undefined"
        assert opened.errors == []
    finally:
        opened.close()
