"""Units: Scales conversions and SI-scaled systems equal their nondimensional form."""

from __future__ import annotations

import numpy as np
import pytest
from numerics_helpers import BOUND, orbit_state  # type: ignore[import-not-found]

from poissonkit.errors import InputError, UnknownNameError
from poissonkit.numerics import Scales, TwoBodySystem, solve


def test_derived_units_follow_from_length_mass_time():
    s = Scales(length=0.02, mass=1e-4, time=0.5)
    assert s.unit("energy") == pytest.approx(1e-4 * 0.02**2 / 0.5**2)
    assert s.unit("alpha") == pytest.approx(1 / (1e-4 * 0.02**2))
    assert s.to_si(s.to_internal(3.7, "momentum"), "momentum") == pytest.approx(3.7)
    e = Scales.from_energy(0.02, 1e-4, 2e-6)
    assert e.unit("energy") == pytest.approx(2e-6)
    with pytest.raises(InputError):
        Scales(length=-1.0)
    with pytest.raises(UnknownNameError):
        s.unit("colour")


def test_si_scaled_two_body_system_matches_the_nondimensional_one(dipole_pair):
    # the same physics written in SI with L = 0.01 m, M = 1e-4 kg, T = 0.2 s: the potential
    # scales as energy E = M L^2 / T^2, so U_SI(r_SI) = E * U(r_SI / L)
    import sympy as sp

    sc = Scales(0.01, 1e-4, 0.2)
    r = sp.Symbol("r", real=True)
    U_si = sc.energy * BOUND.subs(r, r / sc.length)
    si_sys = TwoBodySystem(None, None, 3.0 / sc.unit("inertia"), 5.0 / sc.unit("inertia"), U_si,
                           reduced_mass=2.0 * sc.mass, scales=sc)
    y0 = orbit_state()
    assert np.allclose(si_sys.rhs(0, y0), dipole_pair.rhs(0, y0), rtol=1e-12, atol=1e-14)
    si_state = si_sys.unpack(y0, si=True)
    assert np.allclose(si_state["r"], y0[:3] * 0.01)
    packed = si_sys.pack(*(si_state[k] for k in ("r", "p", "nu1", "m1", "nu2", "m2")), si=True)
    assert np.allclose(packed, y0, rtol=1e-14)
    a = solve(si_sys, y0, 1.0, "splitting4", step=0.05).y[-1]
    b = solve(dipole_pair, y0, 1.0, "splitting4", step=0.05).y[-1]
    assert np.allclose(a, b, rtol=1e-10, atol=1e-12)
