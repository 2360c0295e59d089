"""Push-forward and Poisson maps: FORMULAS.md §6 (canonical -> (42), moment map (43) -> P_{g,0})
and the Chaplygin reduction of Remark 6 (FORMULAS §13: not verified there; pinned here)."""

from __future__ import annotations

import pytest
import sympy as sp
from brackets import p_g  # type: ignore[import-not-found]

from poissonkit.errors import DimensionError, InputError
from poissonkit.structure import Bivector, canonical, e3
from poissonkit.structure.checks import vanishes
from poissonkit.structure.poisson_map import (
    PushForwardError, is_poisson_map, jacobian_bracket, push_forward,
)

R = sp.Rational


def _dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def _deformed_canonical(q, p, g):
    """(42): {q_i, p_j} = g delta_ij, {p_i, p_j} = p_i d_j g - p_j d_i g (FORMULAS §6)."""
    dg = [sp.diff(g, c) for c in q]
    mat = sp.zeros(6, 6)
    for i in range(3):
        mat[i, 3 + i], mat[3 + i, i] = g, -g
        for j in range(3):
            mat[3 + i, 3 + j] = p[i] * dg[j] - p[j] * dg[i]
    return Bivector.from_matrix(mat, list(q) + list(p))


def _p_g0(gam, M, g):
    """P_{g,0} of FORMULAS §5 = (44)."""
    return p_g(gam, M, g, _dot([sp.diff(g, c) for c in gam], M))


def test_canonical_pushed_by_g_times_p_is_bracket_42():
    C = canonical(3)
    q, p = C.coords[:3], C.coords[3:]
    g = sp.Function("g")(*q)
    phi = list(q) + [g * x for x in p]
    out = push_forward(C, phi, C.names)
    assert out.method == "solve" and out.image_relations == ()
    target = _deformed_canonical(q, p, g)
    assert all(vanishes(a - b) for a, b in zip(out.matrix, target.matrix))
    assert is_poisson_map(phi, C, target)
    # the opposite sign of {p_i, p_j} (which breaks Jacobi) is not the push-forward
    flipped = target.matrix.as_mutable()
    flipped[3:, 3:] = -flipped[3:, 3:]
    wrong = Bivector.from_matrix(flipped, target.coords)
    assert not is_poisson_map(phi, C, wrong)


def test_canonical_push_forward_oracle_values():
    # FORMULAS §6 oracle: g = 1 + q1^2 at q = (2/3,1/3,2/3), p = (1,-2,1/2)
    C = canonical(3)
    q, p = C.coords[:3], C.coords[3:]
    g = 1 + q[0] ** 2
    out = push_forward(C, list(q) + [g * x for x in p], C.names).bivector
    pt = dict(zip(out.coords, [R(2, 3), R(1, 3), R(2, 3), 1, -2, R(1, 2)]))
    Q = out.matrix.subs(pt)
    assert (Q[0, 3], Q[3, 4], Q[3, 5], Q[4, 5]) == (R(13, 9), R(8, 3), R(-2, 3), 0)


def test_moment_map_takes_42_to_p_g0():
    q = sp.symbols("q_x q_y q_z", real=True)
    p = sp.symbols("p_x p_y p_z", real=True)
    g = sp.Function("g")
    P42 = _deformed_canonical(q, p, g(*q))
    gam = sp.symbols("gamma_x gamma_y gamma_z", real=True)
    M = sp.symbols("M_x M_y M_z", real=True)
    target = _p_g0(gam, M, g(*gam))
    moment = list(q) + list(sp.Matrix(q).cross(sp.Matrix(p)))
    assert is_poisson_map(moment, P42, target)
    assert not is_poisson_map(list(q) + [-m for m in moment[3:]], P42, target)
    # push-forward: the moment map is not invertible; its image is the leaf (gamma, M) = 0
    out = push_forward(P42, moment, [str(s) for s in gam + M])
    assert out.method == "groebner"
    assert len(out.image_relations) == 1
    assert sp.expand(out.image_relations[0] - _dot(gam, M)) == 0
    diff = out.matrix - target.matrix
    assert all(vanishes(e, constraints=[_dot(gam, M)]) for e in diff)
    # oracle (FORMULAS §6): g = 1 + q1^2, M = q x p = (3/2, 1/3, -5/3), {M1, M2} = -29/27
    J = jacobian_bracket(P42.subs(g(*q), 1 + q[0] ** 2).subs(
        {sp.Derivative(1 + q[0] ** 2, c): sp.diff(1 + q[0] ** 2, c) for c in q}), moment)
    J = J.doit()
    pt = dict(zip(q + p, [R(2, 3), R(1, 3), R(2, 3), 1, -2, R(1, 2)]))
    assert [m.subs(pt) for m in moment[3:]] == [R(3, 2), R(1, 3), R(-5, 3)]
    assert J[3, 4].subs(pt) == R(-29, 27)


