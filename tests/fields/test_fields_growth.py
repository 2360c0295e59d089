"""Tables that grow: a body launched toward the edge of a small region crosses it with a regrow
and follows the run on a large region (the independent truth) within the table's tolerance,
its energy conserved to the table's accuracy; without room the table does not grow."""

from __future__ import annotations

import numpy as np
import pytest

import poissonkit as pk
from poissonkit.errors import NonFiniteStateError
from poissonkit.numerics.fields import tabulated
from poissonkit.numerics.fields.tabulated import tabulated_field
from poissonkit.numerics.nbody import Body, NBodySystem

MU0 = 4e-7 * np.pi
M = np.array([0.0, 0.0, 1.0])  # the source: a point dipole at the origin [A m²]
TOL = 3e-5
SMALL = (np.array([-0.01, -0.01, 0.02]), np.array([0.01, 0.01, 0.04]))
LARGE = (np.array([-0.01, -0.01, 0.02]), np.array([0.025, 0.01, 0.04]))
DURATION = 0.02


def dipole_b(p):
    """The point dipole's B [T] (closed form)."""
    p = np.asarray(p, float).reshape(-1, 3)
    r = np.linalg.norm(p, axis=1)[:, None]
    n = p / r
    return MU0 / (4 * np.pi) * (3 * n * (n @ M)[:, None] - M) / r ** 3


def _run(box):
    field = tabulated_field("dipole", dipole_b, box[0].copy(), box[1].copy(), TOL)
    s = NBodySystem([Body("top", 0.01, alpha=1e5, attributes={"moment": 0.05})],
                    fields=[field])
    y0 = s.pack([[0.0, 0.0, 0.03]], [[0.01 * 0.8, 0.0, 0.0]], [[0.0, 0.0, 1.0]],
                [[0.0, 0.0, 1e-4]], si=True)
    return s, pk.solve(s, y0, DURATION, method="splitting4", step=1e-4)


@pytest.fixture(scope="module")
def runs():
    return _run(SMALL), _run(LARGE)


def test_a_body_crosses_the_edge_of_a_small_region_with_a_regrow(runs):
    (small, sol), (_, ref) = runs
    grown = sol.extra["field_regrowths"]
    assert grown and all(g.get("grown", True) for g in grown)
    assert grown[0]["field"] == "dipole" and grown[0]["old"][1][0] == pytest.approx(0.01)
    assert grown[0]["new"][1][0] > 0.01 and 0 < grown[0]["time"] < DURATION
    r = small.unpack(sol.y[-1], si=True)["r"][0]
    assert r[0] > SMALL[1][0]  # it left the first box, and the table followed
    assert small.fields[0].info["region_m"][1][0] > r[0]
    r_ref = runs[1][0].unpack(ref.y[-1], si=True)["r"][0]
    travel = np.linalg.norm(r - small.unpack(sol.y[0], si=True)["r"][0])
    # both tables are within TOL of the field: the trajectories differ by about that much
    assert np.linalg.norm(r - r_ref) < TOL * travel


def test_the_energy_is_conserved_to_the_table_accuracy(runs):
    (small, sol), _ = runs
    e = np.asarray(small.energy(sol.y))
    assert np.max(np.abs(e - e[0])) / abs(e[0]) < TOL


def test_a_table_without_room_does_not_grow(monkeypatch):
    monkeypatch.setattr(tabulated, "GROWTH_ROOM", 1)
    with pytest.raises(NonFiniteStateError):
        _run(SMALL)


def test_a_box_grows_until_it_holds_a_point_beyond_it():
    from poissonkit.numerics.fields.growth import EDGE_FRACTION, _grown

    lo, hi = _grown(SMALL[0], SMALL[1], np.array([[0.07, 0.0, 0.03]]))
    assert np.array_equal(lo, SMALL[0]) and hi[1:].tolist() == SMALL[1][1:].tolist()
    assert hi[0] - 0.07 >= EDGE_FRACTION * (hi[0] - lo[0])


def test_a_growth_the_memory_cap_refuses_is_recorded_and_the_table_kept():
    from poissonkit.numerics.fields.growth import region_watch

    field = tabulated_field("dipole", dipole_b, SMALL[0].copy(), SMALL[1].copy(), TOL)
    s = NBodySystem([Body("top", 0.01, alpha=1e5, attributes={"moment": 0.05})],
                    fields=[field])
    watch = region_watch(s)
    before = s.data.fields.params.copy()
    far = s.pack([[0.2, 0.0, 0.03]], [[0.0, 0.0, 0.0]], [[0.0, 0.0, 1.0]], [[0.0, 0.0, 0.0]],
                 si=True)
    watch.grow(far, 0.5)
    (entry,) = watch.log
    assert entry["grown"] is False and "reason" in entry and entry["time"] == 0.5
    assert not watch.watched  # left alone from then on
    assert np.array_equal(s.data.fields.params, before)
    assert s.fields[0].info["region_m"][1][0] == pytest.approx(0.01)
