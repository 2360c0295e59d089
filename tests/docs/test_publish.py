"""What a published package needs: a license that matches the metadata, and citation metadata
that is valid Citation File Format 1.2.0 and names the papers the models come from.

Truth for the CFF check: the format's own JSON schema (``cff_schema_1_2_0.json``, version 1.2.0
of the schema published by the Citation File Format project under CC-BY-4.0, as shipped in the
``cffconvert`` package).
"""

from __future__ import annotations

import json
import tomllib
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[2]
PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]


def _citation() -> dict:
    return yaml.safe_load((ROOT / "CITATION.cff").read_text(encoding="utf-8"))


def test_license_file_is_the_license_pyproject_declares():
    text = (ROOT / "LICENSE").read_text(encoding="utf-8")
    assert PYPROJECT["license"] == {"text": "MIT"}
    assert text.startswith("MIT License")
    assert "Copyright (c) 2026 the poissonkit developers" in text
    assert "THE SOFTWARE IS PROVIDED \"AS IS\"" in text


def test_citation_matches_the_package_metadata():
    cff = _citation()
    assert cff["cff-version"] == "1.2.0"
    assert cff["version"] == PYPROJECT["version"]
    assert cff["license"] == PYPROJECT["license"]["text"]
    assert cff["authors"] == [{"name": "poissonkit developers"}]
    assert cff["title"].startswith(PYPROJECT["name"])


def test_citation_names_the_two_source_papers():
    refs = {r["title"]: r for r in _citation()["references"]}
    zub = refs["Mathematical model of magnetically interacting rigid bodies"]
    assert zub["authors"][0]["family-names"] == "Zub"
    bmt = refs["Non-holonomic dynamics and Poisson geometry"]
    assert [a["family-names"] for a in bmt["authors"]] == ["Borisov", "Mamaev", "Tsiganov"]
    assert (bmt["year"], bmt["volume"], bmt["start"]) == (2014, 69, 481)
    assert bmt["doi"] == "10.1070/RM2014v069n03ABEH004899"


def test_citation_is_valid_cff_1_2_0():
    jsonschema = pytest.importorskip("jsonschema")
    schema = json.loads((Path(__file__).parent / "cff_schema_1_2_0.json").read_text("utf-8"))
    validator = jsonschema.Draft7Validator(schema, format_checker=jsonschema.FormatChecker())
    errors = sorted(validator.iter_errors(_citation()), key=lambda e: list(e.path))
    assert not errors, "\n".join(f"{list(e.path)}: {e.message}" for e in errors)
    broken = {**_citation(), "version": None, "authors": []}  # the check can fail
    assert list(validator.iter_errors(broken))
