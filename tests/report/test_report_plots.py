"""Figures chosen by what a run has: N-body figures for a five-magnet scene (their contents,
not only their files), honest drifts with exact zeros, the two-body figures by name."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from scene_texts import magnet_scene  # type: ignore[import-not-found]  # noqa: E402

from poissonkit import cli  # noqa: E402
from poissonkit.numerics.diagnostics import Drift  # noqa: E402
from poissonkit.report.drift_plot import drift_axes, drift_floor  # noqa: E402
from poissonkit.report.figures import PLOTS, RunData, figures_for, register_plot  # noqa: E402
from poissonkit.report.summary import Diagnostics  # noqa: E402

# five magnets, the first bolted down; dumbbell pairs (the kernel magnet_chain uses too)
FIVE = magnet_scene(
    "five_magnets",
    ("m0", "[0.0, 0.0, 0.0]", "[0.0, 0.0, 1.0]", "fixed = true"),
    ("m1", "[0.04, 0.0, 0.0]", "[0.0, 0.0, 1.0]"),
    ("m2", "[0.0, 0.05, 0.01]", "[1.0, 0.0, 0.0]"),
    ("m3", "[-0.05, 0.0, 0.02]", "[0.0, 1.0, 0.0]"),
    ("m4", "[0.0, -0.06, 0.0]", "[0.0, 0.0, -1.0]")) + """[interactions]
