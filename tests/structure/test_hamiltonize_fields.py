"""``pk.hamiltonize`` on vector fields written as text with parameters, against brackets known
from the literature.

Truths: the Euler top is Lie–Poisson on so(3)* with H the kinetic energy and Casimir |M|^2
(Arnold, Mathematical Methods, app. 2); in poissonkit's convention (ẋ = {x, H},
``pk.so3()`` with {m_x, m_y} = m_z) the body-frame field M × ω is ``-so3 dH``. The Lagrange top
is the heavy top on e(3)* with Casimirs (γ, γ), (γ, M) (body frame: ``-e3``, as for the heavy
top in FORMULAS.md §2). The Lotka–Volterra system ẋ_i = x_i Σ_j a_ij x_j with antisymmetric
``a`` is Hamiltonian for Plank's quadratic bracket {x_i, x_j} = a_ij x_i x_j with H = Σ x_i
(Plank, J. Math. Phys. 36 (1995) 3520), with the Casimir Π x_i^{k_i}, ``k`` in the kernel of
``a``, known only through dC/C = Σ k_i dx_i / x_i. Every bracket found is re-checked here
independently of the search: ``X == P dH`` recomputed and Jacobi by ``pk.check_jacobi``.
"""

from __future__ import annotations

import pytest
import sympy as sp

import poissonkit as pk
from poissonkit.errors import InputError, ParseError

POSITIVE = {"positive": True}
EULER = ["(1/I3 - 1/I2)*m2*m3", "(1/I1 - 1/I3)*m3*m1", "(1/I2 - 1/I1)*m1*m2"]
ENERGY = "m1**2/(2*I1) + m2**2/(2*I2) + m3**2/(2*I3)"


def _field(texts, coords, params=None):
    syms = sp.symbols(coords, real=True)
    extra = pk.structure.parsing.declare_parameters(params, syms) if params else {}
    return sp.Matrix([pk.parse_expression(t, syms, extra) for t in texts])


def _reproduces(P, H, X) -> bool:
    return sp.simplify(P.hamiltonian_vector_field(H) - X) == sp.zeros(len(X), 1)


def _relabel(P, coords):
    return P.matrix.subs(dict(zip(P.coords, sp.symbols(coords, real=True))), simultaneous=True)


def test_euler_top_with_parameters_gives_minus_so3():
    params = {"I1": POSITIVE, "I2": POSITIVE, "I3": POSITIVE}
    res = pk.hamiltonize(field=EULER, coords=["m1", "m2", "m3"], params=params,
                         hamiltonian=ENERGY, casimirs=["m1**2 + m2**2 + m3**2"], degree=1)
    assert res.found and res.parameters == () and len(res.solutions) == 1
    P = res.solutions[0]
    assert P.matrix == -_relabel(pk.so3(), ["m1", "m2", "m3"])     # unique: -so(3)
    # the field as printed, independent of the search: M x omega
    m = sp.Matrix(P.coords)
    inertia = sp.symbols("I1 I2 I3", positive=True)
    omega = sp.Matrix([m[i] / inertia[i] for i in range(3)])
    assert sp.simplify(m.cross(omega) - _field(EULER, "m1 m2 m3", params)) == sp.zeros(3, 1)
    assert _reproduces(P, res.hamiltonians[0], m.cross(omega))


def test_lagrange_top_gives_minus_e3():
    field = {
        "gamma_1": "gamma_2*M3/C - gamma_3*M2/A", "gamma_2": "gamma_3*M1/A - gamma_1*M3/C",
        "gamma_3": "(gamma_1*M2 - gamma_2*M1)/A",
        "M1": "M2*M3*(1/C - 1/A) + mu*gamma_2", "M2": "M3*M1*(1/A - 1/C) - mu*gamma_1",
        "M3": "0"}
    res = pk.hamiltonize(field=field, params={"A": POSITIVE, "C": POSITIVE, "mu": None},
                         hamiltonian="(M1**2 + M2**2)/(2*A) + M3**2/(2*C) + mu*gamma_3",
                         casimirs={"(g,g)": "gamma_1**2 + gamma_2**2 + gamma_3**2",
                                   "(g,M)": "gamma_1*M1 + gamma_2*M2 + gamma_3*M3"},
                         integrals={"M3": "M3"}, degree=1)
    assert res.found and res.parameters == () and len(res.solutions) == 1
    P = res.solutions[0]
    coords = ["gamma_1", "gamma_2", "gamma_3", "M1", "M2", "M3"]
    assert P.matrix == -_relabel(pk.e3(), coords)
    assert pk.check_jacobi(P).is_poisson
    # M3 (Lagrange's integral) is not a Casimir of e(3): no combination reported
    assert res.integral_casimirs == ((),)


