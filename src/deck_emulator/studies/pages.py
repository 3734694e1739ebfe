"""The study pages' prose, kept as data: markdown templates shipped in ``templates/``.

A page's fixed text lives in a template and its numbers and tables are ``$fields``
(:class:`string.Template`), so the wording can be read and changed without reading code, and
nothing a template holds is ever run.  A file of snippets holds several short templates, each
after a line ``<!-- name -->``.
"""

from __future__ import annotations

import functools
import re
import string
from importlib import resources

_SNIPPET = re.compile(r"^<!-- (\w+) -->\n", re.MULTILINE)


@functools.cache
def _text(name: str) -> str:
    return resources.files(__package__).joinpath("templates", name).read_text(encoding="utf-8")


def page(name: str, **fields) -> str:
    """The template ``templates/NAME`` with ``fields`` put in."""
    return string.Template(_text(name)).substitute(fields)


@functools.cache
def snippets(name: str) -> dict[str, string.Template]:
    """The snippets of ``templates/NAME`` by name, each without its last newlines."""
    parts = _SNIPPET.split(_text(name))[1:]
    return {key: string.Template(body.rstrip("\n"))
            for key, body in zip(parts[::2], parts[1::2])}


def snippet(name: str, key: str, **fields) -> str:
    """The snippet ``key`` of ``templates/NAME`` with ``fields`` put in."""
    return snippets(name)[key].substitute(fields)
