"""The interactive 3D view (``trajectory.html``) and ``poissonkit view``.

The geometry is checked against the bodies' sizes (mesh vertices at the stated radius from the
axis, within the half-length along it); the page itself is opened in headless Chromium, which
must load it without console errors and show every body.
"""

from __future__ import annotations

import json
import re
import shutil
import sys
from pathlib import Path

import numpy as np
import pytest

from poissonkit import cli
from poissonkit.errors import InputError

xr = pytest.importorskip("xarray")
pytest.importorskip("plotly")

from poissonkit.report.trajectory import open_trajectory  # noqa: E402
from poissonkit.report.view import view_figure  # noqa: E402

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser") \
    or shutil.which("google-chrome")
QUIET = ["--no-progress"]


def _run(monkeypatch, *args: str) -> int:
    argv = ["poissonkit", *args]
    monkeypatch.setattr(sys, "argv", argv)
    return cli.main(argv[1:])


def _dataset(n_bodies: int = 5, n_t: int = 30) -> xr.Dataset:
    t = np.linspace(0.0, 1.0, n_t)
    pos = np.zeros((n_t, n_bodies, 3))
    pos[:, :, 0] = np.arange(n_bodies) * 0.1
    pos[:, :, 2] = 0.01 * np.sin(2 * np.pi * t)[:, None]
    axis = np.zeros_like(pos)
    axis[:, :, 0] = np.cos(t)[:, None]
    axis[:, :, 1] = np.sin(t)[:, None]
    names = [f"m{k}" for k in range(n_bodies)]
    return xr.Dataset(
        {"position": (("time", "body", "component"), pos),
         "axis": (("time", "body", "component"), axis),
         "radius": (("body",), np.full(n_bodies, 0.01)),
         "half_length": (("body",), np.r_[0.0, np.full(n_bodies - 1, 0.02)])},
        coords={"time": t, "body": names, "component": ["x", "y", "z"]})


def test_bodies_are_meshes_of_their_size_along_their_axes():
    ds = _dataset()
    fig = view_figure(ds, title="five")
    meshes = [tr for tr in fig.data if tr.type == "mesh3d"]
    assert [m.name for m in meshes] == [f"m{k}" for k in range(5)]
    assert len(fig.frames) == 30 and "5 bodies" in fig.layout.title.text
    # drawn in millimetres (a scene 0.4 m wide), in single precision
    assert fig.layout.scene.xaxis.title.text == "x [mm]"
    for k, mesh in enumerate(meshes):
        v = np.column_stack([mesh.x, mesh.y, mesh.z]) / 1e3 - ds["position"].values[0, k]
        if k == 0:  # half-length 0: a sphere of the radius
            np.testing.assert_allclose(np.linalg.norm(v, axis=1), 0.01, rtol=1e-5)
            continue
        a = ds["axis"].values[0, k]
        along = v @ a
        across = np.linalg.norm(v - np.outer(along, a), axis=1)
        assert np.max(np.abs(along)) == pytest.approx(0.02, rel=1e-5)
        # rim vertices at the radius, cap centres on the axis
        assert np.sum(np.isclose(across, 0.01, rtol=1e-5)) == 32
        assert np.sum(across < 1e-7) == 2
    # the last frame moves the bodies where the dataset says
    last = fig.frames[-1].data
    np.testing.assert_allclose(np.asarray(last[-1].z) / 1e3, ds["position"].values[-1, :, 2],
                               rtol=1e-6, atol=1e-9)
    markers = [tr for tr in fig.data if tr.name == "bodies"][0]
    assert list(markers.text) == [f"m{k}" for k in range(5)]
    assert fig.frames[-1].traces[-1] == len(fig.data) - 1  # frames move the marker trace


def test_many_bodies_are_markers_and_the_file_stays_bounded():
    fig = view_figure(_dataset(n_bodies=300, n_t=200))
    assert not [tr for tr in fig.data if tr.type == "mesh3d"]
    assert len(fig.frames) <= 150
    big = view_figure(_dataset(n_bodies=30_000, n_t=200))
    assert len(big.frames) <= 400_000 // 30_000


def test_a_dataset_without_bodies_is_refused():
    ds = xr.Dataset({"y": (("time", "state"), np.zeros((3, 2)))}, coords={"time": [0, 1, 2]})
    with pytest.raises(InputError, match="no bodies"):
        view_figure(ds)


@pytest.mark.filterwarnings("error::RuntimeWarning")  # found by the view fuzzer: overflow
def test_values_beyond_single_precision_are_refused_and_a_zero_axis_is_drawn_as_a_sphere():
    huge = _dataset()
    huge["position"][3, 1, 0] = 1e300  # finite, far beyond what the page (float32) holds
    with pytest.raises(InputError, match="beyond what the 3D view can draw"):
        view_figure(huge)
    wide = _dataset()
    wide["radius"][2] = 1e250
    with pytest.raises(InputError, match="beyond what the 3D view can draw"):
        view_figure(wide)
    flat = _dataset()
    flat["axis"][:, 2, :] = 0.0  # no direction: drawn as a sphere of its radius, no NaN
    mesh = [tr for tr in view_figure(flat).data if tr.type == "mesh3d"][2]
    v = np.column_stack([mesh.x, mesh.y, mesh.z]) / 1e3 - flat["position"].values[0, 2]
    assert np.all(np.isfinite(v))
    np.testing.assert_allclose(np.linalg.norm(v, axis=1), 0.01, rtol=1e-5)


