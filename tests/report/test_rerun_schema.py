"""``run --from-summary`` reads a hand-edited summary against one schema
(``poissonkit.report.rerun_schema``): every wrong value is one line of typed error, nothing is
silently accepted, and the summary's scene copy is what runs.

Before, these edits raised ``TypeError``, ``IsADirectoryError``, ``ValueError`` or ``OSError``
tracebacks, or were accepted: an unknown option, ``no_contact = "no"`` read as true, a scene copy
whose sha256 did not match, ``scene_source.kind = "martian"`` running the shipped file."""

from __future__ import annotations

import copy
import json
import sys
from pathlib import Path

import pytest

from poissonkit import cli

ROOT = Path(__file__).resolve().parents[2]
TWO = ROOT / "poissonkit" / "scene" / "shipped" / "two_magnets.toml"
QUIET = ["--no-progress", "--no-plots"]


def _run(monkeypatch, *args: str) -> int:
    argv = ["poissonkit", "run", *args]
    monkeypatch.setattr(sys, "argv", argv)
    return cli.main(argv[1:])


@pytest.fixture(scope="module")
def summary(tmp_path_factory) -> dict:
    out = tmp_path_factory.mktemp("base") / "out"
    assert cli.main(["run", str(TWO), "--duration", "0.0002", "--step", "1e-5", "--out",
                     str(out), *QUIET]) == 0
    return json.loads((out / "summary.json").read_text())


def _set(path: str, value: object):
    def edit(doc: dict) -> None:
        *head, last = path.split(".")
        for key in head:
            doc = doc[key]
        doc[last] = value
    return edit


def _drop(path: str):
    def edit(doc: dict) -> None:
        *head, last = path.split(".")
        for key in head:
            doc = doc[key]
        del doc[last]
    return edit


EDITS = {
    "step-text": _set("options.step", "abc"),
    "save_every-text": _set("options.save_every", "10"),
    "save_every-float": _set("options.save_every", 2.5),
    "step-dict": _set("options.step", {"a": 1}),
    "duration-list": _set("options.duration", [1]),
    "method-number": _set("options.method", 5),
    "tilt-bool": _set("options.tilt", True),
    "step-nan-text": _set("options.step", "NaN"),
    "param-dict": _set("options.param", {"a": "b"}),
    "scene-name-int": _set("scene_source.name", 5),
    "scene-name-dotdot": _set("scene_source.name", ".."),
    "scene-name-300": _set("scene_source.name", "a" * 300 + ".toml"),
    "scene-name-nul": _set("scene_source.name", "a\x00b.toml"),
    "scene-name-folder": _set("scene_source.name", "../../evil.toml"),
    "unknown-option": _set("options.warp_speed", 9),
    "no_contact-no": _set("options.no_contact", "no"),
    "sha256-mismatch": _set("scene_source.text", "# edited\n"),
    "sha256-missing": _drop("scene_source.sha256"),
    "kind-martian": _set("scene_source.kind", "martian"),
    "options-list": _set("options", []),
    "scene_source-text-number": _set("scene_source.text", 7),
}


@pytest.mark.parametrize("edit", list(EDITS))
def test_an_edited_summary_is_refused_in_one_line(summary, tmp_path, monkeypatch, capsys, edit):
    doc = copy.deepcopy(summary)
    EDITS[edit](doc)
    path = tmp_path / "summary.json"
    path.write_text(json.dumps(doc))
    capsys.readouterr()
    assert _run(monkeypatch, "--from-summary", str(path), "--out", str(tmp_path / "o"),
                *QUIET) == 1
    err = capsys.readouterr().err
    assert err.startswith("poissonkit run: error: --from-summary") and err.count("\n") == 1, err
    assert not (tmp_path / "o").exists()  # refused before the output folder is touched


def test_the_unedited_summary_runs_again(summary, tmp_path, monkeypatch):
    path = tmp_path / "summary.json"
    path.write_text(json.dumps(summary))
    assert _run(monkeypatch, "--from-summary", str(path), "--out", str(tmp_path / "o"),
                *QUIET) == 0


def test_the_schema_follows_the_parser():
    from poissonkit.commands.run import _option_schema

    schema = _option_schema()
    assert schema["step"].kind == "float" and schema["save_every"].kind == "int"
    assert schema["no_contact"].kind == "bool" and not schema["no_contact"].nullable
    assert schema["param"].kind == "strlist" and schema["scene"].kind == "str"
