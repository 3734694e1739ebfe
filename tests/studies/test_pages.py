"""The study pages' prose is data: templates shipped in the package, each a well-formed
``string.Template``, every snippet the code asks for present, no field left blank silently."""

from __future__ import annotations

import re
import string
from importlib import resources
from pathlib import Path

import pytest

from deck_emulator.studies import pages

STUDIES = Path(pages.__file__).parent
TEMPLATES = sorted(p.name for p in resources.files("deck_emulator.studies")
                   .joinpath("templates").iterdir() if p.name.endswith(".md"))


def test_the_pages_templates_are_package_data():
    assert {"error_study.md", "error_tolerance.md", "stability_study.md",
            "stability_findings.md", "sensitivity_header.md"} <= set(TEMPLATES)


@pytest.mark.parametrize("name", TEMPLATES)
def test_every_placeholder_is_well_formed(name):
    assert string.Template(pages._text(name)).is_valid()


@pytest.mark.parametrize("module, template, call", [
    ("error.py", "error_tolerance.md", r'snippet\(\s*"error_tolerance\.md",\s*"(\w+)"'),
    ("stability.py", "stability_findings.md", r'_finding\(\s*"(\w+)"'),
])
def test_every_snippet_the_code_asks_for_is_there(module, template, call):
    asked = set(re.findall(call, (STUDIES / module).read_text()))
    assert asked and asked <= set(pages.snippets(template))


def test_a_missing_field_is_an_error_not_a_blank():
    with pytest.raises(KeyError):
        pages.page("sensitivity_header.md", blind="")
