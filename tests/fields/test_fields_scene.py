"""[[fields]] in scene files: validated on load, run by `poissonkit run`, and the same system
as the one built from Python."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scene_texts import CYLINDER_PARAMS, run_scene, top_scene  # type: ignore[import-not-found]

import poissonkit as pk
from poissonkit.errors import SceneError
from poissonkit.scene.loader import loads_scene

ROOT = Path(__file__).resolve().parents[2]

SCENE = top_scene(
    "top_over_cylinder",
    f'source = "magpylib"\nclass = "Cylinder"\n{CYLINDER_PARAMS}\nposition = [0.0, 0.0, 0.0]\n'
    'orientation = [0.0, 0.0, 0.0]\nmode = "table"\ntol = 1e-4\n'
    "region = [-0.01, -0.01, 0.025, 0.01, 0.01, 0.045]",
    r="[0.001, 0.0005, 0.035]", p="[0.0004, 0.0, 0.0]", nu="[0.05, 0.0, -1.0]",
    run='method = "splitting6"\nstep = 2e-4\nduration = 0.04')


def test_a_scene_with_fields_runs_through_the_cli(tmp_path):
    _, summary = run_scene(tmp_path, SCENE)
    assert summary["max_rel_energy_error"] < 1e-12
    fields = summary["parameters"]["fields"]
    assert [f["source"] for f in fields] == ["magpylib", "gravity"]
    assert fields[0]["gradient_error"] <= 1e-4 and fields[0]["class"] == "Cylinder"


def test_the_scene_builds_the_system_python_builds(tabulated_cylinder):
    spec = pk.build_run(loads_scene(SCENE))
    system = spec.system
    assert [f.name for f in system.fields] == ["magpylib", "gravity"]
    assert np.array_equal(system.fields[0].data, tabulated_cylinder.data)
    from poissonkit.numerics.nbody import Body, NBodySystem

    direct = NBodySystem([Body("top", 0.02, alpha=1 / 2e-6, attributes={"moment": 0.1})],
                         fields=[tabulated_cylinder, pk.field("gravity", g=(0, 0, -9.81))])
    y = direct.pack([[0.001, 0.0005, 0.035]], [[0.0004, 0, 0]], [[0.05, 0, -1.0]],
                    [[0, 0, -2e-4]], normalize=True)
    L = system.scales.length if system.scales else 1.0
    si = system.unpack(spec.y0, si=True)
    assert si["r"][0] == pytest.approx(y[:3], abs=1e-15 * L)
    E = system.scales.energy if system.scales else 1.0
    assert system.energy(spec.y0) * E == pytest.approx(direct.energy(y), rel=1e-12)


def test_the_example_scene_file_loads():
    scene = pk.load_scene(ROOT / "examples" / "magnet_over_cylinder.toml")
    assert [f.source for f in scene.fields] == ["magpylib", "gravity"]


@pytest.mark.parametrize("fields, words", [
    ('source = "magnetic"', ["fields[0].source", "magnetic", "gravity"]),
    ('source = "gravity"\ng = [0, 0]\nh = 1', ["fields[0]", "h"]),
    ('source = "gravity"\ng = "down"', ["fields[0]", "g"]),
    ('source = "magpylib"\nclass = "Cylinder"\nparams = { polarization = "up" }',
     ["fields[0]", "polarization"]),
    ('g = [0, 0, -9.81]', ["fields[0].source"]),
])
def test_bad_field_tables_name_the_field(fields, words):
    text = SCENE.split("[[fields]]")[0] + "[[fields]]\n" + fields + "\n\n[run]\nduration = 0.1\n"
    with pytest.raises(SceneError) as info:
        loads_scene(text)
    for w in words:
        assert w in str(info.value)


def test_a_declared_class_outside_magpylibs_sources_fails_when_built():
    text = SCENE.replace('class = "Cylinder"', 'class = "os.system"')
    with pytest.raises(SceneError, match="os.system"):
        pk.build_run(loads_scene(text))


def test_fields_with_a_planner_are_refused_not_dropped():
    text = SCENE.replace("[run]", "[planner]\ntol = 1e-3\n\n[run]")
    with pytest.raises(SceneError, match="planner"):
        loads_scene(text)


def test_a_body_outside_the_declared_region_is_refused_before_the_run():
    text = SCENE.replace("r = [0.001, 0.0005, 0.035]", "r = [0.001, 0.0005, 0.05]")
    with pytest.raises(SceneError, match="outside the region"):
        pk.build_run(loads_scene(text))
