"""CITATION.cff and LICENSE are present and say what the README says.

CITATION.cff is checked against the required keys of the Citation File Format
1.2.0 and the values this repository and its paper must have. (The reference
validator, ``cffconvert --validate``, is not a test dependency: cffconvert 2.0
needs jsonschema 3.2, older than what Jupyter Book uses. Run it by hand in a
separate virtualenv: ``pip install cffconvert && cffconvert --validate``.)
"""

from __future__ import annotations

import datetime
import re
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[1]
CFF = ROOT / "CITATION.cff"

# Keys the CFF 1.2.0 schema requires, at the top level and in a reference.
REQUIRED_TOP = {"cff-version", "message", "title", "authors"}
REQUIRED_REFERENCE = {"type", "title", "authors"}
DOI = "10.1063/5.0160496"
ARXIV = "2303.01057"


@pytest.fixture(scope="module")
def cff() -> dict:
    assert CFF.is_file(), "CITATION.cff missing"
    # CFF is YAML 1.2; PyYAML reads 2026-11-23 as a date, 1.0.0 as a string.
    data = yaml.safe_load(CFF.read_text(encoding="utf-8"))
    assert isinstance(data, dict), "CITATION.cff is not a YAML mapping"
    return data


def _check_authors(authors, where: str) -> list[str]:
    problems = []
    if not isinstance(authors, list) or not authors:
        return [f"{where}: authors must be a non-empty list"]
    for a in authors:
        # A person has family-names (given-names optional); an entity has a name.
        if not isinstance(a, dict) or not (a.get("family-names") or a.get("name")):
            problems.append(f"{where}: author {a!r} has neither family-names nor name")
    return problems


def test_citation_cff_required_keys(cff):
    problems = [f"missing top-level key {k!r}" for k in sorted(REQUIRED_TOP - set(cff))]
    if cff.get("cff-version") != "1.2.0":
        problems.append(f"cff-version is {cff.get('cff-version')!r}, not '1.2.0'")
    problems += _check_authors(cff.get("authors"), "top level")
    ref = cff.get("preferred-citation")
    if not isinstance(ref, dict):
        problems.append("no preferred-citation mapping (the paper)")
    else:
        missing = REQUIRED_REFERENCE - set(ref)
        problems += [f"preferred-citation: missing key {k!r}" for k in sorted(missing)]
        problems += _check_authors(ref.get("authors"), "preferred-citation")
    assert not problems, "CITATION.cff:\n  " + "\n  ".join(problems)


def test_citation_cff_describes_this_repository(cff):
    assert cff["title"] == "The 3-rotor bifurcation cascade, re-derived"
    assert cff["authors"] == [{"name": "rotorlib contributors"}]
    assert cff["repository-code"] == "https://github.com/rotorlib/rotor-cascade"
    assert cff["license"] == "MIT"
    assert re.fullmatch(r"\d+\.\d+\.\d+", str(cff["version"])), (
        f"version {cff['version']!r} is not MAJOR.MINOR.PATCH (semantic versioning)"
    )
    assert isinstance(cff["date-released"], datetime.date), (
        f"date-released must be an ISO date (YYYY-MM-DD), got {cff['date-released']!r}"
    )
    # The version agrees with the package's (set once, in rotorlib/__init__.py).
    init = (ROOT / "rotorlib" / "__init__.py").read_text(encoding="utf-8")
    version = re.search(r'^__version__\s*=\s*"([^"]+)"', init, re.M).group(1)
    assert str(cff["version"]) == version, (
        f"CITATION.cff version {cff['version']} != rotorlib.__version__ {version}"
    )


def test_citation_cff_cites_the_paper(cff):
    ref = cff["preferred-citation"]
    assert ref["type"] == "article"
    families = [a.get("family-names") for a in ref["authors"]]
    assert families == ["Krishnaswami", "Yadav"], families
    assert (ref["journal"], str(ref["volume"]), str(ref["issue"])) == (
        "Chaos",
        "33",
        "8",
    )
    assert str(ref["start"]) == "083101" and int(ref["year"]) == 2023
    assert ref["doi"] == DOI
    identifiers = {str(i.get("value")) for i in ref.get("identifiers", [])}
    assert any(ARXIV in v for v in identifiers | {str(ref.get("url", ""))}), (
        f"arXiv {ARXIV} is named neither in identifiers nor in url"
    )


def test_license_is_mit_and_readme_states_licences():
    license_text = (ROOT / "LICENSE").read_text(encoding="utf-8")
    assert license_text.startswith("MIT License"), "LICENSE is not the MIT licence text"
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    section = re.search(r"^## Licen[cs]e\n(.*?)(?=^## |\Z)", readme, re.M | re.S)
    assert section, "README.md has no '## Licence' section"
    assert "CC-BY-4.0" in section.group(1) or "CC BY 4.0" in section.group(1)
    assert "LICENSE" in section.group(1)


def test_version_says_what_it_promises():
    """From 1.0.0 on the README states what the major version keeps stable."""
    init = (ROOT / "rotorlib" / "__init__.py").read_text(encoding="utf-8")
    version = re.search(r'^__version__\s*=\s*"([^"]+)"', init, re.M).group(1)
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    section = re.search(r"^### Versions\n(.*?)(?=^##)", readme, re.M | re.S)
    if int(version.split(".")[0]) >= 1:
        assert section, "README.md has no '### Versions' section (what 1.x promises)"
        for name in ("rotorlib.orbit", "rotorlib.census", "to_dict()", "semantic"):
            assert name in section.group(1), f"'### Versions' does not name {name}"
