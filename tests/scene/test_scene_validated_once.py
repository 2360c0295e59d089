"""``poissonkit run`` validates its scene file once (a 10⁵-body assembly is built and checked
by validation; the summary's provenance used to validate it a second time). Outside a run,
every call validates anew. Truth: a count of the calls to the validator."""

from __future__ import annotations

import json

import pytest

from poissonkit import cli
from poissonkit.scene import loader
from poissonkit.scene.loader import loads_scene, reuse_validated, shipped_scenes


@pytest.fixture
def counted(monkeypatch):
    calls = []
    inner = loader.scene_from_mapping

    def counting(data, source=""):
        calls.append(source)
        return inner(data, source=source)

    monkeypatch.setattr(loader, "scene_from_mapping", counting)
    return calls


def test_a_run_validates_its_scene_file_once(tmp_path, counted):
    scene = shipped_scenes()["two_magnets"]
    out = tmp_path / "out"
    code = cli.main(["run", str(scene), "--duration", "2e-6", "--step", "1e-6", "--out",
                     str(out), "--no-progress", "--no-plots"])
    assert code == 0
    assert counted == [str(scene)]
    # the provenance still holds the resolved scene
    summary = json.loads((out / "summary.json").read_text())
    assert summary["scene_source"]["resolved"]["name"] == "two_magnets"


def test_outside_a_run_each_load_validates(counted):
    text = shipped_scenes()["two_magnets"].read_text()
    first, second = loads_scene(text, "x"), loads_scene(text, "x")
    assert len(counted) == 2 and first == second
    with reuse_validated():
        third, fourth = loads_scene(text, "x"), loads_scene(text, "x")
    assert len(counted) == 3 and third is fourth
    loads_scene(text, "x")
    assert len(counted) == 4
