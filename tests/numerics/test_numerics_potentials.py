"""compile_potential: sympy potentials differentiated once and compiled; registry entries."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from numerics_helpers import C1, C2, C3, R, dumbbell  # type: ignore[import-not-found]

from poissonkit.errors import InputError
from poissonkit.numerics.potentials import compile_potential
from poissonkit.plugin import PairPotential, Param, entries


def _entry():
    return PairPotential(
        name="test-dumbbell", doc="FORMULAS §1 eq. (16) with half-lengths l1, l2",
        params=(Param("l1", default=0.5), Param("l2", default=0.25)),
        expr=lambda p: dumbbell(p["l1"], p["l2"], 1, 2))


def test_compiled_partials_equal_sympy_derivatives():
    # FORMULAS.md §1: U of (16) at r = 7/3, c' = 1/5, c'' = -2/7, c''' = 3/11, l' = 1/2,
    # l'' = 1/3, kappa' = 2, kappa'' = 3, mu0 = 1 is 0.010084745574149882902
    entry = PairPotential(
        name="oracle-dumbbell", doc="FORMULAS §1 U of (16)",
        expr=lambda p: dumbbell(sp.Rational(1, 2), sp.Rational(1, 3), 2, 3, mu0=1))
    f = compile_potential(entry, {})
    assert f(7 / 3, 1 / 5, -2 / 7, 3 / 11)[0] == pytest.approx(0.010084745574149882902, rel=1e-14)
    U = dumbbell(sp.Rational(1, 2), sp.Rational(1, 3), 2, 3, mu0=1)
    rng = np.random.default_rng(0)
    for _ in range(5):
        pt = {R: rng.uniform(2, 4), C1: rng.uniform(-1, 1), C2: rng.uniform(-1, 1),
              C3: rng.uniform(-1, 1)}
        got = f(*(float(pt[s]) for s in (R, C1, C2, C3)))
        for k, s in enumerate((None, R, C1, C2, C3)):
            ref = float((U if s is None else sp.diff(U, s)).subs(pt).evalf(20))
            assert got[k] == pytest.approx(ref, rel=1e-12, abs=1e-15)


def test_kernels_are_cached_per_entry_and_params():
    e = _entry()
    assert compile_potential(e, {}) is compile_potential(e, {"l1": 0.5})
    assert compile_potential(e, {"l1": 0.4}) is not compile_potential(e, {})


def test_bad_potentials_are_typed_errors():
    with pytest.raises(InputError, match="unresolved"):
        compile_potential(PairPotential(name="x", doc="x", expr=lambda p: sp.Symbol("k") / R), {})
    with pytest.raises(InputError):
        compile_potential(PairPotential(name="y", doc="y"), {})


def test_registered_dipole_agrees_with_formulas_if_present():
    pots = entries("potential")
    if "dipole" not in pots:
        pytest.skip("magnets plugin does not register 'dipole' yet")
    f = compile_potential(pots["dipole"], {"moment1": 1.0, "moment2": 1.0})
    # FORMULAS §1 dipole limit: U = mu0 m1 m2 (c3 - 3 c1 c2) / (4 pi r^3), mu0 = 4 pi 1e-7
    r, c1, c2, c3 = 1.7, 0.3, -0.6, 0.2
    k = 1e-7 / r**3
    expected = (k * (c3 - 3 * c1 * c2), -3 * k * (c3 - 3 * c1 * c2) / r, -3 * k * c2,
                -3 * k * c1, k)
    assert np.allclose(f(r, c1, c2, c3), expected, rtol=1e-12)