def test_lotka_volterra_plank_bracket_from_a_casimir_differential():
    X = ["x1*(a*x2 + b*x3)", "x2*(-a*x1 + c*x3)", "x3*(-b*x1 - c*x2)"]
    kw = dict(field=X, coords=["x1", "x2", "x3"], params=["a", "b", "c"],
              hamiltonian="x1 + x2 + x3", degree=2)
    # C = x1^c x2^-b x3^a is not rational; its logarithmic differential is
    res = pk.hamiltonize(**kw, casimirs={"log C": ["c/x1", "-b/x2", "a/x3"]})
    assert res.found and res.parameters == ()
    x1, x2, x3 = res.problem.coords
    a, b, c = sp.symbols("a b c", real=True)
    plank = sp.Matrix([[0, a * x1 * x2, b * x1 * x3], [-a * x1 * x2, 0, c * x2 * x3],
                       [-b * x1 * x3, -c * x2 * x3, 0]])
    assert res.solutions[0].matrix == plank
    assert pk.check_jacobi(res.solutions[0]).is_poisson
    # without the Casimir the quadratic brackets reproducing X form a family containing it
    free = pk.hamiltonize(**kw)
    assert free.found and len(free.parameters) > 0


def test_hamiltonian_found_as_a_combination_of_integrals():
    # the Euler top (I = 1, 2, 3) in a time rescaled by 2: only |M|^2 and 2 x energy are given
    X = ["2*(1/3 - 1/2)*m2*m3", "2*(1 - 1/3)*m3*m1", "2*(1/2 - 1)*m1*m2"]
    ints = {"L2": "m1**2 + m2**2 + m3**2", "E": "m1**2 + m2**2/2 + m3**2/3"}
    res = pk.hamiltonize(field=X, coords=["m1", "m2", "m3"], integrals=ints, degree=1)
    assert res.found and res.problem.hamiltonian is None
    Xm = _field(X, "m1 m2 m3")
    L2, E = (pk.parse_expression(t, res.problem.coords) for t in ints.values())
    for P, H in zip(res.solutions, res.hamiltonians):
        assert _reproduces(P, H, Xm)                          # recomputed, not trusted
        assert pk.check_jacobi(P).is_poisson
        c = [s for s in H.free_symbols if s.name == "c2"]     # H in span(L2, E)
        assert sp.expand(H - L2 - (c[0] if c else 0) * E) == 0 or sp.expand(H - E) == 0
    # the chart c_L2 = 0 gives H = E; -so(3) is in its family, and there L2 is a Casimir
    k = next(i for i, H in enumerate(res.hamiltonians) if sp.expand(H - E) == 0)
    P = res.solutions[k]
    minus_so3 = -_relabel(pk.so3(), ["m1", "m2", "m3"])
    (t,) = {s for e in P.matrix for s in e.free_symbols} - set(P.coords)
    at = sp.solve(P.matrix[1, 2] - minus_so3[1, 2], t)
    assert P.matrix.subs(t, at[0]) == minus_so3
    assert len(res.integral_casimirs[k]) == 1


def test_no_combination_of_integrals_hamiltonizes_a_damped_top():
    X = ["(1/3 - 1/2)*m2*m3 - k*m1", "(1 - 1/3)*m3*m1 - k*m2", "(1/2 - 1)*m1*m2 - k*m3"]
    res = pk.hamiltonize(field=X, coords=["m1", "m2", "m3"], params={"k": POSITIVE},
                         integrals=["m1**2 + m2**2 + m3**2", "m1**2 + m2**2/2 + m3**2/3"],
                         degree=2)
    assert not res.found and res.proved_absent
    assert res.status == "no_linear_solution" and res.certificate.kind == "linear"
    assert "no bracket in this ansatz" in res.summary()


def test_bad_fields_are_typed_errors():
    coords = ["x", "y"]
    with pytest.raises(ParseError, match="'q' is not allowed.*allowed: x, y, a"):
        pk.hamiltonize(field=["q*y", "-x"], coords=coords, params=["a"], hamiltonian="x*y")
    with pytest.raises(InputError, match="not a rational function"):
        pk.hamiltonize(field=["sin(y)", "-x"], coords=coords, hamiltonian="x**2/2 - cos(y)")
    with pytest.raises(InputError, match="not closed"):
        pk.hamiltonize(field=["y", "-x"], coords=coords, hamiltonian="(x**2 + y**2)/2",
                       casimirs={"C": ["y", "0"]})
    with pytest.raises(InputError, match="nothing to search"):
        pk.hamiltonize(field=["y", "-x"], coords=coords)
    with pytest.raises(InputError, match="components"):
        pk.hamiltonize(field=["y"], coords=coords, hamiltonian="x")
    with pytest.raises(InputError, match="not both"):
        pk.hamiltonize("nh.chaplygin_ball", field=["y", "-x"], coords=coords)


