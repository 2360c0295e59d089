"""With the three built-in plugins blocked, the core still works on its own and with a
third-party plugin: the symbolic core, verify of a user bracket, ``solve`` on user systems and
user potentials, scenes with a plugin's potentials (sweeps: the slow fresh-venv test).

Independent truth: e(3)'s known Casimirs, a hand-integrated harmonic oscillator, and the
Coulomb sum of ``test_plugins_external_dipoles``.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

BLOCKED = "magnets,nbody,nonholonomic"


@pytest.fixture
def blocked(monkeypatch):
    """The core alone: built-ins blocked, and installed third-party plugins not loaded."""
    monkeypatch.setenv("POISSONKIT_BLOCK_PLUGINS", BLOCKED)
    monkeypatch.setenv("POISSONKIT_DISABLE_PLUGIN_AUTOLOAD", "1")


@pytest.fixture
def blocked_with_example(example_discoverable, monkeypatch):
    monkeypatch.setenv("POISSONKIT_BLOCK_PLUGINS", BLOCKED)


def test_the_builtins_are_blocked_and_nothing_of_theirs_is_registered(blocked):
    from poissonkit.plugin import names, plugin_reports

    status = {r.name: r.status for r in plugin_reports()}
    assert all(status[n] == "blocked" for n in BLOCKED.split(","))
    assert names("potential") == [] and names("assembly") == [] and names("model_family") == []
    assert "splitting6" in names("integrator") and "fate" in names("outcome")


def test_symbolic_core_and_verify_of_a_user_bracket(blocked):
    import poissonkit as pk

    P = pk.direct_sum(("orbit", pk.canonical(1, "q", "p")), ("top", pk.e3()))
    assert pk.check_jacobi(P).is_poisson
    found = [sp.expand(c) for c in pk.find_casimirs(P, degree=2)]
    nu = [P.symbol(f"top.nu_{a}") for a in "xyz"]
    m = [P.symbol(f"top.m_{a}") for a in "xyz"]
    # e(3)'s Casimirs |ν|² and (ν, m) span what was found (up to scale and combination)
    known = [sum(x * x for x in nu), sum(a * b for a, b in zip(nu, m))]
    assert len(found) == 2
    for c in found:
        a, b = sp.symbols("a b")
        sol = sp.solve(sp.Poly(sp.expand(c - a * known[0] - b * known[1]),
                               *nu, *m, *P.coords[:2]).coeffs(), [a, b], dict=True)
        assert sol, f"{c} is not a combination of the e(3) Casimirs"
    report = pk.verify(P, "user bracket")
    assert report["ok"] and len(report["casimirs"]) == 2
    # a negative control: random antisymmetric constants in dimension 5 are not Poisson
    rng = np.random.default_rng(1)
    C = [[[0] * 5 for _ in range(5)] for _ in range(5)]
    for i in range(5):
        for j in range(i + 1, 5):
            for k in range(5):
                C[i][j][k] = int(rng.integers(-3, 4))
                C[j][i][k] = -C[i][j][k]
    bad = pk.lie_poisson(C, [f"x{i}" for i in range(5)])
    assert not pk.check_jacobi(bad).is_poisson


def test_solve_a_user_system_against_the_exact_flow(blocked):
    import poissonkit as pk

    P = pk.canonical(1, "q", "p")
    q, p = P.coords
    system = pk.compile_system(pk.HamiltonianSystem(P, (p ** 2 + q ** 2) / 2))
    sol = pk.solve(system, [1.0, 0.0], 2.0, method="midpoint", step=1e-3)
    # the implicit midpoint rule is exact for quadratic invariants: the orbit is the circle,
    # and its phase error after t is t h² / 12 (Cayley transform of a rotation)
    assert np.allclose(sol.y[-1], [np.cos(2.0), -np.sin(2.0)], atol=1e-6)
    assert sol.summary()["max_rel_energy_error"] < 1e-13


def test_solve_with_a_user_potential_object_not_in_any_registry(blocked):
    from poissonkit.numerics.nbody import Body, Interaction, NBodySystem
    from poissonkit.numerics.solver import solve
    from poissonkit.plugin import PairPotential, Param

    spring = PairPotential(
        "user_spring", "U = k (r - r0)^2 / 2",
        params=(Param("k", "float", "stiffness [N/m]"), Param("r0", "float", "rest length [m]")),
        expr=lambda p: p["k"] * (sp.Symbol("r", real=True) - p["r0"]) ** 2 / 2,
        orientation="none")
    system = NBodySystem([Body("a", 1.0), Body("b", 1.0)],
                         [Interaction(0, 1, spring, {"k": 2.0, "r0": 1.0})])
    y0 = system.pack([[0, 0, 0], [1.5, 0, 0]], np.zeros((2, 3)))
    sol = solve(system, y0, 1.0, method="splitting6", step=1e-3)
    r = system.unpack(np.asarray(sol.y))["r"]
    gap = np.linalg.norm(r[:, 1] - r[:, 0], axis=-1)
    # reduced mass 1/2, ω = sqrt(k/μ) = 2: the extension is 0.5 cos(2t)
    assert np.allclose(gap - 1.0, 0.5 * np.cos(2.0 * np.asarray(sol.t)), atol=1e-9)


def test_scene_and_planner_with_a_plugin_and_no_builtins(blocked_with_example, tmp_path):
    import json

    import poissonkit as pk
    from poissonkit.cli import main as cli_main
    from poissonkit.plugin import names

    assert "dipole" not in names("potential") and "finite_dipole" in names("potential")
    near = pk.pair_interaction("auto", (0.02, 0, 0), (0, 0, 1), (0, 0, 1), charge=1e-8,
                               dipole_length=5e-3, tol=1e-2)
    assert near.model == "finite_dipole"
    out = tmp_path / "out"
    assert cli_main(["run", "dipole_pair", "--out", str(out), "--no-progress",
                     "--no-plots"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["max_rel_energy_error"] < 1e-6
    # a sweep of it on Dask with the built-ins blocked: the slow fresh-venv test in
    # test_plugins_external.py (a worker cluster costs seconds to start)
