"""The replay page: one self-contained HTML file (inline CSS and JavaScript, the data as compact JSON).

It opens from disk with no network: no script, style sheet or font is fetched. The page's
template, style and player are the files of ``scenarios/replay/assets/``; the data is
:func:`scenarios.replay.data.replay_data`.
"""

from __future__ import annotations

import html
import json
from importlib import resources

ASSETS = "assets"


def _asset(name: str) -> str:
    return resources.files("scenarios.replay").joinpath(ASSETS, name).read_text(encoding="utf-8")


def _embed_json(data: dict) -> str:
    """Compact JSON safe inside a ``<script>`` element (no ``</`` and no ``<!--``)."""
    text = json.dumps(data, separators=(",", ":"), allow_nan=False)
    return text.replace("<", "\\u003c").replace("\u2028", "\\u2028").replace("\u2029", "\\u2029")


def render_page(data: dict) -> str:
    """The HTML text of the replay page for ``data``."""
    summary = data["match"]["summary"]
    title = f"robotstadium replay: {data['title']}"
    score = summary.get("score")
    if isinstance(score, dict):
        title += f", home {score.get('home')} - {score.get('away')} away"
    parts = {
        "__TITLE__": html.escape(title),
        "__CSS__": _asset("replay.css"),
        "__JS__": _asset("replay.js").replace("</script", "<\\/script"),
        "__DATA__": _embed_json(data),
    }
    page = _asset("replay.html")
    for key in ("__TITLE__", "__CSS__", "__JS__"):  # the data last: it could contain the other keys
        page = page.replace(key, parts[key])
    head, sep, tail = page.partition("__DATA__")
    return head + parts["__DATA__"] + tail
