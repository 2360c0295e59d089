"""Adaptive (octree) tables: the field and its gradient against independent truth (a
dipole's closed form, magpylib), NaN outside the region, and the natural scene over a
magpylib CylinderSegment run from an adaptive table at tol = 1e-5."""

from __future__ import annotations


import magpylib as magpy
import numpy as np
import pytest
from scene_texts import run_scene, top_scene  # type: ignore[import-not-found]

from poissonkit.numerics.fields.octree import evaluate, octree_table
from poissonkit.numerics.fields.solids import Solid
from poissonkit.numerics.fields.tabulated import tabulated_field

MU0 = 4e-7 * np.pi
M = np.array([0.0, 0.0, 1.0])  # dipole moment [A m²] at the origin


def dipole_b(p):
    """The point dipole's B [T] (closed form, the independent truth)."""
    p = np.asarray(p, float).reshape(-1, 3)
    r = np.linalg.norm(p, axis=1)[:, None]
    n = p / r
    return MU0 / (4 * np.pi) * (3 * n * (n @ M)[:, None] - M) / r ** 3


def dipole_j(p):
    """∂B_i/∂x_j of the point dipole (closed form)."""
    p = np.asarray(p, float).reshape(-1, 3)
    out = np.empty((len(p), 3, 3))
    for k, x in enumerate(p):
        r = np.linalg.norm(x)
        mx = M @ x
        out[k] = MU0 / (4 * np.pi) * (
            3 * (np.outer(M, x) + np.outer(x, M) + mx * np.eye(3)) / r ** 5
            - 15 * mx * np.outer(x, x) / r ** 7)
    return out


REGION = (np.array([-0.01, -0.01, 0.004]), np.array([0.01, 0.01, 0.024]))
BALL = Solid("sphere", (0.0, 0.0, 0.0), dimensions={"radius": 0.002}, field="dipole")


@pytest.fixture(scope="module")
def table():
    return octree_table("dipole", dipole_b, *REGION, 1e-4, solids=(BALL,))


def test_octree_b_and_gradient_agree_with_the_closed_form(table):
    info = table.info
    assert info["adaptive"] == "octree" and info["unresolved_cells"] == 0
    assert info["depth"] >= 2  # refined towards the dipole, not uniform
    rng = np.random.default_rng(11)
    pts = REGION[0] + (REGION[1] - REGION[0]) * rng.random((3000, 3))
    B, J = evaluate(table.data, pts)
    b, j = dipole_b(pts), dipole_j(pts)
    bmax = np.max(np.linalg.norm(b, axis=1))
    jmax = np.max(np.linalg.norm(j, axis=(1, 2)))
    assert np.max(np.linalg.norm(B - b, axis=1)) <= 1e-4 * bmax
    assert np.max(np.linalg.norm(J - j, axis=(1, 2))) <= 1e-4 * jmax
    assert info["field_error"] <= 1e-4 and info["gradient_error"] <= 1e-4


def test_octree_gradient_is_the_derivative_of_its_value(table):
    """Inside a cell the returned Jacobian is the exact derivative of the interpolant (the
    kick is the gradient of the energy): central differences of B agree to rounding."""
    p = np.array([0.0031, -0.0047, 0.0113])
    _, J = evaluate(table.data, p)
    h = 1e-8
    fd = np.stack([(evaluate(table.data, p + h * e)[0] - evaluate(table.data, p - h * e)[0])[0]
                   / (2 * h) for e in np.eye(3)], axis=1)
    assert np.allclose(J[0], fd, rtol=1e-6, atol=1e-9 * np.abs(J).max())


def test_octree_is_nan_outside_its_region(table):
    B, _ = evaluate(table.data, [[0.0, 0.0, 0.03]])
    assert np.all(np.isnan(B))


def test_a_uniform_table_that_fits_stays_uniform():
    f = tabulated_field("dipole", dipole_b, np.array([-0.01, -0.01, 0.02]),
                        np.array([0.01, 0.01, 0.03]), 1e-3, adaptive=True)
    assert "adaptive" not in f.info and f.info["nodes"] <= 300_000


