"""Figures chosen by what the scene holds, drawn honestly.

Truths used: the kind of a scene follows from its definition (number of bodies, fields, a mass
100 times every other); a top placed at a chosen height and tilt must be drawn at that height
[mm above the source's top face] and tilt [deg]; the closest pair of bodies placed by hand is
known; a quantity that varies by 1e-13 of its value is constant to round-off, one that varies
by 1e-6 is not; an orbit sampled 5 times per revolution is too coarse to join by lines.
No integration is run: the states are written by hand (the figures only read them).
"""

from __future__ import annotations

import re
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from poissonkit.errors import InputError  # noqa: E402
from poissonkit.numerics import AllPairs, Body, NBodySystem  # noqa: E402
from poissonkit.numerics.fields.base import field  # noqa: E402
from poissonkit.report.figures import RunData, figures_for, register_plot  # noqa: E402
from poissonkit.report.plotkit import caption_of, plot_quantity  # noqa: E402
from poissonkit.report.scene_kind import scene_kind  # noqa: E402
from poissonkit.report.summary import Diagnostics  # noqa: E402

pytest.importorskip("poissonkit_magnets")

G = {"G": 6.674e-11}


def _gravity(masses: list[float], names: str = "abcdefgh") -> NBodySystem:
    return NBodySystem([Body(n, m) for n, m in zip(names, masses)], [AllPairs("gravity", G)])


def _diag(n: int) -> Diagnostics:
    return Diagnostics(np.zeros(n), {}, np.zeros((n, 3)))


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


# ------------------------------------------------------------------ the kind of a scene
def test_scene_kind_follows_bodies_fields_and_a_dominant_mass():
    assert scene_kind(_gravity([1.0, 1.0, 1.0])) == "nbody"
    assert scene_kind(_gravity([2e30, 1.9e27, 5.7e26, 8.7e25])) == "planetary"
    # a planet around a binary: neither star dominates
    assert scene_kind(_gravity([2e30, 1.5e30, 1e25])) == "nbody"
    assert scene_kind(_gravity([2e30, 6e24])) == "two_body"
    top = Body("top", 0.02, alpha=1e4, attributes={"moment": 0.6})
    assert scene_kind(NBodySystem([top], fields=[field("gravity", g=(0, 0, -9.81))])) \
        == "in_field"
    # tops are not point masses: a heavy top among light ones is not a planetary system
    tops = [Body(n, m, alpha=1.0) for n, m in (("a", 1e3), ("b", 1.0), ("c", 1.0))]
    assert scene_kind(NBodySystem(tops, [AllPairs("gravity", G)])) == "nbody"
    assert scene_kind(object(), relative=True) == "two_body"  # the seed's relative form


def test_a_plot_registered_for_an_unknown_kind_is_refused():
    with pytest.raises(InputError, match="unknown scene kind"):
        register_plot("nowhere", lambda run: True, lambda run: None, kinds=("galaxy",))


# ------------------------------------------------------------------ one body in a field
@pytest.fixture(scope="module")
def hovering():
    """A top over a ring magnet (two coaxial cylinder fields, the Levitron's exact base) in
    gravity, at height z(t) = 30 mm + 1 mm sin t, tilted 0.1 rad about x."""
    centre = (0.0, 0.0, -0.005)
    fields = [field("cylinder", polarization=0.265, radius=0.04, length=0.01, position=centre),
              field("cylinder", polarization=-0.265, radius=0.008, length=0.01,
                    position=centre),
              field("gravity", g=(0.0, 0.0, -9.81))]
    system = NBodySystem([Body("top", 0.022, alpha=1e5, attributes={"moment": 0.6})],
                         fields=fields)
    t = np.linspace(0.0, 2.0, 400)
    z = 0.030 + 0.001 * np.sin(t)
    nu = [0.0, -np.sin(0.1), -np.cos(0.1)]  # moment down, tilted 0.1 rad
    y = np.vstack([system.pack([[0.0, 0.0, zk]], [[0.0, 0.0, 0.0]], [nu], [[0.0, 0.0, 1e-3]])
                   for zk in z])
    return system, t, y, z


