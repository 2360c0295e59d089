"""Vectorised mesh evaluation (poissonkit.compat.NumPoissonGeometry) against the PyPI package
``numericalpoissongeometry`` 1.1.2 (``numpoisson.numpoisson``), the symbolic peer
``poissongeometry`` and FORMULAS.md oracles."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from poissonkit.compat import (
    NumericalPoissonGeometry,
    NumPoissonGeometry,
    PoissonGeometry,
)
from poissonkit.errors import InputError

SO3 = {(1, 2): "x3", (1, 3): "-x2", (2, 3): "x1"}
Q = {(1, 2): "x1*x2", (2, 3): "x3"}
RATIONAL_H = "1/(x1 - x2) + 1/(x1 - x3) + 1/(x2 - x3)"
E3 = {(1, 5): "x3", (1, 6): "-x2", (2, 4): "-x3", (2, 6): "x1", (3, 4): "x2", (3, 5): "-x1",
      (4, 5): "x6", (4, 6): "-x5", (5, 6): "x4"}


@pytest.fixture(scope="module")
def mesh() -> np.ndarray:
    # points with distinct coordinates, away from the poles of RATIONAL_H
    rng = np.random.default_rng(20240601)
    pts = rng.uniform(-2.0, 2.0, (40, 3))
    return pts + np.array([0.0, 5.0, 10.0])


@pytest.fixture(scope="module")
def theirs(numeric_peer):
    return numeric_peer(3)


def test_alias_names_the_same_class():
    assert NumericalPoissonGeometry is NumPoissonGeometry


def test_documented_hamiltonian_example():
    out = NumPoissonGeometry(3).num_hamiltonian_vf(SO3, RATIONAL_H, np.array([[1.0, 2.0, 3.0]]))
    assert out.shape == (1, 3, 1)
    np.testing.assert_allclose(out[0, :, 0], [2.5, -5.0, 2.5], rtol=1e-13)


def test_bivector_and_matrix_equal_peer(theirs, mesh):
    ours = NumPoissonGeometry(3)
    for biv in (SO3, Q, {(1, 3): "exp(x2)*x1"}):
        np.testing.assert_allclose(ours.num_bivector(biv, mesh), theirs.num_bivector(biv, mesh))
        np.testing.assert_allclose(ours.num_bivector_to_matrix(biv, mesh),
                                   theirs.num_bivector_to_matrix(biv, mesh))
    d_ours = ours.num_bivector(SO3, mesh[:3], dict_output=True)
    d_theirs = theirs.num_bivector(SO3, mesh[:3], dict_output=True)
    assert d_ours.shape == d_theirs.shape == (3,)
    for a, b in zip(d_ours, d_theirs):
        assert a.keys() == b.keys() and np.allclose([a[k] for k in a], [b[k] for k in a])


def test_sharp_hamiltonian_bracket_equal_peer(theirs, mesh):
    ours = NumPoissonGeometry(3)
    form = {(1,): "x1*x2", (3,): "sin(x3)"}
    np.testing.assert_allclose(ours.num_sharp_morphism(Q, form, mesh),
                               theirs.num_sharp_morphism(Q, form, mesh), rtol=1e-12)
    for biv in (SO3, Q):
        a = ours.num_hamiltonian_vf(biv, RATIONAL_H, mesh)
        b = theirs.num_hamiltonian_vf(biv, RATIONAL_H, mesh)
        assert a.shape == b.shape == (len(mesh), 3, 1)
        np.testing.assert_allclose(a, b, rtol=1e-11, atol=1e-14)
        a = ours.num_poisson_bracket(biv, RATIONAL_H, "x1*x2**2", mesh)
        b = theirs.num_poisson_bracket(biv, RATIONAL_H, "x1*x2**2", mesh)
        assert a.shape == b.shape == (len(mesh),)
        np.testing.assert_allclose(a, b, rtol=1e-11)
    da = ours.num_hamiltonian_vf(SO3, "x1*x2", mesh[:2], dict_output=True)
    db = theirs.num_hamiltonian_vf(SO3, "x1*x2", mesh[:2], dict_output=True)
    for a, b in zip(da, db):
        assert a.keys() == b.keys() and np.allclose([a[k] for k in a], [b[k] for k in a])


def test_one_forms_bracket_gauge_flaschka_normal_form_equal_peer(theirs, numeric_peer, mesh):
    ours = NumPoissonGeometry(3)
    a = {(1,): "x1*x2", (2,): "x2", (3,): "x3**2"}
    b = {(1,): "x3", (2,): "x1*x2", (3,): "x3"}
    np.testing.assert_allclose(ours.num_one_forms_bracket(SO3, a, b, mesh),
                               theirs.num_one_forms_bracket(SO3, a, b, mesh), rtol=1e-12)
    lam = {(1, 2): "0.1", (2, 3): "0.2*x1"}
    np.testing.assert_allclose(ours.num_gauge_transformation(SO3, lam, mesh[:10]),
                               theirs.num_gauge_transformation(SO3, lam, mesh[:10]), rtol=1e-10,
                               atol=1e-12)
    np.testing.assert_allclose(ours.num_linear_normal_form_R3(SO3, mesh),
                               theirs.num_linear_normal_form_R3(SO3, mesh))
    t4, o4 = numeric_peer(4), NumPoissonGeometry(4)
    m4 = np.c_[mesh, mesh[:, 0] * 0.5]
    K = ["x1**2 + x2**2 + x3**2", "x4"]
    np.testing.assert_allclose(o4.num_flaschka_ratiu_bivector(K, m4),
                               t4.num_flaschka_ratiu_bivector(K, m4))
    for x, y in zip(o4.num_flaschka_ratiu_bivector(K, m4, symplectic_form=True),
                    t4.num_flaschka_ratiu_bivector(K, m4, symplectic_form=True)):
        np.testing.assert_allclose(x, y, rtol=1e-12)


def _evaluate_dict(d: dict, point: np.ndarray, dim: int = 3) -> dict:
    """The peer's symbolic string output evaluated at a point (test helper, trusted strings)."""
    from poissonkit.compat._inputs import Reader

    r = Reader(dim)
    sub = dict(zip(r.coords, point.tolist()))
    return {k: float(r.expr(v).subs(sub)) for k, v in d.items()}