potential = "dumbbell"
[run]
method = "splitting4"
step = 1e-4
duration = 0.004
"""

NAMES = ["m0", "m1", "m2", "m3", "m4"]


@pytest.fixture(scope="module")
def five_run(tmp_path_factory):
    """The built scene, its trajectory and diagnostics, and the folder ``poissonkit run``
    wrote for it."""
    from poissonkit.report import diagnostics
    from poissonkit.scene import loads_scene
    from poissonkit.scene.build import build_run

    folder = tmp_path_factory.mktemp("five")
    scene = folder / "five.toml"
    scene.write_text(FIVE)
    out = folder / "out"
    assert cli.main(["run", str(scene), "--out", str(out), "--no-progress"]) == 0
    spec = build_run(loads_scene(FIVE))
    data = np.load(out / "trajectory.npz")
    t, y = data["t"], data["y"]
    run = RunData(spec.system, t, y, diagnostics(spec.system, t, y),
                  time_unit=float(spec.system.scales.time), name="five_magnets",
                  shapes={n: (1.25e-3 / spec.system.scales.length,
                              1e-2 / spec.system.scales.length) for n in NAMES})
    return out, run


def test_five_body_run_writes_the_nbody_figures_and_not_the_two_body_ones(five_run):
    out, _ = five_run
    for name in ("configuration", "closest_pair", "energy_partition", "drifts"):
        assert (out / f"{name}.png").is_file(), name
    for name in ("orbit", "radius_and_x", "angular_momentum_z", "model_timeline"):
        assert not (out / f"{name}.png").exists(), name


def test_configuration_shows_every_body_fixed_one_marked_and_the_axes(five_run):
    from poissonkit.report.nbody_plots import configuration_axes

    _, run = five_run
    xy, xz = configuration_axes(run.system, run.y)
    for ax, second in ((xy, "y"), (xz, "z")):
        assert ax.get_xlabel() == "x [mm]" and ax.get_ylabel() == f"{second} [mm]"
        assert sorted(t.get_text() for t in ax.texts) == NAMES
        fixed = [ln for ln in ax.get_lines() if ln.get_marker() == "s"]
        assert len(fixed) == 1  # m0 only
        x0, y0 = fixed[0].get_data()
        assert (x0[0], y0[0]) == (0.0, 0.0)
        # four moving bodies: a path, a start and an end marker each
        circles = [ln for ln in ax.get_lines() if ln.get_marker() == "o"]
        assert len(circles) == 8
        # five tops (the fixed one too): one arrow each
        (quiver,) = ax.collections
        assert len(quiver.U) == 5
    # the end markers sit where the trajectory ends (mm), body m2 (index 2)
    from poissonkit.report.nbody_plots import positions_si

    end = positions_si(run.system, run.y[-1:])[0] * 1e3
    ends = [ln.get_data() for ln in xy.get_lines()
            if ln.get_marker() == "o" and ln.get_markerfacecolor() != "none"]
    assert any(np.allclose((x[0], y[0]), end[2, :2]) for x, y in ends)
    plt.close("all")


def test_closest_pair_distance_is_the_brute_force_minimum(five_run):
    from poissonkit.report.nbody_plots import closest_pair_axes, positions_si

    _, run = five_run
    ax = closest_pair_axes(run.system, run.t_s, run.y, shapes=run.shapes,
                           length_unit=run.system.scales.length)
    labels = [ln.get_label() for ln in ax.get_lines()]
    assert labels == ["closest-pair distance", "contact: radii sum",
                      "contact: bounding spheres"]
    assert ax.get_ylabel() == "distance [mm]" and ax.get_xlabel() == "t [s]"
    pos = positions_si(run.system, run.y)
    brute = np.min([np.linalg.norm(pos[:, i] - pos[:, j], axis=1)
                    for i in range(5) for j in range(i + 1, 5)], axis=0) * 1e3
    np.testing.assert_allclose(ax.get_lines()[0].get_ydata(), brute, rtol=1e-12)
    # radii sum 2.5 mm; bounding spheres 2 hypot(1.25, 10) mm
    np.testing.assert_allclose(ax.get_lines()[1].get_ydata(), 2.5, rtol=1e-12)
    np.testing.assert_allclose(ax.get_lines()[2].get_ydata(), 2 * np.hypot(1.25, 10), rtol=1e-12)
    plt.close("all")


def test_energy_partition_adds_up_to_the_total(five_run):
    from poissonkit.report.nbody_plots import energy_partition, energy_partition_axes

    _, run = five_run
    parts = energy_partition(run.system, run.y)
    assert list(parts) == ["translational", "rotational", "interaction", "total"]
    # independent kinetic energy from the SI state: Σ p²/2M over the four moving magnets
    p = run.system.unpack(run.y, si=True)["p"].reshape(len(run.y), -1, 3)
    np.testing.assert_allclose(parts["translational"],
                               np.sum(p**2, axis=(1, 2)) / (2 * 7.658e-4), rtol=1e-12)
    assert parts["translational"][0] == 0 and parts["translational"][-1] > 0  # starts at rest
    np.testing.assert_allclose(parts["translational"] + parts["rotational"]
                               + parts["interaction"], parts["total"], rtol=1e-12)
    ax = energy_partition_axes(run.system, run.t_s, run.y)
    assert [ln.get_label() for ln in ax.get_lines()] == list(parts)
    assert ax.get_ylabel() == "energy [J]"
    plt.close("all")


def test_fixed_body_leaves_momenta_out_of_the_drift_figure(five_run):
    from poissonkit.report.summary import conserved_quantities

    _, run = five_run
    ax = drift_axes(run.diag, time_scale=run.time_unit,
                    not_conserved=conserved_quantities(run.system))
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert not any(label.startswith(("|Δj|", "|ΔP|")) for label in labels)
    (note,) = [label for label in labels if "not an invariant here" in label]
    assert "linear momentum" in note and "angular momentum" in note and "m0" in note
    assert ax.get_yscale() == "log"
    plt.close("all")


# ----------------------------------------------------------------- drifts with exact zeros
def _diag(**series: np.ndarray) -> Diagnostics:
    n = len(next(iter(series.values())))
    drifts = {k: Drift(k, v, v, 1e-3 if k == "angular_momentum_drift" else 2.0)
              for k, v in series.items()}
    return Diagnostics(np.arange(n, dtype=float), drifts, np.zeros((n, 3)))


def test_exact_zeros_are_markers_at_a_stated_floor_not_a_clipped_line():
    energy = np.array([0.0, 1e-12, 0.0, 3e-12, 2e-12])
    casimir = np.zeros(5)
    diag = _diag(energy_error=energy, casimir_drift=casimir)
    assert drift_floor(diag) == pytest.approx(1e-13)
    ax = drift_axes(diag)
    lines = ax.get_lines()
    energy_line = next(ln for ln in lines if ln.get_label() == "|ΔH|/|H(0)|")
    y = np.asarray(energy_line.get_ydata(), dtype=float)
    # zeros (and t = 0) are gaps in the line, not 1e-17
    assert np.isnan(y[[0, 2]]).all() and np.allclose(y[[1, 3, 4]], energy[[1, 3, 4]])
    markers = [ln for ln in lines if ln.get_marker() == "v" and len(ln.get_xdata())]
    # energy: one zero at t = 2; Casimirs: zeros at t = 1..4 (t = 0 is zero by definition)
    assert sorted(len(m.get_xdata()) for m in markers) == [1, 4]
    assert all(np.all(m.get_ydata() == 1e-13) for m in markers)
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert "floor 1e-13: markers stand for" in legend and "  exactly 0" in legend
    assert min(ax.get_ylim()) <= 1e-13
    plt.close("all")


def test_tiny_nonzero_drifts_do_not_push_the_floor_to_1e_35():
    from poissonkit.report.drift_plot import LOWEST_FLOOR

    diag = _diag(energy_error=np.array([0.0, 1e-16, 3e-34, 0.0]))
    assert drift_floor(diag) == LOWEST_FLOOR
    ax = drift_axes(diag)
    up = [ln for ln in ax.get_lines() if ln.get_marker() == "^" and len(ln.get_xdata())]
    down = [ln for ln in ax.get_lines() if ln.get_marker() == "v" and len(ln.get_xdata())]
    assert [list(ln.get_xdata()) for ln in up] == [[2.0]]
    assert [list(ln.get_xdata()) for ln in down] == [[3.0]]
    line = next(ln for ln in ax.get_lines() if ln.get_label() == "|ΔH|/|H(0)|")
    assert np.isnan(np.asarray(line.get_ydata(), dtype=float)[[0, 2, 3]]).all()
    plt.close("all")


def test_only_the_invariants_the_run_has_are_drawn():
    ax = drift_axes(_diag(energy_error=np.array([0.0, 1e-9, 2e-9])))
    assert [ln.get_label() for ln in ax.get_lines()] == ["|ΔH|/|H(0)|"]
    plt.close("all")


def test_zero_angular_momentum_scale_is_drawn_as_absolute_not_relative():
    v = np.array([0.0, 1e-15, 2e-15])
    diag = Diagnostics(np.arange(3.0), {"angular_momentum_drift": Drift(
        "angular_momentum_drift", v, v, 1.0)}, np.zeros((3, 3)))  # scale 0 → floored to 1
    (line,) = [ln for ln in drift_axes(diag).get_lines() if ln.get_marker() != "v"]
    assert line.get_label().startswith("|Δj| (scale 0")
    assert "/" not in line.get_label()
    plt.close("all")


# ----------------------------------------------------------------- the registry
def test_two_body_runs_keep_the_seed_figure_names():
    n = 4
    t = np.linspace(0, 1, n)
    rel = np.c_[np.cos(t), np.sin(t), 0 * t] * 0.01
    run = RunData(object(), t, np.zeros((n, 18)), _diag(energy_error=np.full(n, 1e-9)),
                  relative=rel, jz=np.ones(n))
    assert [e.name for e in figures_for(run)] == ["angular_momentum_z", "radius_and_x", "orbit",
                                                 "drifts"]


def test_a_plugin_can_register_its_own_figure(tmp_path):
    from poissonkit.errors import InputError
    from poissonkit.report.figures import write_figures

    def draw(run):
        fig, ax = plt.subplots()
        ax.plot(run.t, run.t)
        return fig

    try:
        register_plot("my_plugin_figure", lambda run: run.name == "mine", draw)
        with pytest.raises(InputError):
            register_plot("my_plugin_figure", lambda run: True, draw)
        run = RunData(object(), np.arange(3.0), np.zeros((3, 2)), _diag(
            energy_error=np.zeros(3)), name="mine")
        names = [p.name for p in write_figures(tmp_path, run)]
        assert names == ["drifts.png", "my_plugin_figure.png"]  # registration order
        assert (tmp_path / "my_plugin_figure.png").is_file()
    finally:
        PLOTS.pop("my_plugin_figure", None)
