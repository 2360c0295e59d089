"""Potential parameters bound to body attributes: ``AllPairs("gravity")`` takes masses from bodies.

Truth: Newton's law summed pair by pair in numpy (independent of the compiled loops).
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from poissonkit.errors import InputError
from poissonkit.numerics import AllPairs, Body, Interaction, NBodySystem
from poissonkit.plugin.contributions import PairPotential, Param

G_SI = 6.67430e-11


def newton(pos: np.ndarray, mass: np.ndarray, G: float) -> tuple[np.ndarray, float]:
    """Forces and potential energy of point masses, pair by pair (no shared code)."""
    F = np.zeros_like(pos)
    U = 0.0
    for i in range(len(mass)):
        for j in range(i + 1, len(mass)):
            d = pos[j] - pos[i]
            r = np.linalg.norm(d)
            U -= G * mass[i] * mass[j] / r
            f = G * mass[i] * mass[j] * d / r**3  # pull on i towards j
            F[i] += f
            F[j] -= f
    return F, U


def cluster(n: int, seed: int = 3):
    rng = np.random.default_rng(seed)
    return rng.uniform(-1, 1, size=(n, 3)), rng.uniform(0.5, 2.0, size=n)


def test_all_pairs_gravity_reads_masses_from_the_bodies():
    pos, mass = cluster(7)
    bodies = [Body(f"s{k}", m) for k, m in enumerate(mass)]
    system = NBodySystem(bodies, [AllPairs("gravity", {"G": 0.7})])
    y = system.pack(pos, np.zeros_like(pos))
    F, _, U = system.forces(y)
    F_ref, U_ref = newton(pos, mass, 0.7)
    np.testing.assert_allclose(F, F_ref, rtol=1e-13, atol=1e-14 * np.abs(F_ref).max())
    assert U == pytest.approx(U_ref, rel=1e-13)
    # the same system written pair by pair with masses taken from the bodies too
    pairs = [Interaction(i, j, "gravity", {"G": 0.7}) for i in range(7) for j in range(i + 1, 7)]
    F2, _, U2 = NBodySystem(bodies, pairs).forces(y)
    np.testing.assert_allclose(F2, F_ref, rtol=1e-13, atol=1e-14 * np.abs(F_ref).max())
    assert U2 == pytest.approx(U_ref, rel=1e-13)


@pytest.mark.slow  # compiles two more kernel sets (~20 s)
def test_explicit_masses_still_win_and_si_scales_are_applied():
    from poissonkit.numerics.units import Scales

    pos, mass = cluster(4)
    bodies = [Body(f"s{k}", m) for k, m in enumerate(mass)]
    # explicit masses override the bodies' (here: twice body 0's mass in every pair's mass1)
    pairs = [Interaction(0, j, "gravity", {"mass1": 2 * mass[0]}) for j in (1, 2, 3)]
    F, _, _ = NBodySystem(bodies, pairs).forces(NBodySystem(bodies, pairs).pack(pos, 0 * pos))
    m2 = mass.copy()
    m2[0] *= 2
    F_ref = np.zeros_like(pos)
    for j in (1, 2, 3):
        d = pos[j] - pos[0]
        f = G_SI * m2[0] * mass[j] * d / np.linalg.norm(d) ** 3
        F_ref[0] += f
        F_ref[j] -= f
    np.testing.assert_allclose(F, F_ref, rtol=1e-12)
    # internal units: forces scale by the force unit
    s = Scales(length=2.0, mass=3.0, time=5.0)
    sys_s = NBodySystem(bodies, [AllPairs("gravity")], scales=s)
    Fs, _, Us = sys_s.forces(sys_s.pack(pos, 0 * pos, si=True))
    F_si, U_si = newton(pos, mass, G_SI)
    np.testing.assert_allclose(Fs * s.unit("force"), F_si, rtol=1e-12)
    assert Us * s.unit("energy") == pytest.approx(U_si, rel=1e-12)


def test_any_body_attribute_can_be_bound():
    """A Coulomb-like potential whose charges come from ``Body.attributes``."""
    r = sp.Symbol("r", real=True)
    coulomb = PairPotential(
        name="test_coulomb", doc="k q1 q2 / r",
        params=(Param("q1", "float", "charge 1"), Param("q2", "float", "charge 2"),
                Param("k", "float", "constant", default=1.0)),
        expr=lambda p: p["k"] * p["q1"] * p["q2"] / r, orientation="none",
        body_params=(("q1", "charge", 1), ("q2", "charge", 2)))
    pos, _ = cluster(5)
    q = np.array([1.0, -2.0, 0.5, 3.0, -1.0])
    bodies = [Body(f"c{k}", 1.0, attributes={"charge": qk}) for k, qk in enumerate(q)]
    F, _, U = NBodySystem(bodies, [AllPairs(coulomb, {"k": 2.0})]).forces(
        NBodySystem(bodies, [AllPairs(coulomb, {"k": 2.0})]).pack(pos, 0 * pos))
    # Coulomb is gravity with G m_i m_j -> -k q_i q_j
    F_ref = np.zeros_like(pos)
    U_ref = 0.0
    for i in range(5):
        for j in range(i + 1, 5):
            d = pos[j] - pos[i]
            rr = np.linalg.norm(d)
            U_ref += 2.0 * q[i] * q[j] / rr
            F_ref[j] += 2.0 * q[i] * q[j] * d / rr**3
            F_ref[i] -= 2.0 * q[i] * q[j] * d / rr**3
    np.testing.assert_allclose(F, F_ref, rtol=1e-13, atol=1e-13)
    assert U == pytest.approx(U_ref, rel=1e-13)
    # a body without the attribute: typed error naming body and attribute
    bad = bodies[:4] + [Body("neutral", 1.0)]
    with pytest.raises(InputError, match="neutral.*charge"):
        NBodySystem(bad, [AllPairs(coulomb)])


def test_bad_body_attributes_are_typed_errors():
    with pytest.raises(InputError, match="charge"):
        Body("a", 1.0, attributes={"charge": "lots"})
    with pytest.raises(InputError, match="finite"):
        Body("a", 1.0, attributes={"charge": float("nan")})
    with pytest.raises(InputError, match="field of the body"):
        Body("a", 1.0, attributes={"mass": 2.0})


SCENE = """
name = "three_stars"
description = "Three point masses bound by gravity; masses come from the bodies"

