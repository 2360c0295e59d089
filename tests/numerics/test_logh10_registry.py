"""``logh10`` in the registry is ``TimeTransformedSplitting(order=10)``, and the close-approach
preset is ``logh10`` with options a scene can give (the order itself is checked against the
exact Kepler orbit in test_integrator_order.py)."""

from __future__ import annotations

import numpy as np

import poissonkit as pk
from poissonkit.numerics import solve
from poissonkit.numerics.integrators.time_transformed import TimeTransformedSplitting


def _attractive(pair):
    return pair.pack([1.5, 0, 0], [0, 0.3, 0], [1, 0, 0], [0, 0, 0.2], [1, 0, 0], [0.1, 0, 0])


def test_the_entry_declares_order_10_and_the_logh_options():
    entry = pk.integrators()["logh10"]
    assert entry.order == 10 and entry.family == "time_transformed"
    assert [p.name for p in entry.params] == [p.name for p in pk.integrators()["logh8"].params]
    assert "for_close_approach" in entry.doc and "track_kinetic" in entry.doc


def test_the_close_approach_preset_is_logh10_with_options(dipole_pair):
    y0 = _attractive(dipole_pair)
    preset = TimeTransformedSplitting.for_close_approach(dipole_pair, y0)
    v0 = float(dipole_pair.kernels.forces(np.array(y0, dtype=float), dipole_pair.data,
                                          dipole_pair.work()))
    assert preset.name == "logh10" and v0 < 0
    by_object = solve(dipole_pair, y0, 2.0, preset, step=0.05)
    by_name = solve(dipole_pair, y0, 2.0, "logh10", step=0.05,
                    options={"track_kinetic": True, "shift": 3 * abs(v0)})
    assert by_name.method == "logh10"
    np.testing.assert_array_equal(by_name.y, by_object.y)
    np.testing.assert_array_equal(by_name.t, by_object.t)
