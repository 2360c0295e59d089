"""magpylib sources as fields: the tabulated field against magpylib itself (independent
truth), typed errors for bad declarations, sources passed from Python."""

from __future__ import annotations

import magpylib as magpy
import numpy as np
import pytest

import poissonkit as pk
from poissonkit.errors import InputError, PoissonkitError, UnknownNameError
from poissonkit.numerics.fields import FieldRequest

from field_cases import CYLINDER, REGION, TOL

MU = 0.1  # moment of the probe magnet [A m²]


def magpylib_gradient(src, r, nu, d=1e-7):
    """∇(ν·B) at r by central differences of magpylib's own field."""
    return np.array([(nu @ src.getB(r + d * e) - nu @ src.getB(r - d * e)) / (2 * d)
                     for e in np.eye(3)])


def test_force_and_torque_agree_with_magpylib_to_the_tolerance(tabulated_cylinder):
    src = magpy.magnet.Cylinder(**CYLINDER)
    lo, hi = np.array(REGION[:3]), np.array(REGION[3:])
    rng = np.random.default_rng(7)
    pts = lo + (hi - lo) * rng.random((40, 3))
    jac_scale = max(np.linalg.norm(np.array([[magpylib_gradient(src, p, e) for e in np.eye(3)]]))
                    for p in pts[:10])
    b_scale = max(np.linalg.norm(src.getB(p)) for p in pts)
    for p in pts:
        nu = rng.normal(size=3)
        nu /= np.linalg.norm(nu)
        F, T = tabulated_cylinder.force_torque(p, nu, MU)
        F_ref = MU * magpylib_gradient(src, p, nu)
        T_ref = MU * np.cross(nu, src.getB(p))
        # |ΔF| <= μ |ΔJ| <= μ tol max|J|; |ΔT| <= μ tol max|B|
        assert np.linalg.norm(F - F_ref) <= 1.5 * MU * TOL * jac_scale
        assert np.linalg.norm(T - T_ref) <= MU * TOL * b_scale
    assert tabulated_cylinder.info["gradient_error"] <= TOL
    assert tabulated_cylinder.info["field_error"] <= TOL


def test_a_tighter_tolerance_refines_the_grid_and_meets_it():
    src = magpy.current.Circle(current=500.0, diameter=0.06)
    coarse = pk.field(src, tol=1e-2, region=(-0.01, -0.01, 0.02, 0.01, 0.01, 0.04),
                      mode="table").compile()
    fine = pk.field(src, tol=1e-4, region=(-0.01, -0.01, 0.02, 0.01, 0.01, 0.04),
                    mode="table").compile()
    assert fine.info["nodes"] > coarse.info["nodes"]
    assert fine.info["gradient_error"] <= 1e-4 < coarse.info["gradient_error"]
    # the error measured on the table is honest: check it independently at fresh points
    rng = np.random.default_rng(3)
    pts = np.array([-0.01, -0.01, 0.02]) + np.array([0.02, 0.02, 0.02]) * rng.random((50, 3))
    B = np.array([fine.energy(p, e, -1.0)[2] for p in pts for e in [np.eye(3)[0]]])
    ref = src.getB(pts)
    assert np.max(np.linalg.norm(B - ref, axis=1)) <= 1e-4 * np.max(np.linalg.norm(ref, axis=1))


def test_a_collection_passed_from_python_is_summed():
    coll = magpy.Collection(magpy.magnet.Cylinder(**CYLINDER),
                            magpy.current.Circle(current=100.0, diameter=0.04,
                                                 position=(0, 0, 0.005)))
    f = pk.field(coll, tol=1e-4, region=REGION).compile()
    p = np.array([0.002, -0.001, 0.03])
    _, _, dnu = f.energy(p, (0, 0, 1), -1.0)  # ∂U/∂ν = -c B with c = -1: B
    assert np.allclose(dnu, coll.getB(p), rtol=1e-4, atol=1e-4 * np.linalg.norm(coll.getB(p)))


def test_the_default_region_covers_the_bodies():
    f = pk.field("magpylib", **{"class": "Circle", "params": {"current": 100.0,
                                                               "diameter": 0.05}},
                 tol=1e-3, mode="table").compile(FieldRequest(np.array([[0.0, 0.0, 0.04]])))
    lo, hi = (np.array(v) for v in f.info["region_m"])
    assert np.all(lo < [0, 0, 0.04]) and np.all(hi > [0, 0, 0.04])


@pytest.mark.parametrize("params, error, words", [
    ({"class": "Eval", "params": {}}, UnknownNameError, ["Eval", "Cylinder"]),
    ({"class": "__import__", "params": {}}, UnknownNameError, ["__import__"]),
    ({"class": "Cylinder", "params": {"polarisation": [0, 0, 1]}}, UnknownNameError,
     ["polarisation", "polarization"]),
    ({"class": "Cylinder", "params": {"polarization": [0, 0, 1], "dimension": [-1, 0.01]}},
     InputError, ["magpylib Cylinder"]),
    ({"class": "Cylinder", "params": {"polarization": "up"}}, InputError, ["polarization"]),
])
def test_bad_declarations_are_typed_errors(params, error, words):
    with pytest.raises(error) as info:
        pk.field("magpylib", **params, region=REGION).compile()
    assert isinstance(info.value, PoissonkitError)
    for w in words:
        assert w in str(info.value)


def test_a_tabulated_field_without_bodies_or_region_says_what_to_give():
    with pytest.raises(InputError, match="region"):
        pk.field("magpylib", **{"class": "Cylinder", "params": CYLINDER},
                 mode="table").compile()
