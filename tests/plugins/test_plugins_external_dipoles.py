"""The example third-party plugin through every extension point a built-in plugin uses.

The plugin (examples/external_plugin) contributes two orientation-dependent potentials of
finite electric dipoles whose charges and lengths are body attributes, a model family of the
two (point dipole far, exact four charges near), a scene and a sweep outcome. The truth here is
an independent Coulomb sum over the four point charges, written in numpy in this file.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from poissonkit.plugin import model_family

K = 8.9875517923e9  # Coulomb's constant (CODATA 2018 ε0)


def charges(centre, nu, q, d):
    """The two point charges of a finite dipole: +q at +d/2 ν, −q at −d/2 ν."""
    centre, nu = np.asarray(centre, float), np.asarray(nu, float)
    return [(centre + 0.5 * d * nu, q), (centre - 0.5 * d * nu, -q)]


def coulomb(r, nu1, nu2, q1, d1, q2, d2):
    """Energy and force on body 2 of two finite dipoles, body 1 at the origin (direct sum)."""
    U, F = 0.0, np.zeros(3)
    for x1, a in charges(np.zeros(3), nu1, q1, d1):
        for x2, b in charges(r, nu2, q2, d2):
            v = x2 - x1
            dist = np.linalg.norm(v)
            U += K * a * b / dist
            F += K * a * b * v / dist ** 3
    return U, F


def random_unit(rng):
    v = rng.normal(size=3)
    return v / np.linalg.norm(v)


Q, D = 1e-8, 5e-3


def test_finite_dipole_energy_force_and_torques_match_the_coulomb_sum(example_discoverable):
    import poissonkit as pk

    rng = np.random.default_rng(3)
    for _ in range(20):
        r = random_unit(rng) * rng.uniform(1.2 * D, 20 * D)
        nu1, nu2 = random_unit(rng), random_unit(rng)
        out = pk.pair_interaction("finite_dipole", r, nu1, nu2, charge=Q, dipole_length=D)
        U, F = coulomb(r, nu1, nu2, Q, D, Q, D)
        assert out.energy == pytest.approx(U, rel=1e-10)
        assert np.allclose(out.force, F, rtol=1e-9, atol=1e-12 * np.linalg.norm(F))
        # torque on body 2 about its centre: Σ (x − c) × f over its charges
        T2 = np.zeros(3)
        for x2, b in charges(r, nu2, Q, D):
            f = sum(K * a * b * (x2 - x1) / np.linalg.norm(x2 - x1) ** 3
                    for x1, a in charges(np.zeros(3), nu1, Q, D))
            T2 += np.cross(x2 - r, f)
        assert np.allclose(out.torque2, T2, rtol=1e-9, atol=1e-12 * np.linalg.norm(T2))


def test_point_dipole_estimate_bounds_the_true_force_error(example_discoverable):
    import poissonkit as pk

    family = model_family("electric_dipoles")
    rng = np.random.default_rng(7)
    worst = 0.0
    for _ in range(300):
        d1, d2 = D, D * rng.uniform(0.2, 1.0)
        dist = rng.uniform(1.2, 40.0) * 0.5 * (d1 + d2)
        r = random_unit(rng) * dist
        nu1, nu2 = random_unit(rng), random_unit(rng)
        out = pk.pair_interaction("point_dipole", r, nu1, nu2, charge=Q, dipole_length1=d1,
                                  dipole_length2=d2)
        _, F = coulomb(r, nu1, nu2, Q, d1, Q, d2)
        scale = max(np.linalg.norm(F), 3 * K * Q * d1 * Q * d2 / dist ** 4)
        err = np.linalg.norm(out.force - F) / scale
        bound = family.estimate("point_dipole", dist, {"charge": Q, "dipole_length": d1},
                                {"charge": Q, "dipole_length": d2})
        assert err <= bound, (dist, err, bound)
        worst = max(worst, err / bound)
    assert worst > 0.2  # the estimate is a bound, not a gross overestimate


def test_auto_picks_the_point_dipole_far_and_the_exact_model_near(example_discoverable):
    import poissonkit as pk

    nu = (0.0, 0.0, 1.0)
    far = pk.pair_interaction("auto", (0.2, 0, 0), nu, nu, charge=Q, dipole_length=D, tol=1e-2)
    near = pk.pair_interaction("auto", (0.02, 0, 0), nu, nu, charge=Q, dipole_length=D,
                               tol=1e-2)
    assert (far.model, near.model) == ("point_dipole", "finite_dipole")
    assert far.estimated_error <= 1e-2 < model_family("electric_dipoles").estimate(
        "point_dipole", 0.02, {"charge": Q, "dipole_length": D},
        {"charge": Q, "dipole_length": D})
    # the far pair's point-dipole force is within the tolerance of the Coulomb sum
    _, F = coulomb(np.array([0.2, 0, 0]), np.array(nu), np.array(nu), Q, D, Q, D)
    assert np.linalg.norm(far.force - F) <= 1e-2 * np.linalg.norm(F)


def test_the_plugin_scene_is_planned_with_both_fidelities_and_runs_clean(example_discoverable):
    import poissonkit as pk
    from poissonkit.scene.registered import registered_run

    spec, _ = registered_run("dipole_pair")
    plan = spec.metadata["plan"]
    assert plan["models"]["finite_dipole"] == 1  # the orbiting pair, 20 mm apart
    assert plan["models"]["point_dipole"] == 2  # each with the fixed dipole 200 mm away
    # the body attributes reach the numerics: the system's energy at t = 0 is the Coulomb sum
    y0 = np.asarray(spec.y0)
    pos = {"a": np.zeros(3), "b": np.array([0.02, 0, 0]), "far": np.array([0.01, 0.2, 0])}
    axes = {"a": np.array([0, 0, 1.0]), "b": np.array([0, 0, -1.0]), "far": np.array([1.0, 0, 0])}
    U = sum(coulomb(pos[j] - pos[i], axes[i], axes[j], Q, D, Q, D)[0]
            for i, j in (("a", "b"), ("a", "far"), ("b", "far")))
    p = 6.24996117955443e-05
    T = 2 * p ** 2 / (2 * 1e-3) + 2 * (2.6e-7) ** 2 * (1 / 2.0833e-9) / 2
    E0 = spec.system.energy(y0) * spec.system.scales.energy
    # the far pairs use the point-dipole model: within its estimated error of the Coulomb sum
    assert E0 == pytest.approx(U + T, rel=2e-3)
    sol = pk.solve(spec.system, y0, spec.t_end, method=spec.method, step=spec.step)
    assert sol.summary()["max_rel_energy_error"] < spec.energy_tol
    r = spec.system.unpack(np.asarray(sol.y), si=True)["r"]
    gap = np.linalg.norm(r[:, 1] - r[:, 0], axis=-1)
    assert gap.min() > 0.015 and gap.max() < 0.03  # a bound orbit, no overlap


def test_the_plugin_scene_runs_by_name_from_the_cli(example_discoverable, tmp_path, capsys):
    import json

    from poissonkit.cli import main as cli_main

    out = tmp_path / "out"
    assert cli_main(["run", "dipole_pair", "--out", str(out), "--no-progress",
                     "--no-plots"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["max_rel_energy_error"] < 1e-6
    assert summary["min_distance_m"] > 0.015


def test_a_sweep_of_the_plugin_scene_reports_the_plugin_outcome(example_discoverable):
    import poissonkit as pk

    ds = pk.sweep("dipole_pair", {"bodies.b.p.1": [6.0e-5, 6.25e-5]},
                  outcomes=["fate", "max_axis_tilt", "max_rel_energy_error"], workers=1,
                  progress=False, fixed={"run.duration": 0.5})
    assert bool(ds["completed"].all()) and not bool(ds["failed"].any())
    # the slower start falls inwards until the dipoles' cylinders touch; the circular one stays
    assert list(ds["fate"].values) == [1, 0]
    tilt = ds["max_axis_tilt"].values
    assert ds["max_axis_tilt"].attrs["units"] == "rad"
    assert np.all(np.isfinite(tilt)) and np.all((tilt >= 0) & (tilt <= np.pi))
    # the circular orbit keeps its axes (the far dipole only nudges them)
    assert tilt[1] < 0.05
    # the bounded run keeps its energy; the infall up to the contact is recorded as it is
    energy = ds["max_rel_energy_error"].values
    assert energy[1] < 1e-8 and np.isfinite(energy[0])


def test_solve_on_a_system_built_from_the_plugin_potentials(example_discoverable):
    from poissonkit.numerics.nbody import Body, Interaction, NBodySystem
    from poissonkit.numerics.solver import solve

    params = {"charge1": Q, "charge2": Q, "dipole_length1": D, "dipole_length2": D}
    system = NBodySystem([Body("a", 1e-3, alpha=1 / 2.0833e-9),
                          Body("b", 1e-3, alpha=1 / 2.0833e-9)],
                         [Interaction(0, 1, "finite_dipole", params)])
    y0 = system.pack([[0, 0, 0], [0.03, 0, 0]], np.zeros((2, 3)),
                     [[0, 0, 1.0], [0, 0, 1.0]], [[0, 0, 2.6e-7], [0, 0, 2.6e-7]], si=True)
    U, _ = coulomb(np.array([0.03, 0, 0]), np.array([0, 0, 1.0]), np.array([0, 0, 1.0]),
                   Q, D, Q, D)
    T = 2 * (2.6e-7) ** 2 / 2.0833e-9 / 2
    assert system.energy(y0) == pytest.approx(U + T, rel=1e-10)
    sol = solve(system, y0, 0.2, method="splitting6", step=1e-3)
    s = sol.summary()
    assert s["max_rel_energy_error"] < 1e-8 and s["max_rel_casimir_drift"] < 1e-12
    assert math.isfinite(float(sol.y[-1][0]))
