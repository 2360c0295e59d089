"""Oracle values of FORMULAS.md §5 and §7–§12, as exact identities at the reference points."""

from __future__ import annotations

import sympy as sp
from poissonkit_nonholonomic.ball import (
    bmf_parts,
    chaplygin_ball,
    chaplygin_ball_sphere_bmf,
    chaplygin_gyrostat,
)
from poissonkit_nonholonomic.general import p_gf_system
from poissonkit_nonholonomic.routh import routh_parts, routh_sphere
from poissonkit_nonholonomic.suslov import suslov, suslov_potential
from poissonkit_nonholonomic.veselova import (
    veselova,
    veselova_gyrostat,
    veselova_maps,
    veselova_original_field,
)

R = sp.Rational
G0 = (R(2, 3), R(1, 3), R(2, 3))
M0 = (1, -2, R(1, 2))


def _eq(a, b) -> bool:
    return sp.simplify(sp.radsimp(sp.sympify(a) - sp.sympify(b))) == 0


def _point(coords, values):
    return {c: sp.sympify(v) for c, v in zip(coords, values)}


def _bracket(system, i, j, point):
    return system.structure.matrix[system.structure.index(i), system.structure.index(j)].subs(point)


def _field(system, point):
    """X = N P dH at a point, substituting before multiplying (fast, exact)."""
    P = system.structure.matrix.subs(point)
    dH = sp.Matrix([sp.diff(system.hamiltonian, x).subs(point) for x in system.coords])
    return list(sp.sympify(system.multiplier).subs(point) * P * dH)


def test_p_gf_brackets_match_formulas_section5():
    for phi, expected in (("gamma_z", (R(947, 486), R(553, 243), R(649, 243))),
                          (None, (R(731, 486), R(607, 243), R(541, 243)))):
        s = p_gf_system(g="1 + gamma_x**2", f="gamma_y", phi=phi)
        pt = _point(s.coords, G0 + (1, -2, R(1, 2)))
        got = [_bracket(s, "M_x", "M_y", pt), _bracket(s, "M_x", "M_z", pt),
               _bracket(s, "M_y", "M_z", pt)]
        assert all(_eq(g, e) for g, e in zip(got, expected))
        assert _eq(_bracket(s, "M_x", "gamma_y", pt), R(26, 27))


def test_chaplygin_ball_oracles_section7():
    s = chaplygin_ball(1, 2, 3, 1)
    pt = _point(s.coords, G0 + M0)
    assert _eq((1 / s.multiplier**2).subs(pt), R(17, 27))  # g^2
    omega = [sp.diff(s.hamiltonian, m).subs(pt) for m in s.coords[3:]]  # dH/dM = omega
    assert all(_eq(a, b) for a, b in zip(omega, (R(41, 68), R(-43, 68), R(3, 17))))
    assert _eq(s.integrals["H1=(M,omega)"].subs(pt), R(133, 68))
    X = _field(s, pt)
    expected = (R(49, 102), R(29, 102), R(-127, 204), R(-5, 136), R(1, 8), R(39, 68))
    assert all(_eq(a, b) for a, b in zip(X, expected))
    r51 = sp.sqrt(51)
    for (i, j), v in {("gamma_x", "M_y"): 2 * r51 / 27, ("gamma_x", "M_z"): -r51 / 27,
                      ("gamma_y", "M_z"): 2 * r51 / 27, ("M_x", "M_y"): 5 * r51 / 153,
                      ("M_x", "M_z"): 143 * r51 / 612, ("M_y", "M_z"): 3 * r51 / 34}.items():
        assert _eq(_bracket(s, i, j, pt), v), (i, j)


def test_chaplygin_gyrostat_oracle_section7():
    s = chaplygin_gyrostat(1, 2, 3, 1, S=(1, 0, -1))
    X = _field(s, _point(s.coords, G0 + M0))
    expected = (R(49, 102), R(29, 102), R(-127, 204), R(-91, 136), R(-89, 136), R(-1, 17))
    assert all(_eq(a, b) for a, b in zip(X, expected))


