"""A griffe extension for the API reference: docstrings written with Sphinx roles read as Markdown.

The docstrings cite code as ``:func:`name``` and end a paragraph before a literal block with
``::``. Markdown has neither, so each role becomes a plain code span (``name``; ``~a.b.c``
gives ``c``) and a closing ``::`` becomes ``:`` (the indented block after it is already a code
block). Only the rendered text changes: the source keeps its docstrings.
"""

from __future__ import annotations

import re

import griffe

ROLE = re.compile(r":(?:py:)?(?:func|class|meth|mod|data|attr|exc|obj|const|ref):`(~?)([^`]+)`")
LITERAL_BLOCK = re.compile(r"::$", re.MULTILINE)


def markdown_of(text: str) -> str:
    """The docstring ``text`` with its Sphinx roles as code spans and its ``::`` as ``:``."""
    text = ROLE.sub(lambda m: f"`{m.group(2).rsplit('.', 1)[-1] if m.group(1) else m.group(2)}`", text)
    return LITERAL_BLOCK.sub(":", text)


class SphinxRoles(griffe.Extension):
    """Rewrites every object's docstring with :func:`markdown_of` as griffe loads it."""

    def on_instance(self, *, obj: griffe.Object, **kwargs: object) -> None:
        if obj.docstring is not None:
            obj.docstring.value = markdown_of(obj.docstring.value)