def test_one_body_in_a_field_gets_height_and_tilt_not_a_relative_orbit(hovering):
    system, t, y, z = hovering
    run = RunData(system, t, y, _diag(len(t)), relative=y[:, :3])
    names = [e.name for e in figures_for(run)]
    assert run.kind == "in_field"
    assert "height_tilt" in names and "configuration" in names
    assert not {"orbit", "radius_and_x", "angular_momentum_z", "closest_pair"} & set(names)
    fig = next(e for e in figures_for(run) if e.name == "height_tilt").draw(run)
    height, tilt = fig.axes[:2]
    assert height.get_ylabel() == "height [mm]" and tilt.get_ylabel() == "tilt [deg]"
    assert height.get_xlabel() == "t [s]"
    # the ring's top face is at z = 0: heights are z in mm
    np.testing.assert_allclose(height.lines[0].get_ydata(), z * 1e3, rtol=1e-12)
    np.testing.assert_allclose(tilt.lines[0].get_ydata(), np.degrees(0.1), rtol=1e-9)
    assert "constant to round-off" in tilt.get_title()  # a fixed tilt is not drawn as noise


def test_the_source_is_drawn_in_the_configuration_and_the_view(hovering, tmp_path):
    from poissonkit.report.nbody_plots import configuration_axes
    from poissonkit.report.source_shapes import source_shapes

    system, t, y, _ = hovering
    shapes = source_shapes(system)
    assert len(shapes) == 1  # the two cylinders are one ring
    ring = shapes[0]
    assert (ring.radius, ring.inner_radius, ring.length) == (0.04, 0.008, 0.01)
    xy, xz = configuration_axes(system, y)
    drawn = [ln for ln in xz.lines if "ring magnet" in str(ln.get_label())]
    assert drawn, [ln.get_label() for ln in xz.lines]
    # the outline spans the ring: ±40 mm in x, z from −10 mm to 0 mm
    ex, ez = drawn[0].get_xdata(), drawn[0].get_ydata()
    assert np.nanmin(ex) == pytest.approx(-40) and np.nanmax(ex) == pytest.approx(40)
    assert np.nanmin(ez) == pytest.approx(-10) and np.nanmax(ez) == pytest.approx(0, abs=1e-12)

    xr = pytest.importorskip("xarray")
    pytest.importorskip("plotly")
    from poissonkit.report.view import PLOTLY_JS, view_figure, write_view

    pos = np.zeros((len(t), 1, 3))
    pos[:, 0] = system.unpack(y, si=True)["r"].reshape(-1, 3)
    ds = xr.Dataset({"position": (("time", "body", "component"), pos)},
                    coords={"time": t, "body": ["top"], "component": ["x", "y", "z"]})
    fig = view_figure(ds, sources=shapes)
    src = [tr for tr in fig.data if tr.type == "mesh3d" and tr.name.startswith("source:")]
    assert len(src) == 1 and np.max(np.abs(src[0].x)) == pytest.approx(40, rel=1e-6)
    page = write_view(tmp_path / "trajectory.html", ds, sources=shapes)
    html = page.read_text(encoding="utf-8")
    assert '"name":"source: ring magnet' in html
    # the only script loaded is the bundle beside the page: no network, no CDN
    assert re.findall(r'<script[^>]*src="([^"]*)"', html) == [PLOTLY_JS]
    assert (tmp_path / PLOTLY_JS).stat().st_size > 1_000_000  # the bundle, beside the page
    assert page.stat().st_size < 1_000_000  # the page itself is small