def test_bmf_oracles_section8():
    s = chaplygin_ball_sphere_bmf(1, 2, 3, 1)
    p = bmf_parts(1, 2, 3, 1)
    assert p["b"] == [5, 3, 1]
    pt = _point(s.coords, (R(1, 3), R(2, 3), R(2, 3)) + M0)
    assert _eq(p["Q"].subs(pt), R(37, 54))
    assert _eq(p["s"].subs(pt), R(-29, 9))
    assert _eq(s.integrals["H1=(M,omega)"].subs(pt), R(1155, 592))
    assert _eq(s.casimirs["C2=(gamma,B M)"].subs(pt), -2)
    X = _field(s, pt)
    expected = (R(-239, 444), R(-245, 888), R(121, 222), R(31, 148), R(11, 74), R(13, 74))
    assert all(_eq(a, b) for a, b in zip(X, expected))
    r = sp.sqrt(222)
    assert _eq(_bracket(s, "gamma_x", "M_y", pt), -19 * r / 486)
    assert _eq(_bracket(s, "M_x", "M_y", pt), 1819 * r / 23976)
    assert _eq(_bracket(s, "M_y", "M_z", pt), -9827 * r / 23976)


def test_veselova_oracles_section9():
    s = veselova(1, 2, 3)
    K0 = (1, 2, -1)
    pt = _point(s.coords, G0 + K0)
    maps = veselova_maps(1, 2, 3)
    assert _eq((1 / s.multiplier**2).subs(pt), 2)
    assert _eq(s.casimirs["H4=(gamma,K)"].subs(pt), R(2, 3))
    assert all(_eq(a.subs(pt), b) for a, b in zip(maps["M"], (R(11, 9), R(19, 9), R(-7, 9))))
    assert all(_eq(a.subs(pt), b) for a, b in zip(maps["omega"], (R(11, 9), R(38, 9), R(-7, 3))))
    X = _field(s, pt)
    expected = (R(-97, 27), R(64, 27), R(65, 27), R(-4, 9), R(10, 9), R(16, 9))
    assert all(_eq(a, b) for a, b in zip(X, expected))
    assert all(_eq(s.original[x].subs(pt), b) for x, b in zip(s.coords, expected))
    assert _eq(s.integrals["H1=(K,A_g K)"].subs(pt), R(106, 9))
    MAM = sum(a * m**2 for a, m in zip((1, 2, 3), maps["M"]))
    assert _eq(MAM.subs(pt), R(110, 9))
    r2 = sp.sqrt(2)
    for (i, j), v in {("K_x", "K_y"): -11 * r2 / 9, ("K_x", "K_z"): -17 * r2 / 9,
                      ("K_y", "K_z"): 7 * r2 / 9, ("K_x", "gamma_y"): 2 * r2 / 3}.items():
        assert _eq(_bracket(s, i, j, pt), v), (i, j)
    o = veselova_original_field(1, 2, 3)
    pt58 = _point(o["coords"], G0 + K0)
    assert _eq(o["lam"].subs(pt58), -2)
    expected58 = (R(-11, 3), R(8, 3), R(7, 3), R(-10, 3), R(4, 3), R(2, 3))
    assert all(_eq(a.subs(pt58), b) for a, b in zip(o["field"], expected58))


def test_veselova_gyrostat_oracles_section10():
    s = veselova_gyrostat(1, 2, 3, k=(1, 1, 0))
    pt = _point(s.coords, G0 + (1, 2, -1))
    assert _eq(s.hamiltonian.subs(pt), R(191, 36))
    assert _eq(s.casimirs["(K+k,gamma)"].subs(pt), R(5, 3))
    X = _field(s, pt)
    expected = (R(-94, 27), R(52, 27), R(68, 27), R(5, 9), R(10, 9), R(40, 9))
    assert all(_eq(a, b) for a, b in zip(X, expected))
    r2 = sp.sqrt(2)
    for (i, j), v in {("K_x", "K_y"): -14 * r2 / 9, ("K_x", "K_z"): -49 * r2 / 18,
                      ("K_y", "K_z"): 13 * r2 / 9, ("K_x", "gamma_y"): 2 * r2 / 3}.items():
        assert _eq(_bracket(s, i, j, pt), v), (i, j)