def test_payload_in_a_field_is_refused_and_never_run(tmp_path):
    marker = tmp_path / "pwned"
    payload = f"__import__('pathlib').Path({str(marker)!r}).write_text('x')"
    for kw in ({"field": [payload, "x"]}, {"field": ["y", "x"], "hamiltonian": payload},
               {"field": ["y", "x"], "integrals": [payload]},
               {"field": ["y", "x"], "casimirs": {"C": [payload, "1"]}}):
        kw.setdefault("hamiltonian", "x*y")
        with pytest.raises(ParseError):
            pk.hamiltonize(coords=["x", "y"], **kw)
    assert not marker.exists()


def test_system_with_text_hamiltonian_and_integrals_by_name():
    # the same Lotka–Volterra system as a HamiltonianSystem whose fields are text
    P = pk.Bivector.from_components({(1, 2): "x1*x2", (1, 3): "-x1*x3", (2, 3): "x2*x3"},
                                    ["x1", "x2", "x3"])
    S = pk.HamiltonianSystem(P, "x1 + x2 + x3", integrals={"sum": "x1 + x2 + x3",
                                                             "prod": "x1*x2*x3"})
    res = pk.hamiltonize(S, integrals=["sum", "prod"], degree=2, casimirs=["prod"])
    assert res.found
    x1, x2, x3 = P.coords
    for Q, H in zip(res.solutions, res.hamiltonians):
        assert _reproduces(Q, H, S.vector_field()) and pk.check_jacobi(Q).is_poisson
        assert sp.expand(Q.bracket(x1 * x2 * x3, x1)) == 0         # the imposed Casimir
    # x1 x2 x3 is a Casimir of Plank's bracket for a = (1, -1, 1): that bracket is the answer,
    # and H is x1 + x2 + x3 up to the free multiple c2 of the Casimir
    plank = sp.Matrix([[0, x1 * x2, -x1 * x3], [-x1 * x2, 0, x2 * x3], [x1 * x3, -x2 * x3, 0]])
    assert [Q.matrix for Q in res.solutions] == [plank]
    (H,) = res.hamiltonians
    (c2,) = H.free_symbols - set(P.coords)
    assert sp.expand(H - (x1 + x2 + x3) - c2 * x1 * x2 * x3) == 0
    # by name in the field form: a Casimir that names one of the integrals
    res2 = pk.hamiltonize(field=list(S.vector_field()), coords=P.coords, hamiltonian=x1 + x2 + x3,
                          integrals={"prod": "x1*x2*x3"}, casimirs=["prod"], degree=2)
    assert res2.found and res2.problem.casimirs == {"prod": x1 * x2 * x3}
    assert res2.integral_casimirs[0] == ({"prod": 1},)


def test_span_search_decides_jacobi_like_the_survey_on_suslov():
    # FORMULAS.md §12: for U = 3 gamma3 + gamma1^2 gamma2 the bracket (127) is Poisson (oracle
    # matrix at one point, as in test_hamiltonize_survey); for U = gamma3^2/2 + gamma1^2 gamma2
    # no bracket of the family satisfies Jacobi. The span path reaches both verdicts itself.
    from poissonkit_nonholonomic.suslov import suslov_potential

    R = sp.Rational
    good = suslov_potential(I11=2, I22=1, U="3*gamma_z + gamma_x**2*gamma_y")
    res = pk.hamiltonize(good, integrals={"H": good.hamiltonian}, degree=3)
    assert res.found and len(res.solutions) == 1
    assert sp.expand(res.hamiltonians[0] - good.hamiltonian) == 0
    P = res.solutions[0]
    point = dict(zip(P.coords, (R(2, 3), R(1, 3), R(2, 3), 1, -2, 0)))
    oracle = sp.Matrix([[0, 0, 2, 0, 3, 0], [0, 0, 1, R(-3, 2), 0, 0],
                        [-2, -1, 0, R(2, 9), R(-4, 9), 0], [0, R(3, 2), R(-2, 9), 0, 0, 0],
                        [-3, 0, R(4, 9), 0, 0, 0], [0, 0, 0, 0, 0, 0]])
    assert P.matrix.subs(point) == oracle
    bad = suslov_potential(I11=2, I22=1, U="gamma_z**2/2 + gamma_x**2*gamma_y")
    res = pk.hamiltonize(bad, integrals={"H": bad.hamiltonian}, degree=3)
    assert res.status == "no_jacobi_solution" and res.proved_absent
    assert res.certificate.kind == "jacobi" and "unit ideal" in res.certificate.text