SCENE = top_scene(
    "top_over_cylinder_segment",
    'source = "magpylib"\nclass = "CylinderSegment"\n'
    "params = { polarization = [0.0, 0.0, 1.0], dimension = [0.005, 0.025, 0.01, 0.0, 360.0] }\n"
    "tol = 1e-5")


@pytest.mark.slow
def test_a_top_over_a_cylinder_segment_runs_from_an_adaptive_table(tmp_path):
    out, summary = run_scene(tmp_path, SCENE)
    field = summary["parameters"]["fields"][0]
    assert field["adaptive"] == "octree" and field["tol"] == 1e-5
    assert field["field_error"] <= 1e-5 and field["gradient_error"] <= 1e-5
    # energy conserved to the table's stated accuracy (steps where cells of two sizes meet)
    assert summary["max_rel_energy_error"] <= 1e-4
    traj = np.load(out / "trajectory.npz")
    z = traj["y"][:, 2] * summary["units"]["internal_unit_in_si"]["length"]
    assert z[-1] > z[0]  # pushed up
    # the table's B against magpylib at fresh random points of its region
    from poissonkit.scene.build import build_run
    from poissonkit.scene.loader import loads_scene

    built = build_run(loads_scene(SCENE)).system.fields[0]
    lo, hi = (np.array(v) for v in built.info["region_m"])
    pts = lo + (hi - lo) * np.random.default_rng(5).random((2000, 3))
    src = magpy.magnet.CylinderSegment(polarization=(0, 0, 1.0),
                                       dimension=(0.005, 0.025, 0.01, 0, 360))
    ref = src.getB(pts)
    B, _ = evaluate(built.data, pts)
    assert np.max(np.linalg.norm(B - ref, axis=1)) <= 1e-5 * built.info["max_B_T"]


def test_a_body_leaving_a_table_is_named_with_its_field_position_and_time(monkeypatch):
    """The run stops with NaN forces once the body is outside the table; the explanation names
    the field, the body, where it is [m] and when [s]."""
    import poissonkit as pk
    from poissonkit.errors import NonFiniteStateError
    from poissonkit.numerics.fields import tabulated
    from poissonkit.numerics.fields.regions import FieldRegionError, explain_nonfinite
    from poissonkit.numerics.nbody import Body, NBodySystem
    from poissonkit.numerics.units import Scales

    monkeypatch.setattr(tabulated, "GROWTH_ROOM", 1)  # no room: the table cannot grow
    field = tabulated_field("dipole", dipole_b, np.array([-0.01, -0.01, 0.02]),
                            np.array([0.01, 0.01, 0.03]), 1e-3)
    s = NBodySystem([Body("top", 0.02, alpha=1 / 2e-6, attributes={"moment": 0.1})],
                    scales=Scales(length=0.01, mass=0.02, time=0.01), fields=[field])
    y0 = s.pack([[0.0, 0.0, 0.025]], [[0.0, 0.0, 0.02 * 0.5]], [[0.0, 0.0, -1.0]],
                [[0.0, 0.0, -2e-5]], si=True)
    with pytest.raises(NonFiniteStateError) as info:
        pk.solve(s, y0, 5.0, method="splitting4", step=0.01)
    err = info.value
    # the state at the failure: the drift carried the body out with finite momenta, the kick
    # there gave NaN momenta
    y_fail = s.pack([[0.0, 0.0, 0.0305]], [[0.0, 0.0, 0.01]], [[0.0, 0.0, -1.0]],
                    [[0.0, 0.0, -2e-5]], si=True)
    y_fail[3:6] = np.nan
    explained = explain_nonfinite(s, y_fail, err)
    assert isinstance(explained, FieldRegionError)
    assert explained.field == "dipole" and explained.body == "top"
    assert explained.position[2] > 0.03
    assert explained.time_s == pytest.approx(err.time * 0.01)
    assert "left the region of field 'dipole'" in str(explained) and " s:" in str(explained)