# ------------------------------------------------------------------ N bodies
def test_the_closest_pair_is_named():
    from poissonkit.report.nbody_plots import closest_pair_axes

    system = _gravity([1.0, 1.0, 1.0, 1.0])
    t = np.linspace(0, 1, 50)
    rows = []
    for s in t:  # a and c close throughout; b and d far apart
        r = [[0, 0, 0], [1.0, 0, 0], [0.01 + 0.001 * s, 0, 0], [0, 2.0, 0]]
        rows.append(system.pack(r, np.zeros((4, 3))))
    ax = closest_pair_axes(system, t, np.array(rows))
    assert ax.get_title() == "Closest pair: a–c"
    rows = [system.pack([[0, 0, 0], [1.0, 0, 0], [0.01 + s, 0, 0], [0, 2.0, 0]],
                        np.zeros((4, 3))) for s in t]  # c drifts from a towards b
    ax = closest_pair_axes(system, t, np.array(rows))
    labels = [str(ln.get_label()) for ln in ax.lines]
    assert ax.get_title().startswith("Closest pair: ")
    assert any(lb.startswith("a–c (") for lb in labels)
    assert any(lb.startswith("b–c (") for lb in labels)


# ------------------------------------------------------------------ honest axes
def test_a_quantity_constant_to_roundoff_is_drawn_flat_and_said_so():
    fig, ax = plt.subplots()
    t = np.linspace(0, 1, 100)
    noise = 1e-13 * np.sin(37 * t)
    assert plot_quantity(ax, t, 0.0327 * (1 + noise))
    assert "constant to round-off" in ax.get_title()
    lo, hi = ax.get_ylim()
    assert lo == pytest.approx(0.0327 * 0.95) and hi == pytest.approx(0.0327 * 1.05)
    fig, ax = plt.subplots()
    assert not plot_quantity(ax, t, 0.0327 * (1 + 1e-6 * np.sin(t)))
    assert "constant" not in ax.get_title()


def test_coarse_samples_are_points_and_the_caption_says_so():
    from poissonkit.report.planet_plots import orbits_axes

    system = _gravity([2e30, 1.9e27, 5.7e26], names=["sun", "jupiter", "saturn"])
    au = 149_597_870_700.0

    def states(per_orbit_j: float, n: int) -> np.ndarray:
        k = np.arange(n)
        th_j, th_s = 2 * np.pi * k / per_orbit_j, 2 * np.pi * k / (2.5 * per_orbit_j)
        return np.array([system.pack([[0, 0, 0], [5.2 * au * np.cos(a), 5.2 * au * np.sin(a), 0],
                                      [9.5 * au * np.cos(b), 9.5 * au * np.sin(b), 0]],
                                     np.zeros((3, 3)), si=True) for a, b in zip(th_j, th_s)])

    ax = orbits_axes(system, states(5.0, 40))
    assert ax.get_xlabel().endswith("[AU]")
    cap = caption_of(ax.figure)
    assert "drawn as points" in cap and "jupiter" in cap and "saturn" not in cap
    jupiter = next(ln for ln in ax.lines if ln.get_label() == "jupiter")
    assert jupiter.get_linestyle() == "None" and jupiter.get_marker() == "."
    ax = orbits_axes(system, states(100.0, 200))
    assert caption_of(ax.figure) == ""


def test_the_view_labels_planets_in_au_without_si_prefixes():
    xr = pytest.importorskip("xarray")
    pytest.importorskip("plotly")
    from poissonkit.report.view import view_figure

    au = 149_597_870_700.0
    t = np.linspace(0, 3.15e9, 20)  # 100 years
    pos = np.zeros((20, 2, 3))
    pos[:, 1, 0], pos[:, 1, 1] = 5.2 * au * np.cos(t / 3.7e8), 5.2 * au * np.sin(t / 3.7e8)
    ds = xr.Dataset({"position": (("time", "body", "component"), pos)},
                    coords={"time": t, "body": ["sun", "jupiter"],
                            "component": ["x", "y", "z"]})
    fig = view_figure(ds)
    scene = fig.layout.scene
    for ax in (scene.xaxis, scene.yaxis, scene.zaxis):
        assert ax.title.text.endswith("[AU]") and ax.exponentformat == "e"
    assert max(abs(v) for v in scene.xaxis.range) < 10  # drawn in AU, not metres
    assert fig.layout.sliders[0].steps[-1].label.endswith(" yr")


