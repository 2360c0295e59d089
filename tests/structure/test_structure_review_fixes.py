"""Regression tests for review findings in jacobi.py, schouten.py, bivector.py, verify.

Truth: identities constructed by hand (sums of fractions minus their own common-denominator
form), exact rational evaluation at points, FORMULAS.md §2 (e(3)) and §7 (Chaplygin ball).
"""

from __future__ import annotations

import random

import pytest
import sympy as sp

import poissonkit.commands.verify as verify_cmd
from poissonkit.cli import main
from poissonkit.structure import HamiltonianSystem, Multivector, e3, so3
from poissonkit.structure.jacobi import is_zero_expression
from poissonkit.structure.schouten import is_poisson_vector_field

R = sp.Rational
x, y, z, a = sp.symbols("x y z a", real=True)


def _rational_identities(n: int, seed: int) -> list[sp.Expr]:
    rng = random.Random(seed)

    def poly():
        return sum(rng.randint(-5, 5) * x**i * y**j * z**k
                   for i in range(3) for j in range(3) for k in range(2))

    out = []
    for _ in range(n):
        s = poly() / (poly() + a) + poly() / poly() + poly() / (x - y + a)
        out.append(s - sp.together(s))  # zero, but expand() cannot see it
    return out


# ------------------------------------------------ is_zero_expression: rational fast path
@pytest.mark.timeout(600)  # hang guard only; speed is measured in benchmarks/
def test_rational_zero_test_is_exact_on_sums_of_fractions():
    zeros = _rational_identities(3, seed=1)
    assert all(e != 0 for e in zeros)
    assert all(is_zero_expression(e) for e in zeros)
    # non-zero controls: a small perturbation, checked non-zero by exact evaluation
    for e in zeros[:2]:
        bad = e + x / (y + a)
        assert bad.subs({x: 1, y: 2, z: 3, a: 5}) != 0
        assert not is_zero_expression(bad)


def test_zero_test_keeps_square_roots_and_functions_exact():
    g = sp.Function("g")(x)
    r = sp.sqrt(x**2 + 1)
    assert is_zero_expression(1 / r - r / (x**2 + 1))
    assert not is_zero_expression(1 / r - 1 / (x**2 + 1))
    assert is_zero_expression(g / (x + 1) - g * (x - 1) / (x**2 - 1))
    assert not is_zero_expression(g / (x + 1) - sp.diff(g, x) / (x + 1))
    assert is_zero_expression(sp.sin(x) ** 2 + sp.cos(x) ** 2 - 1)


# ------------------------------------------------ Poisson vector fields with rational components
def test_poisson_vector_field_with_rational_components():
    P = so3()
    x1, x2, x3 = P.coords
    # Hamiltonian fields are Poisson: L_{X_H} P = 0 for every H, here rational
    H = 1 / (x1 + 2 * x2) + x3 / (x1 - x3)
    X = Multivector.vector_field(list(P.hamiltonian_vector_field(H)), P.coords)
    assert is_poisson_vector_field(P, X)
    # Y = x1/(x2 + 1) d/dx1 is not: (L_Y P)^{12} = Y(x3) - P^{k2} d_k Y^1 - P^{1k} d_k Y^2
    # = 0 - (P^{12} d_1 Y^1 + P^{32} d_3 Y^1 + P^{22} d_2 Y^1) = -x3/(x2 + 1) != 0
    Y = Multivector.vector_field([x1 / (x2 + 1), 0, 0], P.coords)
    assert not is_poisson_vector_field(P, Y)


# ------------------------------------------------ bracket / Hamiltonian field with square roots
@pytest.mark.timeout(600)  # hang guard only
def test_chaplygin_vector_field_matches_formulas_oracle_without_expanding():
    from poissonkit.structure.deformed import chaplygin_ball_system

    S = chaplygin_ball_system(I=(1, 2, 3), d=1)
    X = S.vector_field()
    gam, M = S.structure.coords[:3], S.structure.coords[3:]
    pt = dict(zip(gam + M, [R(2, 3), R(1, 3), R(2, 3), 1, -2, R(1, 2)]))
    # FORMULAS.md §7: X equals the original equations (34) (omega from (35)) at the point
    orig = [sp.radsimp(S.original[c].subs(pt)) for c in S.structure.coords]
    assert [sp.radsimp(e.subs(pt)) for e in X] == orig
    # the bracket agrees with the Hamiltonian field: X_i = N {x_i, H}
    for i in (0, 4):
        lhs = S.multiplier * S.structure.bracket(S.structure.coords[i], S.hamiltonian)
        assert sp.radsimp((lhs - X[i]).subs(pt)) == 0


def test_polynomial_brackets_are_still_expanded():
    P = e3()
    nu, m = P.coords[:3], P.coords[3:]
    H = sum(c**2 for c in m) / 2 + nu[2] * (nu[0] + m[1])
    X = P.hamiltonian_vector_field(H)
    assert all(c == sp.expand(c) for c in X)
    b = P.bracket(m[0] * (nu[1] + 1), H)
    assert b == sp.expand(b)


# ------------------------------------------------ poissonkit verify: failed claims exit non-zero
def _e3_system(**claims):
    P = e3()
    nu, m = P.coords[:3], P.coords[3:]
    return HamiltonianSystem(P, sum(c**2 for c in m) / 2 + nu[2], **claims), nu, m


@pytest.mark.parametrize("kind", ["casimir", "integral", "measure", "original", "none"])
def test_verify_exit_code_reflects_claimed_properties(kind, monkeypatch, capsys):
    P = e3()
    nu, m = P.coords[:3], P.coords[3:]
    claims = {
        "casimir": {"casimirs": {"C": m[0]}},           # {m_y, m_x} = -m_z: not a Casimir
        "integral": {"integrals": {"F": m[0]}},         # X(m_x) = -nu_y != 0 (FORMULAS §2)
        "measure": {"measure": nu[0]},                  # div(nu_x X) = X(nu_x) != 0
        "original": {"original": {c: 0 for c in P.coords}},
        "none": {"integrals": {"H": sum(c**2 for c in m) / 2 + nu[2]},
                 "casimirs": {"C": sum(c**2 for c in nu)}},
    }[kind]
    S = HamiltonianSystem(P, sum(c**2 for c in m) / 2 + nu[2], **claims)
    monkeypatch.setattr(verify_cmd, "load_target", lambda target, params=(): ("t", "doc", S))
    code = main(["verify", "t", "--casimir-degree", "1"])
    out = capsys.readouterr().out
    if kind == "none":
        assert code == 0 and "FAILED" not in out
    else:
        assert code == 1 and ": FAILED" in out
