"""The multi-threaded cell-list pair loop: bit-for-bit the serial loop, and right.

Claims checked here:

* the parallel loop on 2 threads and on 1 thread (``numba.set_num_threads``) gives forces,
  torques and energy **bitwise** equal to the serial loop (``parallel=False``), with a
  truncated and a smooth cutoff, for magnets (forces and torques) and for the
  orientation-free point-mass fast path; repeated evaluations and whole runs (slow test) are
  bitwise identical too;
* independent truth: a direct O(N²) numpy sum of the analytic point-dipole forces and torques
  (``F_j = 3/r⁴ [c1 ν_j + c2 ν_i + c3 e − 5 c1 c2 e]``, ``τ_i = ν_i × B_j``) and of Newtonian
  gravity, truncated at the cutoff, agrees to 1e-12 of the largest force;
* bad ``parallel`` / ``parallel_min_bodies`` raise :class:`InputError` naming the option.

The parallel loop needs at least two numba threads; on a one-core machine those tests skip.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

import numba
import numpy as np
import pytest
import sympy as sp

from poissonkit.errors import InputError
from poissonkit.numerics import AllPairs, Body, NBodySystem, solve

R, C1, C2, C3 = sp.symbols("r c1 c2 c3", real=True)
DIPOLE = (C3 - 3 * C1 * C2) / R**3
CUTOFF = 2.0
TWO = numba.config.NUMBA_NUM_THREADS >= 2
needs_two = pytest.mark.skipif(not TWO, reason="the parallel loop needs >= 2 numba threads")


@contextmanager
def numba_threads(k: int) -> Iterator[None]:
    """Run the block on ``k`` numba threads, then restore the previous number."""
    before = numba.get_num_threads()
    numba.set_num_threads(k)
    try:
        yield
    finally:
        numba.set_num_threads(before)


def lattice(side: int, seed: int) -> np.ndarray:
    """A jittered cubic lattice of spacing 1 (no close pairs, ~30 neighbours within 2)."""
    rng = np.random.default_rng(seed)
    g = np.arange(side, dtype=float)
    pos = np.array(np.meshgrid(g, g, g, indexing="ij")).reshape(3, -1).T
    return pos + rng.uniform(-0.2, 0.2, size=pos.shape)


def magnets(parallel: bool, smooth: float | None = None, side: int = 7, seed: int = 3):
    """``side³`` dipolar tops (unit moments, mass 1, alpha 1), parallel loop from 0 bodies."""
    rng = np.random.default_rng(seed)
    pos = lattice(side, seed)
    n = len(pos)
    bodies = [Body(f"b{k}", 1.0, 1.0) for k in range(n)]
    system = NBodySystem(bodies, [AllPairs(DIPOLE)], cutoff=CUTOFF, smooth_cutoff=smooth,
                         parallel=parallel, parallel_min_bodies=0)
    y = system.pack(pos, 0.1 * rng.normal(size=(n, 3)), rng.normal(size=(n, 3)),
                    0.1 * rng.normal(size=(n, 3)), normalize=True)
    return system, y


def planets(parallel: bool, side: int = 7, seed: int = 5):
    """``side³`` point masses of unequal mass under gravity (the fast path, masses per pair)."""
    rng = np.random.default_rng(seed)
    pos = lattice(side, seed)
    n = len(pos)
    masses = rng.uniform(0.5, 2.0, size=n)
    bodies = [Body(f"p{k}", float(m)) for k, m in enumerate(masses)]
    system = NBodySystem(bodies, [AllPairs("gravity", {"G": 1.0})], cutoff=CUTOFF,
                         parallel=parallel, parallel_min_bodies=0)
    y = system.pack(pos, 0.1 * rng.normal(size=(n, 3)))
    return system, y, masses


def assert_bitwise(a, b) -> None:
    Fa, Ta, Ua = a
    Fb, Tb, Ub = b
    np.testing.assert_array_equal(Fa, Fb)
    np.testing.assert_array_equal(Ta, Tb)
    assert Ua == Ub


@needs_two
@pytest.mark.parametrize("smooth", [None, 1.5], ids=["truncated", "smooth"])
def test_parallel_magnet_forces_torques_and_energy_equal_the_serial_loop_bitwise(smooth):
    serial, y = magnets(False, smooth)
    par, y2 = magnets(True, smooth)
    np.testing.assert_array_equal(y, y2)
    assert not serial._parallel and par._parallel  # two different loops really run
    s = serial.forces(y)
    with numba_threads(2):
        p = par.forces(y)
        assert_bitwise(par.forces(y), p)  # run to run
        assert par.energy(y) == serial.energy(y)
    with numba_threads(1):
        p1 = par.forces(y)
    assert np.abs(s[0]).max() > 0 and np.abs(s[1]).max() > 0
    assert_bitwise(p, s)
    assert_bitwise(p1, s)


@pytest.mark.slow  # 12-15 s on a cold kernel cache; the default run keeps a smaller sibling
@needs_two
def test_parallel_point_mass_fast_path_equals_the_serial_loop_bitwise():
    serial, y, _ = planets(False)
    par, _, _ = planets(True)
    assert par._parallel and par.data.set_central.tolist() == [1]  # orientation-free fast path
    with numba_threads(2):
        p = par.forces(y)
    with numba_threads(1):
        p1 = par.forces(y)
    s = serial.forces(y)
    assert_bitwise(p, s)
    assert_bitwise(p1, s)


@pytest.mark.slow  # compiles splitting4 for two kernel sets; the force tests cover the kick
@needs_two
def test_a_run_on_two_threads_is_the_run_on_one_thread_bit_for_bit():
    serial, y = magnets(False, 1.5, side=5)
    par, _ = magnets(True, 1.5, side=5)
    a = solve(serial, y, 0.1, method="splitting4", step=0.01)
    with numba_threads(2):
        b = solve(par, y, 0.1, method="splitting4", step=0.01)
        c = solve(par, y, 0.1, method="splitting4", step=0.01)
    assert not np.array_equal(a.y[-1], y)  # it moved
    np.testing.assert_array_equal(b.y, a.y)
    np.testing.assert_array_equal(c.y, b.y)


def dipole_truth(pos: np.ndarray, nu: np.ndarray, cutoff: float):
    """Direct O(N²) sum of point-dipole forces, torques and energy (numpy, no cell list)."""
    d = pos[None, :, :] - pos[:, None, :]  # d[i, j] = r_j − r_i
    r = np.linalg.norm(d, axis=-1)
    np.fill_diagonal(r, np.inf)
    mask = r <= cutoff
    e = d / r[..., None]
    c1 = np.einsum("ijk,ik->ij", e, nu)  # e · ν_i
    c2 = np.einsum("ijk,jk->ij", e, nu)  # e · ν_j
    c3 = nu @ nu.T
    r3 = np.where(mask, r**-3, 0.0)
    pair_u = r3 * (c3 - 3 * c1 * c2)
    energy = 0.5 * np.sum(pair_u)
    # force on j from i, summed over i
    fj = 3 * (r3 / r)[..., None] * (c1[..., None] * nu[None, :, :] + c2[..., None] * nu[:, None, :]
                                    + (c3 - 5 * c1 * c2)[..., None] * e)
    force = fj.sum(axis=0)
    # torque on i: ν_i × B_j(r_i), B_j = (3 (ν_j·e) e − ν_j) / r³
    b = r3[..., None] * (3 * c2[..., None] * e - nu[None, :, :])
    torque = np.cross(nu, b.sum(axis=1))
    return force, torque, energy, 0.5 * np.sum(np.abs(pair_u))


@needs_two
def test_parallel_magnet_forces_match_a_direct_numpy_sum_of_point_dipoles():
    par, y = magnets(True, side=6)
    with numba_threads(2):
        F, T, U = par.forces(y)
    st = par.unpack(y)
    f_ref, t_ref, u_ref, u_scale = dipole_truth(st["r"], st["nu"], CUTOFF)
    scale = np.abs(f_ref).max()
    np.testing.assert_allclose(F, f_ref, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(T, t_ref, rtol=0, atol=1e-12 * np.abs(t_ref).max())
    assert abs(U - u_ref) <= 1e-13 * u_scale


@needs_two
def test_parallel_gravity_matches_a_direct_numpy_sum():
    par, y, m = planets(True, side=6)
    with numba_threads(2):
        F, _, U = par.forces(y)
    pos = par.unpack(y)["r"]
    d = pos[None, :, :] - pos[:, None, :]
    r = np.linalg.norm(d, axis=-1)
    np.fill_diagonal(r, np.inf)
    w = np.where(r <= CUTOFF, m[:, None] * m[None, :] / r**3, 0.0)
    f_ref = -(w[..., None] * d).sum(axis=0)  # force on j pulls it towards every i
    u_ref = -0.5 * np.sum(np.where(r <= CUTOFF, m[:, None] * m[None, :] / r, 0.0))
    np.testing.assert_allclose(F, f_ref, rtol=0, atol=1e-12 * np.abs(f_ref).max())
    assert abs(U - u_ref) <= 1e-12 * abs(u_ref)


@pytest.mark.parametrize("bad", [0, 1, "yes", None])
def test_a_non_boolean_parallel_is_refused_naming_the_option(bad):
    with pytest.raises(InputError, match="parallel"):
        NBodySystem([Body("a", 1.0), Body("b", 1.0)], [AllPairs("gravity", {"G": 1.0})],
                    cutoff=1.0, parallel=bad)


@pytest.mark.parametrize("bad", [-5, 2.5, "10", True])
def test_a_bad_parallel_threshold_is_refused(bad):
    with pytest.raises(InputError, match="parallel_min_bodies"):
        NBodySystem([Body("a", 1.0), Body("b", 1.0)], cutoff=1.0, parallel_min_bodies=bad)


def test_a_serial_or_small_system_compiles_no_parallel_loop():
    bodies = [Body(f"p{k}", 1.0) for k in range(10)]
    pairs = [AllPairs("gravity", {"G": 1.0})]
    assert not NBodySystem(bodies, pairs, cutoff=1.0)._parallel  # below the default threshold
    assert not NBodySystem(bodies, pairs, cutoff=1.0, parallel=False,
                           parallel_min_bodies=0)._parallel
    assert not NBodySystem(bodies, pairs, parallel_min_bodies=0)._parallel  # no cutoff
