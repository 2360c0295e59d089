"""The seed 000 parameter table and circular orbit, against the seed's printed Maple output.

Printed values: seed text ``zub-magnetic-rigid-bodies.txt``, "Parameters of cylindrical magnets
(dumb-bells)" and ``P_orb`` (Maple, 20 digits). The force in the orbit test is recomputed
independently as an explicit Coulomb sum over the four pole pairs in 3-D (mpmath).
"""

from __future__ import annotations

import mpmath
import pytest

from poissonkit_magnets import seed000
from poissonkit.errors import InputError

# The seed's printed values (copied from the seed text, not from poissonkit).
PRINTED = {
    "V": "0.98174770424681038703e-7",
    "m_cyl": "0.00076576320931251210188",
    "m": "0.00038288160465625605093",
    "I_perp": "0.25824566564054770102e-7",
    "I_axial": "0.59825250727540007960e-9",
    "alpha": "0.38722818348939904682e8",
    "J_Fe": "0.15835916837643585909e7",
    "mu": "0.15546875",
}
P_ORB_PRINTED = "0.00064910356642626862477"


@pytest.fixture(autouse=True)
def _forty_digits():
    """Compare at 40 digits (mpf arithmetic outside workdps would round to 15)."""
    with mpmath.workdps(40):
        yield


@pytest.mark.parametrize("name", sorted(PRINTED))
def test_table_entry_matches_seed_to_printed_precision(name):
    table = seed000.parameter_table(dps=40)
    got = getattr(table, name)
    want = mpmath.mpf(PRINTED[name])
    # 20 printed digits: agreement to the last printed digit (Maple rounds its 20th digit)
    assert abs(got - want) / want < 2e-19


def test_inertia_convention_is_solid_cylinder_about_centre():
    # transverse axis: m (3a^2 + h^2)/12; axial: m a^2/2. The thin-rod m h^2/12 misses the seed.
    t = seed000.parameter_table(dps=40)
    rod = t.m_cyl * t.h**2 / 12
    assert abs(rod - mpmath.mpf(PRINTED["I_perp"])) / rod > 1e-3
    assert abs(t.I_perp - t.m_cyl * (3 * t.a**2 + t.h**2) / 12) == 0


def test_reduced_mass_is_carried_at_full_precision():
    t = seed000.parameter_table(dps=40)
    assert t.m == t.m_cyl / 2
    assert seed000.parameter_table(dps=40).as_floats()["m"] == float(t.m_cyl / 2)


def _coulomb_force_x(R, mu, l, mu0):
    """x-force on body 2 at (R, 0, 0), axes +z (body 1) and -z (body 2): explicit pole sum."""
    kappa = mu / (2 * l)
    poles1 = [((0, 0, l), kappa), ((0, 0, -l), -kappa)]
    poles2 = [((R, 0, -l), kappa), ((R, 0, l), -kappa)]  # body 2's +nu end is at -z
    fx = 0
    for (x1, q1) in poles1:
        for (x2, q2) in poles2:
            d = [b - a for a, b in zip(x1, x2)]
            dist = mpmath.sqrt(sum(c * c for c in d))
            fx += mu0 * q1 * q2 / (4 * mpmath.pi) * d[0] / dist**3
    return fx


def test_orbit_momentum_reproduces_seed_P_orb():
    with mpmath.workdps(40):
        t = seed000.parameter_table(dps=40)
        orbit = seed000.circular_orbit("0.01", table=t, configuration="antiparallel")
        assert abs(orbit.momentum - mpmath.mpf(P_ORB_PRINTED)) / orbit.momentum < 1e-18
        # independent force: Coulomb sum over poles, centripetal balance P^2/(m R) = -F_x
        fx = _coulomb_force_x(mpmath.mpf("0.01"), t.mu, t.l, t.mu0)
        assert fx < 0  # attraction
        P = mpmath.sqrt(t.m * mpmath.mpf("0.01") * (-fx))
        assert abs(P - mpmath.mpf(P_ORB_PRINTED)) / P < 1e-18
        # period: T = 2 pi R m / P
        assert abs(orbit.period - 2 * mpmath.pi * mpmath.mpf("0.01") * t.m / P) / orbit.period < 1e-30


def test_orbit_radius_recovered_from_printed_momentum():
    r = seed000.find_orbit_radius(P_ORB_PRINTED, table=seed000.parameter_table(dps=40))
    assert abs(r - mpmath.mpf("0.01")) < 1e-20


def test_only_the_antiparallel_configuration_gives_a_round_radius():
    # coaxial (head to tail) balances at an irrational-looking radius between 30 and 50 mm
    r = seed000.find_orbit_radius(P_ORB_PRINTED, table=seed000.parameter_table(dps=40),
                                  configuration="coaxial", bracket=(0.03, 0.05))
    assert 0.03 < r < 0.05
    assert abs(r * 1000 - mpmath.nint(r * 1000)) > 0.1  # not a whole number of millimetres


def test_parallel_pair_repels_so_has_no_orbit():
    with pytest.raises(InputError, match="repels"):
        seed000.circular_orbit("0.01", configuration="parallel")


def test_bad_geometry_is_a_typed_error():
    with pytest.raises(InputError, match="diameter"):
        seed000.parameter_table(diameter="-1")
    with pytest.raises(InputError, match="height"):
        seed000.parameter_table(height="abc")
    with pytest.raises(InputError):
        seed000.initial_state(tilt=float("nan"))


def test_initial_state_is_the_orbit_in_internal_units():
    import numpy as np

    y0 = seed000.initial_state(spin_ratio=20.0)
    sc = seed000.scales()
    # radius R_orb and momentum P_orb, converted back to SI
    assert np.isclose(np.linalg.norm(y0[:3]) * sc.length, 0.01, rtol=1e-15)
    assert np.isclose(np.linalg.norm(y0[3:6]) * sc.unit("momentum"), 6.4910356642626862477e-4,
                      rtol=1e-14)
    # unit axes, antiparallel, normal to the orbital plane; spin along each axis
    assert np.allclose(y0[6:9], [0, 0, 1]) and np.allclose(y0[12:15], [0, 0, -1])
    alpha = seed000.nondimensional_parameters()["alpha1"]
    assert np.isclose(alpha * np.linalg.norm(y0[9:12]), 20.0)
    assert np.isclose(np.dot(y0[9:12], y0[6:9]), np.linalg.norm(y0[9:12]))
