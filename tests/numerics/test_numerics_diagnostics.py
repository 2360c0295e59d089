"""The one definition of each run diagnostic (:mod:`poissonkit.numerics.diagnostics`).

Truth: hand-made trajectories of a toy system whose energy, Casimirs and body momenta are read
straight from chosen state entries, so every expected figure below is written out by hand
(mostly exact binary fractions); and a real symmetric n-body start, where the total momentum
P(0) cancels to round-off while single bodies carry momentum of order one.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from poissonkit.errors import DimensionError, InputError
from poissonkit.numerics import diagnostics as dg
from poissonkit.numerics.solution import Solution


class Toy:
    """State ``[H, C1, C2, r1, p1, r2, p2, m]`` (3-vectors from index 3): two bodies, one spin.

    ``energy`` and ``casimirs`` return the stored entries; the momenta are computed from the
    bodies as a system of bodies does.
    """

    def energy(self, y):
        return np.asarray(y, dtype=float)[..., 0]

    def casimirs(self, y):
        return np.asarray(y, dtype=float)[..., 1:3]

    def unpack(self, y):
        y = np.asarray(y, dtype=float)
        v = y[..., 3:].reshape(y.shape[:-1] + (5, 3))
        return {"r": v[..., [0, 2], :], "p": v[..., [1, 3], :], "m": v[..., 4:5, :]}

    def linear_momentum(self, y):
        return self.unpack(y)["p"].sum(axis=-2)

    def angular_momentum(self, y):
        u = self.unpack(y)
        return np.cross(u["r"], u["p"]).sum(axis=-2) + u["m"].sum(axis=-2)


class ScaledToy(Toy):
    """The toy with declared natural Casimir sizes 1 and 2."""

    def casimir_scales(self, y):
        return np.array([1.0, 2.0])


class EnergyOnly:
    def energy(self, y):
        return np.asarray(y, dtype=float)[..., 0]


def state(H=1.0, C=(0.0, 0.0), r1=(0, 0, 0), p1=(0, 0, 0), r2=(0, 0, 0), p2=(0, 0, 0),
          m=(0, 0, 0)):
    return np.array([H, *C, *r1, *p1, *r2, *p2, *m], dtype=float)


def rows(*states):
    return np.vstack(states)


# --------------------------------------------------------------------------- energy
def test_energy_error_is_abs_change_over_abs_initial_energy():
    d = dg.energy_error(Toy(), rows(state(H=-4.0), state(H=-3.0), state(H=-4.5)))
    np.testing.assert_array_equal(d.absolute, [0.0, 1.0, 0.5])
    np.testing.assert_array_equal(d.relative, [0.0, 0.25, 0.125])
    assert d.scale == 4.0
    assert d.report() == {"max_abs_energy_error": 1.0, "max_rel_energy_error": 0.25,
                          "energy_error_scale": 4.0}


def test_energy_error_with_zero_initial_energy_is_absolute_with_scale_one():
    d = dg.energy_error(Toy(), rows(state(H=0.0), state(H=0.001953125), state(H=-0.00390625)))
    assert d.scale == dg.SCALE_FLOOR == 1.0
    assert d.max_relative == d.max_absolute == 0.00390625


def test_energy_error_of_a_series_is_the_same_definition():
    assert dg.energy_error_of([8.0, 9.0, 6.0]).report() == {
        "max_abs_energy_error": 2.0, "max_rel_energy_error": 0.25, "energy_error_scale": 8.0}


def test_a_constant_trajectory_has_exact_zero_errors():
    s = state(H=3.0, C=(2.0, 0.5), r1=(1, 0, 0), p1=(0, 1, 0), m=(0, 0, 2))
    rep = dg.report(dg.drifts(Toy(), rows(s, s, s)))
    assert {k: v for k, v in rep.items() if k.startswith("max_")} == {
        f"max_{kind}_{q}": 0.0 for q in dg.QUANTITIES for kind in ("abs", "rel")}


# --------------------------------------------------------------------------- Casimirs
def test_casimir_drift_without_declared_scales_divides_by_abs_initial_value():
    # C1(0) = 3 (scale 3); C2(0) = 0 exactly (scale falls back to 1)
    d = dg.casimir_drift(Toy(), rows(state(C=(3.0, 0.0)), state(C=(3.75, 0.0009765625))))
    assert d.scale == (3.0, 1.0)
    np.testing.assert_array_equal(d.absolute, [0.0, 0.75])  # max over Casimirs
    np.testing.assert_array_equal(d.relative, [0.0, 0.25])  # max(0.75 / 3, 2**-10 / 1)


def test_casimir_with_zero_initial_value_drifts_absolutely():
    d = dg.casimir_drift(Toy(), rows(state(C=(1.0, 0.0)), state(C=(1.0, -0.125))))
    assert d.max_relative == d.max_absolute == 0.125


def test_declared_casimir_scales_win():
    d = dg.casimir_drift(ScaledToy(), rows(state(C=(3.0, 0.0)), state(C=(3.5, 0.75))))
    assert d.scale == (1.0, 2.0)
    assert d.max_absolute == 0.75
    assert d.max_relative == 0.5  # max(0.5 / 1, 0.75 / 2)


def test_system_without_casimirs_reports_none():
    class NoCasimirs(Toy):
        def casimirs(self, y):
            return np.zeros(np.asarray(y).shape[:-1] + (0,))

    y = rows(state(), state())
    assert dg.casimir_drift(NoCasimirs(), y) is None
    assert "casimir_drift" not in dg.drifts(NoCasimirs(), y)
    sol = Solution(t=np.arange(2.0), y=y, method="toy", steps=1, wall_time=0.0,
                   system=NoCasimirs())
    np.testing.assert_array_equal(sol.casimir_drift(), [0.0, 0.0])


# --------------------------------------------------------------------------- linear momentum
def test_symmetric_start_is_measured_against_the_single_body_momenta():
    # P(0) = 2**-52 (round-off), |p1| = 1.25; later P changes by 2**-45 ≈ 2.8e-14
    y0 = state(p1=(0.75, 1.0, 0.0), p2=(-0.75, -1.0 + 2.0**-52, 0.0))
    y1 = state(p1=(0.75, 1.0, 0.0), p2=(-0.75, -1.0 + 2.0**-52 + 2.0**-45, 0.0))
    d = dg.linear_momentum_drift(Toy(), rows(y0, y1))
    assert d.scale == 1.25
    assert d.max_absolute == 2.0**-45
    assert d.max_relative == 2.0**-45 / 1.25  # ~2.3e-14
    assert 2.0**-45 / 2.0**-52 == 128.0  # what dividing by |P(0)| reported


def test_bodies_at_rest_give_scale_one():
    d = dg.linear_momentum_drift(Toy(), rows(state(), state(p1=(0.0, 0.0, 0.5))))
    assert d.scale == 1.0 and d.max_relative == d.max_absolute == 0.5


# --------------------------------------------------------------------------- angular momentum
def test_angular_momentum_scale_sums_the_magnitudes_of_the_terms():
    # r1 × p1 = (0, 0, 2), r2 × p2 = (0, 0, -12), m = (0, 0, 5): j = (0, 0, -5), scale 19
    kw = dict(r1=(1, 0, 0), p1=(0, 2, 0), r2=(0, 3, 0), p2=(4, 0, 0))
    y0, y1 = state(m=(0, 0, 5), **kw), state(m=(0, 0.0009765625, 5), **kw)
    d = dg.angular_momentum_drift(Toy(), rows(y0, y1))
    assert d.scale == 19.0
    assert d.max_absolute == 0.0009765625
    assert d.max_relative == 0.0009765625 / 19.0


def test_zero_total_angular_momentum_still_has_a_physical_scale():
    # j(0) = 2 - 12 + 10 = 0, yet the terms are of size 24
    kw = dict(r1=(1, 0, 0), p1=(0, 2, 0), r2=(0, 3, 0), p2=(4, 0, 0))
    y0, y1 = state(m=(0, 0, 10), **kw), state(m=(0, 0, 10.5), **kw)
    d = dg.angular_momentum_drift(Toy(), rows(y0, y1))
    assert d.scale == 24.0 and d.max_relative == 0.5 / 24.0


def test_spin_entries_m1_m2_count_and_axes_do_not():
    class TwoBodyLike:
        def unpack(self, y):
            return {"r": np.array([2.0, 0, 0]), "p": np.array([0, 3.0, 0]),
                    "nu1": np.array([0, 0, 1.0]), "m1": np.array([0, 0, 4.0]),
                    "nu2": np.array([0, 0, -1.0]), "m2": np.array([0, 0, -7.0])}

    assert dg.angular_momentum_scale(TwoBodyLike(), np.zeros(18)) == 6.0 + 4.0 + 7.0


# --------------------------------------------------------------------------- shapes, errors
def test_only_the_quantities_a_system_defines_are_reported():
    found = dg.drifts(EnergyOnly(), rows(state(H=2.0), state(H=3.0)))
    assert list(found) == ["energy_error"]
    assert isinstance(Toy(), dg.HasBodyMomenta) and not isinstance(EnergyOnly(), dg.HasBodyMomenta)


def test_bad_trajectories_raise_typed_errors():
    with pytest.raises(DimensionError):
        dg.energy_error(Toy(), state())  # one state, not rows
    with pytest.raises(InputError):
        dg.energy_error(Toy(), np.zeros((0, 18)))


# --------------------------------------------------------------------------- Solution
def test_solution_methods_and_summary_use_the_one_definition():
    kw = dict(r1=(1, 0, 0), r2=(0, 3, 0), p2=(4, 0, 0))
    y = rows(state(H=-4.0, C=(3.0, 0.0), p1=(0, 2, 0), m=(0, 0, 5), **kw),
             state(H=-3.0, C=(3.75, 0.0), p1=(0, 2.5, 0), m=(0, 0, 5), **kw))
    sol = Solution(t=np.arange(2.0), y=y, method="toy", steps=1, wall_time=0.0, system=Toy())
    s = sol.summary()
    assert s["max_rel_energy_error"] == 0.25 and s["final_rel_energy_error"] == 0.25
    assert s["max_rel_casimir_drift"] == 0.25
    assert s["linear_momentum_drift_scale"] == 4.0  # largest |p_i(0)|: |p2| = 4
    assert s["max_rel_linear_momentum_drift"] == 0.5 / 4.0
    # |Δj| = |r1 × Δp1| = 0.5; scale 2 + 12 + 5 = 19
    assert s["angular_momentum_drift_scale"] == 19.0
    assert s["max_rel_angular_momentum_drift"] == 0.5 / 19.0
    np.testing.assert_array_equal(sol.momentum_drift(), sol.linear_momentum_drift())
    assert np.max(sol.angular_momentum_drift()) == s["max_rel_angular_momentum_drift"]
    assert "max |Δj|/(Σ|r×p|+Σ|m|)" in str(sol)


def test_symmetric_nbody_start_reports_a_round_off_momentum_drift():
    """Three gravitating bodies whose momenta cancel: P(0) is round-off, |ΔP| too; the relative
    drift must be round-off as well (dividing by |P(0)| reported numbers of order 10-100)."""
    from poissonkit.numerics import AllPairs, Body, NBodySystem, solve

    system = NBodySystem([Body(f"s{k}", 1.0) for k in range(3)], [AllPairs("gravity")])
    pos = np.array([[1.0, 0.0, 0.1], [-0.5, 0.9, 0.0], [-0.5, -0.8, -0.1]])
    mom = np.array([[0.1, 0.7, 0.0], [0.2, -0.4, 0.05], [-0.3, -0.3, -0.05]])  # Σ p ≈ 8e-17
    sol = solve(system, system.pack(pos, mom), 2.0, "splitting4", step=0.01)
    s = sol.summary()
    P = system.linear_momentum(sol.y)
    dP = float(np.max(np.linalg.norm(P - P[0], axis=1)))
    assert 0 < np.linalg.norm(P[0]) < 1e-15 and dP / np.linalg.norm(P[0]) > 1  # the old figure
    assert s["max_abs_linear_momentum_drift"] == dP
    assert s["linear_momentum_drift_scale"] == pytest.approx(
        max(np.linalg.norm(mom, axis=1)), rel=1e-15)
    assert s["max_rel_linear_momentum_drift"] < 1e-13
    assert math.isfinite(s["max_rel_angular_momentum_drift"])
    assert s["max_rel_angular_momentum_drift"] < 1e-12
