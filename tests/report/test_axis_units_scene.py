"""Figures and the 3D view speak the scene's ``[units]``.

Truths used: bodies placed by hand at 5.2 AU and 9.5 AU from the Sun must be drawn at 5.2 and
9.5 on an axis labelled AU; 100 days are 100/365.25 Julian years; in N-body units (G = 1) the
numbers are drawn as they are, labelled L and T; an SI magnet scene keeps millimetres and
seconds. No integration is run: the states are written by hand.
"""

from __future__ import annotations

import re

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import pytest

from poissonkit.numerics import AllPairs, Body, NBodySystem
from poissonkit.numerics.unitsystem import UnitSystem
from poissonkit.report.axis_units import (
    dataset_units,
    quantity_unit,
    run_axis_units,
    scene_units,
)
from poissonkit.report.figures import RunData, figures_for
from poissonkit.report.summary import Diagnostics

AU, DAY, YEAR = 149_597_870_700.0, 86_400.0, 365.25 * 86_400.0
AU_YR = UnitSystem("AU", "yr", "Msun")


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def _run(masses, names, units: UnitSystem | None, days: float = 100.0) -> RunData:
    system = NBodySystem([Body(n, m) for n, m in zip(names, masses)],
                         [AllPairs("gravity", {"G": 6.674e-11})])
    t = np.linspace(0.0, days * DAY, 40)
    r0 = np.array([[0.0, 0.0, 0.0], [5.2 * AU, 0.0, 0.0], [0.0, 9.5 * AU, 0.0]])[:len(masses)]
    y = np.array([system.pack(r0, np.zeros_like(r0), si=True)] * len(t))
    meta = {} if units is None else {"units": units.as_dict()}
    return RunData(system, t, y, Diagnostics(np.zeros(len(t)), {}, np.zeros((len(t), 3))),
                   metadata=meta)


def _units_in_labels(run: RunData) -> dict[str, set[str]]:
    """``{figure: the bracketed units of its axis labels}``."""
    out = {}
    for entry in figures_for(run):
        labels = [lab for ax in entry.draw(run).axes for lab in (ax.get_xlabel(), ax.get_ylabel())]
        out[entry.name] = {m for lab in labels for m in re.findall(r"\[([^\]]+)\]", lab)}
    return out


@pytest.mark.parametrize("masses, names", [
    ([2e30, 1.9e27, 5.7e26], ["sun", "jupiter", "saturn"]),  # planetary
    ([2e30, 1.5e30, 1e25], ["a", "b", "p"])])  # N bodies, none dominant
def test_every_figure_of_an_au_year_scene_reads_au_and_years(masses, names):
    run = _run(masses, names, AU_YR)
    found = _units_in_labels(run)
    assert found  # figures were drawn
    allowed = {"AU", "yr", "deg", "M☉ AU²/yr²"}
    for name, units in found.items():
        assert units <= allowed, (name, units)
    # the SI default would have drawn 100 days in days
    assert any("yr" in u for u in found.values())
    assert not any("day" in u or "J" in u for u in found.values())


def test_positions_and_times_are_drawn_in_the_scene_units():
    run = _run([2e30, 1.9e27, 5.7e26], ["sun", "jupiter", "saturn"], AU_YR)
    figs = {e.name: e for e in figures_for(run)}
    ax = figs["orbits"].draw(run).axes[0]
    assert ax.get_xlabel().endswith("[AU]")
    xs = sorted(float(np.max(np.abs(line.get_xdata()))) for line in ax.lines)
    assert max(xs) == pytest.approx(5.2, rel=1e-12)
    energy = figs["energy_partition"].draw(run).axes[0]
    assert energy.get_xlabel() == "t [yr]"
    assert float(energy.lines[0].get_xdata()[-1]) == pytest.approx(100 / 365.25, rel=1e-12)
    lunit, tunit = run_axis_units(run.t_s, None, AU_YR)
    assert (lunit.name, tunit.name) == ("AU", "yr") and tunit.size == YEAR


def test_nbody_units_are_labelled_l_and_t():
    nbody = UnitSystem(G=1.0)
    lunit, tunit = run_axis_units(np.array([0.0, 20.0]), np.array([[3.0, 0.0, 0.0]]), nbody)
    assert (lunit.name, lunit.size, tunit.name, tunit.size) == ("L", 1.0, "T", 1.0)
    assert quantity_unit("energy", np.array([0.5]), nbody).name == "M L²/T²"


def test_an_si_magnet_scene_keeps_millimetres_seconds_and_joules():
    t = np.linspace(0.0, 0.7, 10)
    pos = np.array([[0.01, 0.0, 0.0]])
    assert [u.name for u in run_axis_units(t, pos)] == ["mm", "s"]
    with scene_units(UnitSystem()):  # an explicit SI scene: the same choice
        assert [u.name for u in run_axis_units(t, pos)] == ["mm", "s"]
        assert quantity_unit("energy", np.array([1e-3])).name == "J"
    with scene_units(AU_YR):  # the context is what figures of a run draw in
        assert [u.name for u in run_axis_units(t, pos)] == ["10⁻¹⁵ AU", "10⁻⁹ yr"]  # 6.7e-14 AU, 2.2e-8 yr


def test_the_view_of_a_dataset_in_au_and_years_reads_au_and_years():
    xr = pytest.importorskip("xarray")
    pytest.importorskip("plotly")
    from poissonkit.report.trajectory import unit_attributes
    from poissonkit.report.view import view_figure

    t = np.linspace(0.0, 12.0, 20)  # years, as trajectory.nc of an AU/yr scene holds them
    pos = np.zeros((20, 2, 3))
    pos[:, 1, 0], pos[:, 1, 1] = 5.2 * np.cos(t), 5.2 * np.sin(t)
    ds = xr.Dataset({"position": (("time", "body", "component"), pos)},
                    coords={"time": t, "body": ["sun", "jupiter"],
                            "component": ["x", "y", "z"]}, attrs=unit_attributes(AU_YR))
    assert dataset_units(ds.attrs) == AU_YR
    fig = view_figure(ds)
    scene = fig.layout.scene
    for ax in (scene.xaxis, scene.yaxis, scene.zaxis):
        assert ax.title.text.endswith("[AU]")
    assert 5.2 < max(abs(v) for v in scene.xaxis.range) < 10  # drawn in AU
    assert fig.layout.sliders[0].steps[-1].label == "12 yr"
