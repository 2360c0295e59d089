"""A scene's ``[[fields]]`` table with missing or malformed entries is refused with a typed
error naming the field (never a magpylib or numpy exception)."""

from __future__ import annotations

import numpy as np
import pytest
from scene_texts import top_scene  # type: ignore[import-not-found]

import poissonkit as pk
from poissonkit.errors import InputError, PoissonkitError
from poissonkit.numerics.fields.base import FieldRequest
from poissonkit.scene.loader import loads_scene
from poissonkit.scene.build import build_run

GOOD = {"polarization": [0.0, 0.0, 1.0], "dimension": [0.05, 0.01]}
AT = FieldRequest(np.array([[0.0, 0.0, 0.03]]))

SCENE = top_scene("t", 'source = "magpylib"\nclass = "Cylinder"\n{extra}', gravity=False,
                  run="step = 2e-4\nduration = 0.002")


@pytest.mark.parametrize("kw, match", [
    ({}, "params is missing or empty"),
    ({"params": {}}, "params is missing or empty"),
    ({"params": GOOD, "orientation": [0.1, 0.2]}, "orientation .* 3-vector"),
    ({"params": GOOD, "position": [0.0, 0.01]}, "position .* 3-vector"),
    ({"params": GOOD, "orientation": [0.1, float("nan"), 0.0]}, "orientation"),
])
def test_python_field_with_bad_declaration_is_an_input_error(kw, match):
    with pytest.raises(InputError, match=match):
        pk.field("magpylib", **{"class": "Cylinder", **kw}).compile(AT)


@pytest.mark.parametrize("extra, match", [
    ("", "params is missing or empty"),
    ("params = {}", "params is missing or empty"),
    ("params = { polarization = [0.0, 0.0, 1.0], dimension = [0.05, 0.01] }\n"
     "orientation = [0.1, 0.2]", "orientation"),
    ("params = { polarization = [0.0, 0.0, 1.0], dimension = [0.05, 0.01] }\n"
     "position = [1.0, 2.0]", "position"),
])
def test_scene_field_with_bad_declaration_is_a_typed_error(extra, match):
    with pytest.raises(PoissonkitError, match=match) as info:
        build_run(loads_scene(SCENE.format(extra=extra)))
    assert "magpylib Cylinder" in str(info.value)


BODY_AT = SCENE.replace("r = [0.0, 0.0, 0.03]", "r = {r}").replace(
    'source = "magpylib"\nclass = "Cylinder"\n{extra}', "{field}")


@pytest.mark.parametrize("r, field, match", [
    ("[0.0, 0.0, 0.001]", 'source = "magpylib"\nclass = "Cylinder"\n'
     "params = { polarization = [0.0, 0.0, 1.0], dimension = [0.05, 0.01] }",
     "field 'magpylib': body 'top' starts inside"),
    ("[0.0, 0.0, 0.001]", 'source = "cylinder"\npolarization = 1.0\nradius = 0.02\n'
     "length = 0.01", "field 'cylinder': body 'top' starts inside"),
    ("[0.02, 0.0, 0.0]", 'source = "current_loop"\ncurrent = 10.0\nradius = 0.02',
     "field 'current_loop': body 'top' starts on the wire"),
])
def test_a_body_inside_a_source_or_on_its_wire_is_refused(r, field, match):
    with pytest.raises(PoissonkitError, match=match):
        build_run(loads_scene(BODY_AT.format(r=r, field=field)))


def test_solids_describe_the_source_for_drawing():
    from poissonkit.numerics.fields.solids import field_solids

    f = pk.field("magpylib", **{"class": "CylinderSegment", "params": {
        "polarization": [0, 0, 1.0], "dimension": [0.005, 0.025, 0.01, 0, 360]},
        "position": [0.0, 0.0, -0.005], "tol": 1e-3}).compile(AT)
    (s,) = field_solids([f])
    d = s.describe()
    assert d["kind"] == "cylinder_segment" and d["position_m"] == [0.0, 0.0, -0.005]
    assert d["dimensions"]["outer_radius"] == 0.025 and d["field"] == "magpylib"
    assert s.contact_shape() == (0.025, 0.005)
    assert s.inside([[0.01, 0.0, -0.005], [0.002, 0.0, -0.005], [0.01, 0.0, 0.01]]).tolist() \
        == [True, False, False]