def test_planetary_runs_get_orbits_and_elements_only_when_the_run_has_them():
    au = 149_597_870_700.0
    system = _gravity([2e30, 1.9e27, 5.7e26], names=["sun", "jupiter", "saturn"])
    t = np.linspace(0, 3.15e8, 30)  # ten years
    y = np.array([system.pack([[0, 0, 0], [5.2 * au, 0, 0], [0, 9.5 * au, 0]],
                              np.zeros((3, 3)), si=True)] * len(t))
    plain = RunData(system, t, y, _diag(len(t)))
    names = [e.name for e in figures_for(plain)]
    assert plain.kind == "planetary"
    assert "orbits" in names and "elements" not in names and "closest_pair" not in names
    elements = {"a": np.tile([5.2 * au, 9.5 * au], (len(t), 1)),
                "e": np.tile([0.048, 0.054], (len(t), 1)),
                "inc": np.tile([0.0228, 0.0434], (len(t), 1))}
    with_elements = RunData(system, t, y, _diag(len(t)), elements=elements)
    entry = next(e for e in figures_for(with_elements) if e.name == "elements")
    axes = entry.draw(with_elements).axes
    assert [ax.get_ylabel() for ax in axes] == ["a [AU]", "e", "inc [deg]"]
    assert axes[0].get_xlabel() == "t [yr]"
    np.testing.assert_allclose(axes[0].lines[1].get_ydata(), 9.5, rtol=1e-12)
    np.testing.assert_allclose(axes[2].lines[0].get_ydata(), np.degrees(0.0228), rtol=1e-12)


@pytest.mark.slow  # compiles the field kernels of the scene: minutes on a cold cache
def test_poissonkit_run_of_a_top_over_a_magnet_writes_height_and_tilt(tmp_path):
    from poissonkit import cli

    scene = Path(__file__).resolve().parents[2] / "examples" / "magnet_over_cylinder.toml"
    out = tmp_path / "out"
    assert cli.main(["run", str(scene), "--duration", "0.01", "--out", str(out),
                     "--no-progress"]) == 0
    written = {p.name for p in out.glob("*.png")}
    assert {"height_tilt.png", "configuration.png"} <= written
    assert not {"orbit.png", "radius_and_x.png", "angular_momentum_z.png"} & written


def test_two_body_figures_of_the_sun_and_earth_read_au_and_years():
    au, year = 149_597_870_700.0, 365.25 * 86_400.0
    system = _gravity([2e30, 6e24], names=["sun", "earth"])
    t = np.linspace(0, 3 * year, 300)
    rel = au * np.column_stack([np.cos(2 * np.pi * t / year), np.sin(2 * np.pi * t / year),
                                np.zeros_like(t)])
    y = np.array([system.pack([[0, 0, 0], r], np.zeros((2, 3)), si=True) for r in rel])
    run = RunData(system, t, y, _diag(len(t)), relative=rel, jz=np.full(len(t), 2.7e40))
    figs = {e.name: e for e in figures_for(run)}
    orbit = figs["orbit"].draw(run).axes[0]
    assert orbit.get_xlabel() == "x [AU]" and orbit.get_title() == "Relative orbit r = r2 - r1"
    np.testing.assert_allclose(np.hypot(*orbit.lines[0].get_data()), 1.0, rtol=1e-12)
    radius = figs["radius_and_x"].draw(run).axes[0]
    assert radius.get_xlabel() == "t [yr]" and radius.get_ylabel() == "[AU]"
    assert "constant to round-off" in radius.get_title()  # a circle: |r| = 1 AU throughout
    jz = figs["angular_momentum_z"].draw(run).axes[0]
    assert "constant to round-off" in jz.get_title() and jz.get_xlabel() == "t [yr]"
