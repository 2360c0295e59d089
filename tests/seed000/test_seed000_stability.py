"""The seed's stability statement: one stable and one unstable parameter choice.

Axes tilted by 0.02 rad. Without spin the magnets turn towards each other and touch within a
fraction of a period; with spin ratio alpha|m|/omega_orb = 20 the orbit stays within 2 % of
R_orb for 20 periods. The contact time is cross-checked with an independent integrator
(scipy DOP853 at tol 1e-11 on the same equations).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from poissonkit_magnets import seed000
from poissonkit.numerics.solver import solve


def test_axis_distance_geometry():
    l = 1.0
    side = np.zeros(18)
    side[[0, 8, 14]] = [1.0, 1.0, -1.0]  # side by side at distance 1
    coax = np.zeros(18)
    coax[[0, 6, 12]] = [3.0, 1.0, 1.0]  # head to tail, gap 1
    cross = np.zeros(18)
    cross[[0, 6, 13]] = [1.0, 1.0, 1.0]  # crossing segments
    assert np.allclose(seed000.axis_distance(np.stack([side, coax, cross]), l), [1.0, 1.0, 0.0])


def test_spinning_orbit_is_stable():
    fate = seed000.orbit_fate(spin_ratio=20.0, tilt=0.02, periods=20)
    assert fate.kind == "bounded"
    assert fate.t_end == pytest.approx(20.0)
    assert 0.98 < fate.r_min and fate.r_max < 1.0 + 1e-6
    assert fate.max_energy_error < 1e-12


def test_orbit_without_spin_collides_and_dop853_agrees_on_when():
    fate = seed000.orbit_fate(spin_ratio=0.0, tilt=0.02, periods=5)
    assert fate.kind == "collision"
    assert fate.t_end < 0.5
    assert fate.max_energy_error < 1e-5  # the run up to contact is resolved
    # independent integrator: time at which the axis segments come within 2a
    spec = seed000.default_run(periods=0.5, spin_ratio=0.0, tilt=0.02)
    sol = solve(spec.system, spec.y0, spec.t_end, method="dop853", tol=1e-11,
                options={"max_step": 2 * math.pi / 2000})
    table = seed000.parameter_table()
    contact = float(2 * table.a / seed000.circular_orbit(table=table).radius)
    gap = seed000.axis_distance(sol.y, seed000.nondimensional_parameters()["half_length1"])
    k = int(np.argmax(gap < contact))
    assert gap[k] < contact
    t_contact = sol.t[k] / (2 * math.pi)
    # orbit_fate saves every T/400: it reports the last state before contact
    assert abs(t_contact - fate.t_end) < 2.0 / 400
