"""The registered Levitron scene against the standalone reference (tests/reference_levitron.py).

The scene's system (an NBodySystem with the exact field of two coaxial cylinders and gravity,
the field hook's kernels, internal units) and the reference (an analytic on-axis field, a
hand-written linearisation) share no code: the hovering height, the spectrum on the leaf, the
linear window's edges and the outcome of integrations are compared. Every test that builds the
scene's system pays the field kernels' numba compilation (tens of seconds in a fresh
process), so they are marked slow: ``pytest -m slow tests/magnets/test_levitron_scene.py``.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
import reference_levitron as ref  # noqa: E402

import poissonkit as pk  # noqa: E402

lev = pytest.importorskip("poissonkit_magnets.levitron")

P = lev.LevitronParameters()
REF = ref.LevitronParameters()


@pytest.fixture(scope="module")
def window() -> tuple[float, float]:
    return ref.stability_window(REF, points=120)


def test_parameter_sets_agree():
    for name in ("mass", "moment", "I1", "I3", "polarization", "inner_radius", "outer_radius",
                 "thickness", "g"):
        assert getattr(P, name) == getattr(REF, name)


@pytest.mark.slow  # builds and compiles the field kernels (~30 s per process)
def test_hovering_state_and_spectrum_match_the_reference():
    system = lev.levitron_system(P)
    s = lev.hover_stability(P, 1200.0)
    z0 = system.unpack(s.equilibrium.state, si=True)["r"][0, 2]
    assert z0 == pytest.approx(ref.hover_height(REF), rel=1e-9)
    expected = ref.leaf_spectrum(REF, 1200.0)
    freq = np.sort(s.frequencies) / system.scales.time  # internal time → s
    assert np.allclose(freq, np.sort(expected.imag[expected.imag >= 0]), rtol=1e-6)
    assert s.reduced_dimension == 10 and s.spectrally_stable
    assert s.energy_casimir == "inconclusive"  # gyroscopic: no energy–Casimir function


@pytest.mark.slow  # builds and compiles the field kernels (~30 s per process)
def test_linear_window_edges_match_the_reference(window):
    lower, upper = window
    system = lev.levitron_system(P)
    base = lev.hovering_state(system, P, 1200.0)
    verdicts = {rpm: lev.hover_stability(P, rpm, base).spectrally_stable
                for rpm in (0.99 * lower, 1.01 * lower, 0.99 * upper, 1.01 * upper)}
    assert list(verdicts.values()) == [False, True, True, False]


@pytest.mark.slow  # builds and compiles the field kernels (~30 s per process)
def test_a_top_outside_the_mass_window_has_no_stable_spin():
    light = P.with_values(mass=0.0214)  # hovers above the adiabatic trap (reference: 21.6 g)
    assert not any(lev.hover_stability(light, rpm).spectrally_stable
                   for rpm in (800.0, 1200.0, 1600.0))
    with pytest.raises(pk.PoissonkitError):  # too heavy: the base cannot hold it up
        lev.hover_stability(P.with_values(mass=0.0230), 1200.0)


@pytest.mark.slow  # builds and compiles the field kernels (~30 s per process)
def test_run_levitron_conserves_energy_and_hovers():
    from poissonkit.scene.registered import registered_run

    spec, used = registered_run("levitron", {"duration": 0.3, "spin_rpm": 1200.0})
    assert {"duration", "spin_rpm"} <= used
    sol = pk.solve(spec.system, spec.y0, spec.t_end, method=spec.method, step=spec.step)
    assert np.max(sol.energy_error()) < 1e-12
    assert np.max(sol.casimir_drift()) < 1e-12
    z = spec.system.unpack(np.asarray(sol.y), si=True)["r"][:, 0, 2]
    z0 = spec.metadata["hover_height_m"]
    assert np.max(np.abs(z - z0)) < 2e-3


@pytest.mark.slow
def test_sweep_window_agrees_with_the_linear_analysis(window):
    """Integrations (3 s each) fail below the window (the top flips and falls), stay bounded
    inside and escape above (the axis no longer follows the field)."""
    from poissonkit_magnets.levitron_sweep import LevitronScene

    lower, upper = window
    scene = LevitronScene()
    prep = scene.prepare()
    fates = {rpm: scene.run(prep, {"spin_rpm": rpm}).fate
             for rpm in (0.9 * lower, 1.06 * lower, np.sqrt(lower * upper), 0.95 * upper,
                         1.1 * upper)}
    assert list(fates.values()) == ["collision", "bounded", "bounded", "bounded", "escape"]


@pytest.mark.slow
def test_magpylib_base_gives_the_same_window(window):
    """The base as magpylib's CylinderSegment, tabulated (tricubic Hermite, tol 1e-4): the
    hovering height to the interpolation tolerance, the window within 0.5 %."""
    p = P.with_values(field="magpylib")
    system = lev.levitron_system(p)
    info = system.fields[0].info
    assert info["gradient_error"] <= 1e-4
    z0 = system.unpack(lev.hover_stability(p, 1200.0).equilibrium.state, si=True)["r"][0, 2]
    assert z0 == pytest.approx(ref.hover_height(REF), rel=1e-5)
    lower, upper = lev.stability_window(p, lo=500.0, hi=3000.0, points=12, resolution=2.0)
    assert lower == pytest.approx(window[0], rel=5e-3)
    assert upper == pytest.approx(window[1], rel=5e-3)


@pytest.mark.slow
def test_poissonkit_run_levitron_takes_scene_parameters(tmp_path, monkeypatch, capsys):
    import json

    from poissonkit import cli

    out = tmp_path / "run"
    argv = ["run", "levitron", "--param", "spin_rpm=1500", "--param", "mass=0.0221",
            "--duration", "0.1", "--no-plots", "--no-progress", "--out", str(out)]
    monkeypatch.setattr(sys, "argv", ["poissonkit", *argv])
    assert cli.main(argv) == 0
    summary = json.loads((out / "summary.json").read_text())
    text = json.dumps(summary)
    assert "1500" in text and "0.0221" in text
    code = cli.main(["run", "levitron", "--param", "spin=3", "--no-plots", "--no-progress",
                     "--out", str(tmp_path / "bad")])
    assert code == 1 and "not a parameter" in capsys.readouterr().err


def test_fates_are_classified_by_the_first_failure():
    system = lev.levitron_system(P)  # no kernels compiled: only packing and unpacking
    z0 = 0.0327

    def state(r, nu):
        return system.pack([r], [[0.0, 0.0, 0.0]], [nu], [[0.0, 0.0, 0.0]], si=True,
                           normalize=True)

    hover = state([0, 0, z0], [0, 0, -1])
    flipped = state([0.001, 0, z0], [0.3, 0, 0.2])
    down = state([0, 0, 0.002], [0, 0, -1])
    away = state([0.05, 0, z0], [0, 0, -1])
    cases = {"bounded": [hover, hover], "flip": [hover, flipped, down],
             "fall": [hover, down, flipped], "escape": [hover, away]}
    for fate, rows in cases.items():
        kind, k = lev.classify(system, np.array(rows), z0)
        assert kind == fate
        assert k == (-1 if fate == "bounded" else 1)
    assert lev.classify(system, np.array([hover, np.full_like(hover, np.nan)]), z0) == ("fall", 1)
