"""The third-party path: the example plugin in examples/external_plugin, discovered for real.

Fast test: the example's own entry-point declaration (read from its pyproject.toml) is written
into a ``*.dist-info`` next to its source on ``sys.path`` — what an editable install leaves.
Slow test: ``pip install`` into a fresh virtual environment and ``poissonkit plugins`` there.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from poissonkit.cli import main as cli_main
from poissonkit.plugin import plugin_reports, potential

ROOT = Path(__file__).resolve().parents[2]  # the project root

EXAMPLE = ROOT / "examples" / "external_plugin"




def lj_reference(r, eps, sigma):
    """Closed-form Lennard-Jones energy and dU/dr (independent of the plugin)."""
    s6 = (sigma / r) ** 6
    return 4 * eps * (s6 * s6 - s6), 4 * eps * (-12 * s6 * s6 + 6 * s6) / r


def test_example_plugin_is_listed_by_the_cli(example_discoverable, capsys):
    assert cli_main(["plugins"]) == 0
    out = capsys.readouterr().out
    assert "lennard_jones 0.2.0 (poissonkit-lj-example)" in out
    assert "    potential: lennard_jones" in out
    rep = next(r for r in plugin_reports() if r.name == "lennard_jones")
    assert rep.status == "ok"
    assert rep.contributions == {"potential": ["lennard_jones", "finite_dipole", "point_dipole"],
                                 "model_family": ["electric_dipoles"], "scene": ["dipole_pair"],
                                 "outcome": ["max_axis_tilt"], "field": ["harmonic_trap"]}


def test_example_potential_is_usable_through_the_registry_and_the_numerics(example_discoverable):
    lj = potential("lennard_jones")
    assert lj.orientation == "none"
    assert {p.name: p.unit for p in lj.params} == {"epsilon": "J", "sigma": "m"}
    params = lj.resolve_params({"epsilon": 1.65e-21, "sigma": 3.4e-10})
    from poissonkit.numerics.potentials import compile_potential

    f = compile_potential(lj, params)
    for r in (3.2e-10, 2 ** (1 / 6) * 3.4e-10, 5e-10, 1e-9):
        U, U_r, U_c1, U_c2, U_c3 = f(r, 0.3, -0.2, 0.5)
        U0, dU0 = lj_reference(r, 1.65e-21, 3.4e-10)
        assert U == pytest.approx(U0, rel=1e-12)
        assert U_r == pytest.approx(dU0, rel=1e-10, abs=1e-12 * 1.65e-21 / 3.4e-10)
        assert (U_c1, U_c2, U_c3) == (0.0, 0.0, 0.0)


@pytest.mark.slow
def test_two_lj_particles_oscillate_about_the_minimum(example_discoverable):
    """A pair released at rest at r0 > r_min stays bounded and conserves energy and momentum."""
    from poissonkit.numerics.nbody import Body, Interaction, NBodySystem

    eps, sigma, mass = 1.65e-21, 3.4e-10, 6.6e-26
    from poissonkit.numerics.units import Scales

    system = NBodySystem([Body("a", mass), Body("b", mass)],
                         [Interaction(0, 1, "lennard_jones", {"epsilon": eps, "sigma": sigma})],
                         scales=Scales.from_energy(sigma, mass, eps))
    y = system.pack([[0, 0, 0], [4.0e-10, 0, 0]], np.zeros((2, 3)), si=True)
    E0 = system.energy(y)
    assert E0 * system.scales.energy == pytest.approx(lj_reference(4.0e-10, eps, sigma)[0])
    # leapfrog on the compiled right-hand side (independent of poissonkit's integrators)
    h = 1e-3
    for _ in range(3000):
        d = system.rhs(0.0, y)
        y = y + 0.5 * h * np.where(np.arange(y.size) % 6 >= 3, d, 0)
        d = system.rhs(0.0, y)
        y = y + h * np.where(np.arange(y.size) % 6 < 3, d, 0)
        d = system.rhs(0.0, y)
        y = y + 0.5 * h * np.where(np.arange(y.size) % 6 >= 3, d, 0)
    sep = np.linalg.norm(y[6:9] - y[0:3]) * sigma
    assert 3.0e-10 < sep < 4.01e-10
    assert abs(system.energy(y) - E0) < 1e-4 * abs(E0)
    assert np.allclose(system.linear_momentum(y), 0.0, atol=1e-12)


@pytest.mark.slow
def test_pip_install_into_a_fresh_venv_lists_and_uses_the_plugin(tmp_path):
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(venv)], check=True)
    python = venv / ("Scripts" if os.name == "nt" else "bin") / "python"
    probe = subprocess.run([str(python), "-c", (
        "import setuptools, sys; "
        "v = tuple(int(x) for x in setuptools.__version__.split('.')[:2]);"
        "import importlib.util as u;"
        "sys.exit(0 if v >= (70, 1) or u.find_spec('wheel') else 1)")], check=False)
    if probe.returncode:
        # setuptools < 70.1 builds wheels only with the `wheel` package; fetch it into the venv
        got = subprocess.run([str(python), "-m", "pip", "install", "--quiet", "wheel"],
                             check=False)
        if got.returncode:
            pytest.skip("building the example needs `wheel` (setuptools < 70.1) and it is "
                        "not installable here")
    source = tmp_path / "external_plugin"  # build from a copy: no artifacts in the checkout
    shutil.copytree(EXAMPLE, source, ignore=shutil.ignore_patterns("build", "*.egg-info",
                                                                   "__pycache__"))
    subprocess.run([str(python), "-m", "pip", "install", "--quiet", "--no-deps",
                    "--no-build-isolation", str(source)], check=True, cwd=tmp_path)
    env = {k: v for k, v in os.environ.items() if not k.startswith("POISSONKIT_")}
    out = subprocess.run([str(python), "-m", "poissonkit", "plugins", "--json"], check=True,
                         capture_output=True, text=True, env=env, cwd=tmp_path).stdout
    listed = {r["name"]: r for r in json.loads(out)}
    assert listed["lennard_jones"]["source"] == "poissonkit-lj-example"
    assert listed["lennard_jones"]["status"] == "ok"
    code = ("from poissonkit.plugin import potential; p = potential('lennard_jones'); "
            "import sympy as sp; e = p.expr(p.resolve_params({'epsilon': 2.0, 'sigma': 1.0}));"
            "print(float(e.subs(sp.Symbol('r', real=True), 2 ** (1 / 6))))")
    value = subprocess.run([str(python), "-c", code], check=True, capture_output=True, text=True,
                           env=env, cwd=tmp_path).stdout
    assert float(value) == pytest.approx(-2.0)  # the well depth -epsilon at r = 2^(1/6) sigma
    # every path a built-in's contributions take, with the three built-in plugins blocked
    blocked = dict(env, POISSONKIT_BLOCK_PLUGINS="magnets,nbody,nonholonomic",
                   POISSONKIT_CACHE_DIR=str(tmp_path / "cache"))
    run = subprocess.run([str(python), str(Path(__file__).with_name("external_plugin_paths.py"))],
                         capture_output=True, text=True, env=blocked, cwd=tmp_path)
    assert run.returncode == 0, run.stderr[-3000:]
    got = json.loads(run.stdout.strip().splitlines()[-1])
    assert got["blocked"] == ["magnets", "nbody", "nonholonomic"]
    assert "dipole" not in got["potentials"] and "gravity" not in got["potentials"]
    assert (got["auto_far"], got["auto_near"]) == ("point_dipole", "finite_dipole")
    assert got["plan"]["finite_dipole"] == 1 and got["plan"]["point_dipole"] == 2
    assert got["run_exit"] == 0 and got["run_energy_error"] < 1e-6
    assert got["sweep_completed"] and got["sweep_fate"] == [1, 0]
    assert got["sweep_tilt"][1] < 0.05
    assert got["solve_energy_error"] < 1e-6
    # the system interpreter is untouched
    assert "lennard_jones" not in [r.name for r in plugin_reports()]