def test_coboundary_equals_symbolic_peer(mesh, peer):
    # numericalpoissongeometry's num_coboundary_operator fails with the current `permutation`
    # package (TypeError), so compare with poissongeometry's symbolic result at the points.
    symbolic = peer(3)
    ours = NumPoissonGeometry(3)
    cases = [(Q, Q), (SO3, {(1,): "x1**2", (3,): "x2"}), (Q, {(1, 2): "x3**2"}),
             (SO3, {(1, 2): "x1*x3"})]
    for biv, mv in cases:
        sym = symbolic.coboundary_operator(biv, mv)
        num = ours.num_coboundary_operator(biv, mv, mesh[:5])
        if not sym:  # identically zero: an empty array, as NumericalPoissonGeometry
            assert num.size == 0
            continue
        degree = len(next(iter(mv))) + 1
        assert num.shape == (5,) + (3,) * degree
        for p in range(5):
            want = _evaluate_dict(sym, mesh[p])
            for key, value in want.items():
                idx = tuple(k - 1 for k in key)
                assert num[(p,) + idx] == pytest.approx(value, rel=1e-12, abs=1e-12)
                # antisymmetry of the full tensor
                swapped = (idx[1], idx[0]) + idx[2:]
                assert num[(p,) + swapped] == pytest.approx(-value, rel=1e-12, abs=1e-12)
    assert ours.num_coboundary_operator(SO3, SO3, mesh).size == 0  # [P, P] = 0: empty
    f = ours.num_coboundary_operator(SO3, "x1**2*x3", mesh[:3])
    want = symbolic.coboundary_operator(SO3, "x1**2*x3")
    for p in range(3):
        got = _evaluate_dict(want, mesh[p])
        np.testing.assert_allclose(f[p, :, 0], [got[(i,)] for i in (1, 2, 3)], rtol=1e-12)


def test_curl_and_modular_on_the_mesh_use_the_corrected_density_derivative(mesh):
    ours = NumPoissonGeometry(3)
    x1, x2, x3 = mesh.T
    # curl of x2 d1^d3 for f = exp(x3): the d1 component is -x2 (docs/compat.md)
    c = ours.num_curl_operator({(1, 3): "x2"}, "exp(x3)", mesh)
    assert c.shape == (len(mesh), 3, 1)
    np.testing.assert_allclose(c[:, 0, 0], -x2)
    np.testing.assert_allclose(c[:, 1:, 0], 0.0)
    # vector field: divergence relative to f Omega, f = exp(x1 x2): div X + X(log f)
    d = ours.num_curl_operator({(1,): "x1", (2,): "x3", (3,): "x2"}, "exp(x1*x2)", mesh)
    assert d.shape == (len(mesh),)
    np.testing.assert_allclose(d, 1.0 + x1 * x2 + x3 * x1, rtol=1e-12)
    # modular field of so(3) relative to exp(x3) dx: P d log f = column 3 of P = (-x2, x1, 0)
    z = ours.num_modular_vf(SO3, "exp(x3)", mesh)
    np.testing.assert_allclose(z[:, :, 0], np.c_[-x2, x1, 0 * x1], atol=1e-14)