[[bodies]]
name = "a"
mass = 2.0e30
r = [0.0, 0.0, 0.0]

[[bodies]]
name = "b"
mass = 1.0e30
r = [1.5e11, 0.0, 0.0]
p = [0.0, 3.0e34, 0.0]

[[bodies]]
name = "c"
mass = 5.0e29
r = [0.0, 4.0e11, 1.0e10]
p = [-1.0e34, 0.0, 0.0]

[interactions]
potential = "gravity"

[run]
method = "splitting4"
step = 1e4
duration = 1e6
"""


def test_scene_gravity_without_pair_list_binds_masses(tmp_path):
    from poissonkit.scene import build_run, load_scene

    path = tmp_path / "stars.toml"
    path.write_text(SCENE)
    run = build_run(load_scene(path))
    system = run.system
    # one all-pairs interaction (one kernel), not a list of per-pair kernels
    assert len(system.interactions) == 1 and isinstance(system.interactions[0], AllPairs)
    s = system.scales
    F, _, U = system.forces(run.y0)
    pos = np.array([[0, 0, 0], [1.5e11, 0, 0], [0, 4.0e11, 1.0e10]], float)
    F_ref, U_ref = newton(pos, np.array([2.0e30, 1.0e30, 5.0e29]), G_SI)
    np.testing.assert_allclose(F * s.unit("force"), F_ref, rtol=1e-12)
    assert U * s.unit("energy") == pytest.approx(U_ref, rel=1e-12)