@pytest.fixture(scope="module")
def chain_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("chain") / "out"
    mp = pytest.MonkeyPatch()
    try:
        code = _run(mp, "run", "magnet_chain", "--duration", "0.004", "--out", str(out), *QUIET)
    finally:
        mp.undo()
    assert code == 0
    return out


def test_run_writes_the_view_with_every_body_and_their_sizes(chain_run):
    summary = json.loads((chain_run / "summary.json").read_text())
    assert summary["view"] == "trajectory.html"
    ds = open_trajectory(chain_run / "trajectory.nc")
    assert ds["radius"].attrs["units"] == "m" and np.all(ds["radius"].values > 0)
    html = (chain_run / "trajectory.html").read_text(encoding="utf-8")
    # plotly.js from the one file beside the page: no network, no CDN, not inlined per page
    scripts = re.findall(r'<script[^>]*src="([^"]*)"', html)
    assert scripts == ["plotly.min.js"], scripts
    assert (chain_run / "plotly.min.js").stat().st_size > 1_000_000
    assert (chain_run / "trajectory.html").stat().st_size < 1_000_000
    for name in ds["body"].values:
        assert f'"name":"{name}"' in html


def test_view_command_rebuilds_a_missing_page_from_the_dataset(chain_run, tmp_path,
                                                              monkeypatch, capsys):
    copy = tmp_path / "run"
    copy.mkdir()
    shutil.copy(chain_run / "trajectory.nc", copy)
    assert _run(monkeypatch, "view", str(copy), "--no-open") == 0
    assert Path(capsys.readouterr().out.strip()) == (copy / "trajectory.html").resolve()
    assert (copy / "trajectory.html").stat().st_size > 10_000
    assert (copy / "plotly.min.js").is_file()
    assert _run(monkeypatch, "view", str(tmp_path / "nothing"), "--no-open") == 1
    assert "no trajectory.html and no trajectory.nc" in capsys.readouterr().err


@pytest.mark.skipif(CHROMIUM is None, reason="needs chromium (apt-get install chromium)")
def test_the_page_loads_in_headless_chromium_and_lists_every_body(chain_run):
    sync_api = pytest.importorskip("playwright.sync_api")
    names = [str(b) for b in open_trajectory(chain_run / "trajectory.nc")["body"].values]
    problems: list[str] = []
    with sync_api.sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=[
            "--no-sandbox", "--disable-background-networking", "--disable-component-update",
            "--disable-sync", "--no-first-run", "--enable-unsafe-swiftshader"])
        try:
            page = browser.new_page()
            page.on("console", lambda m: problems.append(m.text) if m.type == "error" else None)
            page.on("pageerror", lambda e: problems.append(str(e)))
            page.goto((chain_run / "trajectory.html").as_uri())
            page.wait_for_function("() => { const g = document.querySelector('.js-plotly-plot');"
                                   " return g && g._fullLayout; }", timeout=60_000)
            shown = page.evaluate("""() => {
                const g = document.querySelector('.js-plotly-plot');
                return {traces: g.data.map(d => d.name),
                        legend: Array.from(document.querySelectorAll('.legendtext'))
                                     .map(e => e.textContent),
                        frames: g._transitionData._frames.length,
                        gl: !!document.querySelector('.gl-container canvas')};
            }""")
        finally:
            browser.close()
    assert not problems, problems
    assert shown["gl"], "no WebGL canvas: the 3D scene did not render"
    for name in names:
        assert name in shown["legend"] and name in shown["traces"]
    assert shown["frames"] >= 2


def test_fixed_bodies_are_in_the_dataset_and_the_view_at_their_place():
    from poissonkit.numerics import AllPairs, Body, NBodySystem
    from poissonkit.report.trajectory import trajectory_dataset

    system = NBodySystem([Body("a", 1.0), Body("anchor", 2.0, fixed=True, position=(1.0, 0, 0),
                                                axis=(0, 0, 1.0))],
                         [AllPairs("gravity", {"G": 1.0})])
    y = np.vstack([system.pack([[0.0, 0, 0]], [[0.0, 0.1, 0]]),
                   system.pack([[0.0, 0.1, 0]], [[0.0, 0.1, 0]])])
    ds = trajectory_dataset(system, np.array([0.0, 1.0]), y, scales=None,
                            shapes={"anchor": (0.1, 0.0)})
    assert list(ds["body"].values) == ["a", "anchor"]
    assert ds["fixed"].values.tolist() == [0, 1]
    np.testing.assert_array_equal(ds["position"].sel(body="anchor").values,
                                  [[1.0, 0, 0], [1.0, 0, 0]])
    assert np.isnan(ds["radius"].sel(body="a")) and ds["radius"].sel(body="anchor") == 0.1
    markers = [tr for tr in view_figure(ds).data if tr.name == "bodies"][0]
    assert list(markers.text) == ["a (size not to scale)", "anchor (fixed)"]