def test_symmetric_density_curl_equals_symbolic_peer(mesh, peer):
    symbolic = peer(3)
    sym = symbolic.modular_vf(SO3, "exp(x1 + x2 + x3)")
    num = NumPoissonGeometry(3).num_modular_vf(SO3, "exp(x1 + x2 + x3)", mesh[:4])
    for p in range(4):
        want = _evaluate_dict(sym, mesh[p])
        np.testing.assert_allclose(num[p, :, 0], [want.get((i,), 0.0) for i in (1, 2, 3)],
                                   atol=1e-12)


def test_e3_hamiltonian_on_mesh_equals_minus_formulas_oracle():
    """FORMULAS.md §2: P0 dH at gamma = (2/3, 1/3, 2/3), L = (1, -2, 1/2) for
    H = (L, A L)/2 + gamma3, A = diag(1/2, 1/3, 1/4); PoissonGeometry's sign gives -P0 dH."""
    point = np.array([[2 / 3, 1 / 3, 2 / 3, 1.0, -2.0, 0.5]] * 2)
    out = NumPoissonGeometry(6).num_hamiltonian_vf(E3, "x4**2/4 + x5**2/6 + x6**2/8 + x3", point)
    oracle = np.array([-35 / 72, -1 / 4, 11 / 18, -5 / 12, 13 / 24, -1 / 3])
    np.testing.assert_allclose(out[:, :, 0], -np.vstack([oracle, oracle]), rtol=1e-14)


def test_poisson_bracket_on_mesh_matches_exact_bracket():
    # {f, g} evaluated exactly with sympy at rational points, then compared
    pg, npg = PoissonGeometry(3), NumPoissonGeometry(3)
    f, g = "x1*exp(x2) + x3**2", "sin(x1*x3) + x2"
    pts = np.array([[0.5, -1.25, 2.0], [1.5, 0.25, -0.75], [-2.0, 3.0, 0.125]])
    num = npg.num_poisson_bracket(Q, f, g, pts)
    from poissonkit.compat._inputs import Reader

    exact = Reader(3).expr(pg.poisson_bracket(Q, f, g))
    for p, value in zip(pts, num):
        want = exact.subs({x: sp.Rational(v) for x, v in zip(pg.coords, p)})
        assert value == pytest.approx(float(want.evalf(30)), rel=1e-13)


def test_cache_distinguishes_inputs_and_meshes(mesh):
    npg = NumPoissonGeometry(3)
    a = npg.num_hamiltonian_vf(SO3, "x1", mesh)
    b = npg.num_hamiltonian_vf(SO3, "x2", mesh)
    assert not np.allclose(a, b)
    c = npg.num_hamiltonian_vf(SO3, "x1", mesh[:5] * 2)
    np.testing.assert_allclose(c, npg.num_hamiltonian_vf(SO3, "x1", mesh[:5]) * 2)
    # constant entries broadcast over the mesh
    k = npg.num_bivector({(1, 2): "1", (2, 3): "x1"}, mesh)
    np.testing.assert_allclose(k[:, 0, 1], 1.0)
    np.testing.assert_allclose(k[:, 1, 0], -1.0)


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_non_finite_mesh_is_an_input_error_naming_the_row(bad, mesh):
    points = mesh[:4].copy()
    points[2, 1] = bad
    npg = NumPoissonGeometry(3)
    # the mesh is checked up front: neither a NaN result (the so(3) field depends on x2) nor a
    # finite-looking one (a constant bivector) comes back for a point that is not a point
    with pytest.raises(InputError, match="mesh is not finite at 1 point.*row 2"):
        npg.num_bivector({(1, 2): "1"}, points)
    with pytest.raises(InputError, match="mesh is not finite"):
        npg.num_hamiltonian_vf(SO3, "x1", points)
    with pytest.raises(InputError, match="mesh is not finite"):
        npg.num_poisson_bracket(SO3, "x1", "x2", points)
    with pytest.raises(InputError, match="mesh is not finite"):
        npg.num_gauge_transformation(SO3, {(1, 2): "x1"}, points)
