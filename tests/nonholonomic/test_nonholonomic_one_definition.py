"""Each survey model is defined once (issue 28): the plugin's systems are built from the core's
brackets (``pk.chaplygin_ball``, ``poissonkit.structure.veselova``, ...) and the core's Chaplygin-ball system, so
both routes give the same brackets, Hamiltonians, Casimirs and integrals.

Truth independent of either route: the survey's family ``P_{g,f}`` (22)/(23) with the
Veselova ``g = (gamma, A gamma)^{1/2}``, ``f = g^{-2}`` (survey (65)), and the Chaplygin
``P_g = P_{g,0}`` with ``g = sqrt(1 - d (gamma, A gamma))`` (survey (38)).
"""

from __future__ import annotations

import pytest
import sympy as sp
from poissonkit_nonholonomic import ball, veselova

import poissonkit as pk
from poissonkit.structure import deformed
from poissonkit.structure.bivector import Bivector

I_SYM = sp.symbols("I1:4", positive=True)
D_SYM = sp.Symbol("d", positive=True)
A_SYM = sp.symbols("a1:4", positive=True)


def _zero(M: sp.Matrix) -> bool:
    return all(sp.simplify(e) == 0 for e in M)


@pytest.mark.parametrize("I, d", [((1, 2, 3), 1), ((sp.Rational(3, 2), 2, 5), sp.Rational(1, 3))])
def test_chaplygin_ball_both_routes_identical(I, d):
    plugin = ball.chaplygin_ball(*I, d)
    core = deformed.chaplygin_ball_system(I=I, d=d)
    bracket = pk.chaplygin_ball(I=I, d=d)
    assert isinstance(bracket, Bivector) and isinstance(plugin, pk.HamiltonianSystem)
    assert plugin.structure.matrix == bracket.matrix == core.structure.matrix
    assert sp.simplify(plugin.hamiltonian - core.hamiltonian) == 0
    assert sp.simplify(plugin.multiplier - core.multiplier) == 0
    for a, b in zip(plugin.casimirs.values(), core.casimirs.values(), strict=True):
        assert sp.simplify(a - b) == 0
    for a, b in zip(plugin.integrals.values(), core.integrals.values(), strict=True):
        assert sp.simplify(a - b) == 0
    # the survey's P_{g,0}, independently of both
    a_ = [1 / (sp.sympify(Ii) + d) for Ii in I]
    g = lambda gam: sp.sqrt(1 - d * sum(ai * gi**2 for ai, gi in zip(a_, gam)))
    assert _zero(bracket.matrix - deformed.p_gf(g, 0).matrix)


def test_chaplygin_gyrostat_both_routes_identical():
    S = (1, 0, -1)
    plugin = ball.chaplygin_gyrostat(*I_SYM, D_SYM, S=S)
    core = deformed.chaplygin_ball_system(I=I_SYM, d=D_SYM, S=S)
    assert plugin.structure.matrix == deformed.chaplygin_gyrostat(S, I=I_SYM, d=D_SYM).matrix
    assert sp.simplify(plugin.hamiltonian - core.hamiltonian) == 0
    for a, b in zip(plugin.casimirs.values(), core.casimirs.values(), strict=True):
        assert sp.simplify(a - b) == 0


@pytest.mark.parametrize("a", [(1, 2, 3), A_SYM])
def test_veselova_both_routes_identical(a):
    plugin = veselova.veselova(*a)
    bracket = deformed.veselova(a=a)
    assert plugin.structure.matrix == bracket.matrix
    g = lambda gam: sp.sqrt(sum(ai * gi**2 for ai, gi in zip(a, gam)))
    survey = deformed.p_gf(g, lambda gam: 1 / g(gam)**2, names=("gamma", "K"))
    assert _zero(bracket.matrix - survey.matrix)
    for name, value in plugin.casimirs.items():
        assert _zero(bracket.matrix * bracket.gradient(value)), name


def test_veselova_gyrostat_both_routes_identical():
    k = (1, 1, 0)
    plugin = veselova.veselova_gyrostat(*A_SYM, k=k)
    bracket = deformed.veselova_gyrostat(a=A_SYM, k=k)
    assert plugin.structure.matrix == bracket.matrix
    for name, value in plugin.casimirs.items():
        assert _zero(bracket.matrix * bracket.gradient(value)), name