@pytest.fixture(scope="module")
def chaplygin_symbolic():
    gam = sp.symbols("gamma_x gamma_y gamma_z", real=True)
    M = sp.symbols("M_x M_y M_z", real=True)
    a = sp.symbols("a1 a2 a3", positive=True)
    d = sp.Symbol("d", positive=True)
    Ag = [ai * gi for ai, gi in zip(a, gam)]
    g = sp.sqrt(1 - d * _dot(gam, Ag))
    return p_g(gam, M, g, -(d * _dot(M, Ag) / g)), gam, M, Ag, g, d


def test_remark_6_holds_exactly_on_the_leaf_gamma_dot_M_zero(chaplygin_symbolic):
    """Remark 6: L = M/g takes P_g to e(3) on (gamma, M) = 0 (FORMULAS §13, now checked)."""
    P, gam, M, _Ag, g, _d = chaplygin_symbolic
    target = e3("gamma_M", names=("gamma", "L"))
    phi = list(gam) + [m / g for m in M]
    assert is_poisson_map(phi, P, target, constraints=[_dot(gam, M)])


def test_remark_6_fails_off_the_leaf_with_the_identity_pinned(chaplygin_symbolic):
    """Off the leaf {L_i, L_j} - eps_ijk L_k = -(d/g^3) (gamma, M) eps_ijk (A gamma)_k."""
    P, gam, M, Ag, g, d = chaplygin_symbolic
    target = e3("gamma_M", names=("gamma", "L"))
    phi = list(gam) + [m / g for m in M]
    res = is_poisson_map(phi, P, target)
    assert not res
    assert [lab for lab, _ in res.failures] == ["{L_x, L_y}", "{L_x, L_z}", "{L_y, L_z}"]
    J = jacobian_bracket(P, phi)
    L = [m / g for m in M]
    gM = _dot(gam, M)
    for (i, j, k) in [(0, 1, 2), (1, 2, 0), (2, 0, 1)]:
        defect = J[3 + i, 3 + j] - L[k]
        assert vanishes(defect + d / g**3 * gM * Ag[k])
    # the gamma rows are exactly e(3): {L_i, gamma_j} = eps_ijk gamma_k everywhere
    for i in range(3):
        for j in range(3):
            assert vanishes(J[3 + i, j] - target.matrix[3 + i, j])


def test_bad_input_is_rejected_with_typed_errors():
    C = canonical(1)
    q, p = C.coords
    with pytest.raises(DimensionError):
        push_forward(C, [q, p], ["a"])
    with pytest.raises(InputError):
        push_forward(C, ["q_1", p], ["a", "b"])
    with pytest.raises(InputError):
        push_forward(C, [q, p * sp.Symbol("zz")], ["a", "b"])
    with pytest.raises(DimensionError):
        is_poisson_map([q], C, C)
    with pytest.raises(InputError):
        is_poisson_map([q, p], C.matrix, C)
    # (q1, q2 p1): {q1, q2 p1} = q2 is not a function of (u, v) — the bracket does not descend
    P4 = canonical(2)
    a, b, c, e = P4.coords
    with pytest.raises(PushForwardError):
        push_forward(P4, [a, b * c], ["u", "v"])