def test_routh_sphere_oracles_section11():
    p = routh_parts(R=2, a=R(1, 2), m=3, I1=5, I3=7, u=10)
    s = routh_sphere(R=2, a=R(1, 2), m=3, I1=5, I3=7, u=10)
    pt = _point(s.coords, G0 + M0)
    omega = [w.subs(pt) for w in p["omega"]]
    assert all(_eq(a, b) for a, b in zip(omega, (R(10496, 145029), R(-11422, 145029),
                                                 R(181, 3334))))
    expected = (R(61435, 870174), R(5245, 435087), R(-20, 261), R(40975358, 12617523),
                R(-168233597, 25235046), R(7760, 145029))
    assert all(_eq(s.original[x].subs(pt), b) for x, b in zip(s.coords, expected))
    assert all(_eq(a, b) for a, b in zip(_field(s, pt), expected))
    assert _eq(s.hamiltonian.subs(pt), R(7883987, 1160232))
    assert _eq(p["J1"].subs(pt), R(11, 12))
    assert _eq((p["g"] ** 2).subs(pt), R(1667, 12))
    assert _eq(p["J2"].subs(pt), 181 * sp.sqrt(5001) / 20004)
    # X(J1) = X(J2) = X(H) = 0 and div(g^{-1} X) = 0 at this point (FORMULAS.md §11)
    for F in (p["J1"], p["J2"], s.hamiltonian):
        assert _eq(sum(sp.diff(F, x).subs(pt) * v for x, v in zip(s.coords, expected)), 0)
    def div(rho):  # substitute all other coordinates first: univariate derivatives are cheap
        total = 0
        for x in s.coords:
            others = {c: v for c, v in pt.items() if c != x}
            total += sp.diff((rho * s.original[x]).subs(others), x).subs(x, pt[x])
        return total

    assert _eq(div(1 / p["g"]), 0)
    assert not _eq(div(p["g"]), 0)


def test_suslov_oracles_section12():
    s = suslov(I11=2, I22=1, I13=R(1, 2), I23=R(1, 3))
    pt = _point(s.coords, G0 + (1, -2, 0))  # coords are (gamma, omega)
    X = [s.original[x].subs(pt) for x in s.coords]
    # FORMULAS orders (omega, gamma): (-1/6, -1/6, 0, 4/3, 2/3, -5/3)
    assert X[3:] + X[:3] == [R(-1, 6), R(-1, 6), 0, R(4, 3), R(2, 3), R(-5, 3)]
    assert s.measure.subs(pt) == -6
    assert all(_eq(a, b) for a, b in zip(_field(s, pt), X))


def test_suslov_potential_oracles_section12():
    s = suslov_potential(I11=2, I22=1, U="3*gamma_z + gamma_x**2*gamma_y")
    pt = _point(s.coords, G0 + (1, -2, 0))
    expected = sp.Matrix([[0, 0, 2, 0, 3, 0], [0, 0, 1, R(-3, 2), 0, 0],
                          [-2, -1, 0, R(2, 9), R(-4, 9), 0], [0, R(3, 2), R(-2, 9), 0, 0, 0],
                          [-3, 0, R(4, 9), 0, 0, 0], [0, 0, 0, 0, 0, 0]])
    P = s.structure.matrix.subs(pt)
    assert P == expected
    assert P.rank() == 4
    assert _field(s, pt) == [R(4, 3), R(2, 3), R(-5, 3), R(19, 54), R(-46, 27), 0]
