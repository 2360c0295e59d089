"""The outcome registry on single seed-orbit runs, against the seed's own numbers.

Truth: the seed prints P_orb = 6.4910356642626862477e-4 N s for the circular orbit of radius
R_orb = 10 mm (see tests/seed000/test_seed000_table.py); the total angular momentum of that
orbit is R_orb P_orb (the antiparallel spins cancel); without spin the tilted pair falls into
contact (the seed's "stable only with spin", tests/seed000/test_seed000_stability.py); started
30 % wide of the circle with the circular momentum it starts at its closest point.
"""

from __future__ import annotations

import math

import pytest

from poissonkit.errors import UnknownNameError
from poissonkit.sweeps.outcomes import DEFAULT_OUTCOMES, OUTCOMES, reduce_run, resolve_outcomes
from poissonkit.sweeps.targets import FATES
from poissonkit_magnets.seed000_sweep import SeedScene

P_ORB = 6.4910356642626862477e-4  # N s, seed 000
R_ORB = 0.01  # m


@pytest.fixture(scope="module")
def seed():
    scene = SeedScene(periods=4)
    return scene, scene.prepare()


def test_registry_entries_are_documented_and_typed():
    for name, o in OUTCOMES.items():
        assert o.name == name and o.description and o.units
        assert o.dtype in ("i1", "f8")
    assert "megno" in OUTCOMES and "megno" not in DEFAULT_OUTCOMES
    assert resolve_outcomes("min_distance") == ("fate", "min_distance")
    with pytest.raises(UnknownNameError, match="available"):
        resolve_outcomes(["fate", "lyapunov_colour"])


def test_circular_orbit_outcomes_match_the_seed(seed):
    scene, prep = seed
    out = reduce_run(scene.run(prep, {"spin_ratio": 20.0, "tilt": 0.0}), list(OUTCOMES))
    assert FATES[out["fate"]] == "bounded" and math.isnan(out["fate_time"])
    T_orb = float(prep["orbit"].period)
    assert out["end_time"] == pytest.approx(4 * T_orb, rel=1e-12)
    assert out["min_distance"] == pytest.approx(R_ORB, rel=1e-7)
    assert out["final_angular_momentum"] == pytest.approx(R_ORB * P_ORB, rel=1e-9)
    assert out["max_rel_energy_error"] < 1e-10
    assert out["max_rel_casimir_drift"] < 1e-12 and out["max_rel_angular_momentum_drift"] < 1e-12


def test_no_spin_collides_and_wide_start_escapes(seed):
    scene, prep = seed
    fall = reduce_run(scene.run(prep, {"spin_ratio": 0.0, "tilt": 0.02}), DEFAULT_OUTCOMES)
    assert FATES[fall["fate"]] == "collision"
    assert 0 < fall["fate_time"] <= fall["end_time"] + 1e-15
    assert fall["min_distance"] < R_ORB
    wide = reduce_run(scene.run(prep, {"spin_ratio": 20.0, "radius_factor": 1.3}),
                      DEFAULT_OUTCOMES)
    assert FATES[wide["fate"]] == "escape"
    assert wide["min_distance"] == pytest.approx(1.3 * R_ORB, rel=1e-6)  # it starts at apsis


def test_other_orbit_radius_is_the_circular_orbit_of_that_radius(seed):
    # truth: seed000.circular_orbit balances centrifugal and magnetic force at 20 mm (mpmath)
    from poissonkit_magnets import seed000

    scene, prep = seed
    out = reduce_run(scene.run(prep, {"spin_ratio": 20.0, "orbit_radius": 1.0}),
                     DEFAULT_OUTCOMES)
    orbit = seed000.circular_orbit(0.02)
    assert FATES[out["fate"]] == "bounded"
    assert out["end_time"] == pytest.approx(4 * float(orbit.period), rel=1e-12)
    assert out["min_distance"] == pytest.approx(0.02, rel=1e-7)
    assert out["final_angular_momentum"] == pytest.approx(0.02 * float(orbit.momentum), rel=1e-9)
