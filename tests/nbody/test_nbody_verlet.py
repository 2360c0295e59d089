"""Verlet neighbour lists (``NBodySystem(..., skin=s)``): right, safe and bitwise parallel.

Claims checked here:

* independent truth: forces, torques and energy of dipoles with a hard core match a direct
  O(N²) numpy sum truncated at the cutoff;
* the list is rebuilt whenever a body moved more than ``s/2`` (a pair that jumps from far
  outside the list into the cutoff is found: a stale list would miss it and give zero), and
  kept when every body moved less (pairs that entered the cutoff are still found);
* serial and parallel walks are bitwise equal on 1 and on 2 threads, for a fresh list and for
  a kept one after the bodies moved;
* a run with a skin conserves energy and momentum like the cell-list run of the same system
  and follows it to round-off amplified by the dynamics;
* the orientation-free fast path through the list, in SI units with scales (the skin in
  metres), matches a direct sum of Newtonian gravity, serial and parallel bitwise;
* a bad skin is refused naming the option.
"""

from __future__ import annotations

import numba
import numpy as np
import pytest
import sympy as sp

from poissonkit.errors import InputError
from poissonkit.numerics import AllPairs, Body, NBodySystem, solve

R, C1, C2, C3 = sp.symbols("r c1 c2 c3", real=True)
GAS = (C3 - 3 * C1 * C2) / (20 * R**3) + 1 / R**9  # weak dipoles with a hard core
CUTOFF = 2.0
SKIN = 0.3
needs_two = pytest.mark.skipif(numba.config.NUMBA_NUM_THREADS < 2,
                               reason="the parallel loop needs >= 2 numba threads")


def cluster(side: int = 5, seed: int = 2):
    """Positions, momenta, axes and spins of ``side³`` magnets on a jittered lattice of 1.4."""
    rng = np.random.default_rng(seed)
    g = np.arange(side, dtype=float) * 1.4
    pos = np.array(np.meshgrid(g, g, g, indexing="ij")).reshape(3, -1).T
    pos = pos + rng.uniform(-0.15, 0.15, size=pos.shape)
    n = len(pos)
    return (pos, 0.3 * rng.normal(size=(n, 3)), rng.normal(size=(n, 3)),
            0.1 * rng.normal(size=(n, 3)))


def system(n: int, skin: float | None = SKIN, parallel: bool = False,
           smooth: float | None = None) -> NBodySystem:
    bodies = [Body(f"b{k}", 1.0, 1.0) for k in range(n)]
    return NBodySystem(bodies, [AllPairs(GAS)], cutoff=CUTOFF, skin=skin, parallel=parallel,
                       parallel_min_bodies=0, smooth_cutoff=smooth)


def truth(pos: np.ndarray, nu: np.ndarray):
    """Direct numpy sum of the dipole forces/torques/energy (/20) plus the 1/r⁹ core."""
    d = pos[None, :, :] - pos[:, None, :]  # d[i, j] = r_j − r_i
    r = np.linalg.norm(d, axis=-1)
    np.fill_diagonal(r, np.inf)
    mask = r <= CUTOFF
    e = d / r[..., None]
    c1 = np.einsum("ijk,ik->ij", e, nu)
    c2 = np.einsum("ijk,jk->ij", e, nu)
    c3 = nu @ nu.T
    r3 = np.where(mask, r**-3, 0.0) / 20
    r9 = np.where(mask, r**-9, 0.0)
    energy = 0.5 * np.sum(r3 * (c3 - 3 * c1 * c2) + r9)
    fj = (3 * (r3 / r)[..., None] * (c1[..., None] * nu[None, :, :]
                                     + c2[..., None] * nu[:, None, :]
                                     + (c3 - 5 * c1 * c2)[..., None] * e)
          + (9 * r9 / r)[..., None] * e)
    b = r3[..., None] * (3 * c2[..., None] * e - nu[None, :, :])
    return fj.sum(axis=0), np.cross(nu, b.sum(axis=1)), energy


def evaluate(s: NBodySystem, y: np.ndarray, work: tuple) -> tuple:
    u = s.kernels.forces(y, s.data, work)
    return work.F.copy(), work.T.copy(), float(u)


def test_listed_forces_torques_and_energy_match_a_direct_numpy_sum():
    pos, p, nu, m = cluster()
    s = system(len(pos))
    y = s.pack(pos, p, nu, m, normalize=True)
    F, T, U = s.forces(y)
    f_ref, t_ref, u_ref = truth(pos, s.unpack(y)["nu"])
    np.testing.assert_allclose(F, f_ref, rtol=0, atol=1e-12 * np.abs(f_ref).max())
    np.testing.assert_allclose(T, t_ref, rtol=0, atol=1e-12 * np.abs(t_ref).max())
    assert abs(U - u_ref) <= 1e-12 * abs(u_ref)


def three_bodies(gap: float):
    """Bodies 0 and 1 a hard-core distance apart, body 2 ``gap`` beyond body 1 on the x axis."""
    pos = np.array([[0.0, 0.0, 0.0], [1.2, 0.0, 0.0], [1.2 + gap, 0.0, 0.0]])
    nu = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]])
    s = system(3)
    return s, pos, nu


def test_a_body_that_moved_more_than_half_the_skin_is_found_through_a_rebuilt_list():
    s, pos, nu = three_bodies(CUTOFF + SKIN + 1.0)  # body 2 far outside the list
    work = s.work()
    y0 = s.pack(pos, np.zeros((3, 3)), nu, np.zeros((3, 3)))
    evaluate(s, y0, work)
    pos[2, 0] = 1.2 + 0.5 * CUTOFF  # a jump into the cutoff of body 1
    y1 = s.pack(pos, np.zeros((3, 3)), nu, np.zeros((3, 3)))
    F, T, U = evaluate(s, y1, work)
    f_ref, t_ref, u_ref = truth(pos, nu)
    assert abs(f_ref[2]).max() > 1e-3  # the pair acts
    np.testing.assert_allclose(F, f_ref, rtol=0, atol=1e-13 * np.abs(f_ref).max())
    np.testing.assert_allclose(T, t_ref, rtol=0, atol=1e-13 * np.abs(t_ref).max())
    assert U == pytest.approx(u_ref, rel=1e-13)
    assert work.lists.refs[0][:, 0].max() == pos[2, 0]  # the list was rebuilt at these positions


def test_a_kept_list_finds_pairs_that_entered_the_cutoff_within_half_the_skin():
    s, pos, nu = three_bodies(CUTOFF + 0.25)  # listed (within cutoff + skin), not acting
    work = s.work()
    y0 = s.pack(pos, np.zeros((3, 3)), nu, np.zeros((3, 3)))
    _, _, u0 = evaluate(s, y0, work)
    ref0 = np.array(work.lists.refs[0])
    pos[1, 0] += 0.13  # every body moves less than skin / 2 = 0.15; 1 and 2 towards
    pos[2, 0] -= 0.14  # each other, into the cutoff
    pos[0, 1] += 0.1
    y1 = s.pack(pos, np.zeros((3, 3)), nu, np.zeros((3, 3)))
    F, T, U = evaluate(s, y1, work)
    np.testing.assert_array_equal(np.array(work.lists.refs[0]), ref0)  # the list was kept
    f_ref, t_ref, u_ref = truth(pos, nu)
    assert np.linalg.norm(pos[2] - pos[1]) < CUTOFF and abs(f_ref[2]).max() > 1e-4
    np.testing.assert_allclose(F, f_ref, rtol=0, atol=1e-13 * np.abs(f_ref).max())
    assert U == pytest.approx(u_ref, rel=1e-13) and U != u0


@needs_two
def test_serial_and_parallel_walks_are_bitwise_equal_fresh_and_after_the_bodies_moved():
    pos, p, nu, m = cluster()
    n = len(pos)
    serial, par = system(n), system(n, parallel=True)
    assert par._parallel and not serial._parallel
    ws, w1, w2 = serial.work(), par.work(), par.work()
    rng = np.random.default_rng(7)
    before = numba.get_num_threads()
    try:
        for step in range(4):  # moves of 0.02 keep the list, 0.3 rebuild it
            jolt = 0.02 if step < 3 else 0.3
            moved = pos + jolt * rng.uniform(-1, 1, size=pos.shape) if step else pos
            y = serial.pack(moved, p, nu, m, normalize=True)
            a = evaluate(serial, y, ws)
            numba.set_num_threads(2)
            b = evaluate(par, y, w2)
            numba.set_num_threads(1)
            c = evaluate(par, y, w1)
            for got in (b, c):
                np.testing.assert_array_equal(got[0], a[0])
                np.testing.assert_array_equal(got[1], a[1])
                assert got[2] == a[2]
    finally:
        numba.set_num_threads(before)


@pytest.mark.slow  # compiles splitting2 for two kernel sets (~40 s on a cold cache)
def test_a_run_with_a_skin_conserves_energy_and_momentum_like_the_cell_list_run():
    pos, p, nu, m = cluster()
    n = len(pos)
    # a smooth cutoff: the energy error is the integrator's, not jumps at the cutoff
    listed, cells = system(n, skin=0.1, smooth=1.5), system(n, skin=None, smooth=1.5)
    y = cells.pack(pos, p, nu, m, normalize=True)
    a = solve(listed, y, 2.0, method="splitting2", step=0.01, save_every=10)
    b = solve(cells, y, 2.0, method="splitting2", step=0.01, save_every=10)
    r = listed.unpack(a.y)["r"]
    assert np.abs(r[-1] - r[0]).max() > 0.3  # moved by several skins: rebuilt on the way
    ea, eb = listed.energy(a.y), cells.energy(b.y)
    kin = 0.5 * np.sum(p**2)
    err_a, err_b = np.abs(ea - ea[0]).max() / kin, np.abs(eb - eb[0]).max() / kin
    assert err_a < 1e-3 and err_a == pytest.approx(err_b, rel=1e-3)
    pa = listed.linear_momentum(a.y)
    assert np.abs(pa - pa[0]).max() < 1e-12 * np.abs(p).sum()
    assert np.abs(a.y[-1] - b.y[-1]).max() < 1e-8 * np.abs(b.y[-1]).max()


def test_a_skin_needs_a_cutoff():
    with pytest.raises(InputError, match="skin"):
        NBodySystem([Body("a", 1.0), Body("b", 1.0)], [AllPairs("gravity", {"G": 1.0})],
                    skin=0.3)


@pytest.mark.parametrize("bad", [0, -0.1, float("nan"), float("inf"), "0.3", True])
def test_a_bad_skin_is_refused_naming_the_option(bad):
    with pytest.raises(InputError, match="skin"):
        NBodySystem([Body("a", 1.0), Body("b", 1.0)], [AllPairs("gravity", {"G": 1.0})],
                    cutoff=1.0, skin=bad)


@pytest.mark.slow  # its own serial and parallel gravity kernels (~16 s cold)
@needs_two
def test_listed_gravity_in_si_units_matches_a_direct_sum_serial_and_parallel_bitwise():
    """The orientation-free fast path through the list, with scales: the skin is given in
    metres like the cutoff (here 300 m = 0.3 internal lengths)."""
    from poissonkit.numerics import Scales

    rng = np.random.default_rng(5)
    L = 1000.0
    pos = cluster(side=5)[0] * L
    n = len(pos)
    masses = rng.uniform(0.5, 2.0, size=n)
    bodies = [Body(f"p{k}", float(m)) for k, m in enumerate(masses)]
    scales = Scales(length=L)

    def planets(parallel: bool) -> NBodySystem:
        return NBodySystem(bodies, [AllPairs("gravity", {"G": 1.0})], cutoff=CUTOFF * L,
                           scales=scales, skin=SKIN * L, parallel=parallel,
                           parallel_min_bodies=0)

    serial, par = planets(False), planets(True)
    assert serial.data.set_central.tolist() == [1]  # the fast path
    assert serial.work().lists.skin == pytest.approx(SKIN)  # internal units
    y = serial.pack(pos, np.zeros((n, 3)), si=True)
    F, _, U = serial.forces(y)
    before = numba.get_num_threads()
    numba.set_num_threads(2)
    try:
        F2, _, U2 = par.forces(y)
    finally:
        numba.set_num_threads(before)
    np.testing.assert_array_equal(F2, F)
    assert U2 == U
    r = pos / L
    d = r[None, :, :] - r[:, None, :]
    dist = np.linalg.norm(d, axis=-1)
    np.fill_diagonal(dist, np.inf)
    mm = masses[:, None] * masses[None, :]
    w = np.where(dist <= CUTOFF, mm / dist**3, 0.0)
    f_ref = -(w[..., None] * d).sum(axis=0)
    u_ref = -0.5 * np.sum(np.where(dist <= CUTOFF, mm / dist, 0.0))
    # internal units: G = 1 m³/(kg s²) becomes 1/L³ with the unit mass and time
    np.testing.assert_allclose(F * L**3, f_ref, rtol=0, atol=1e-12 * np.abs(f_ref).max())
    assert U * L**3 == pytest.approx(u_ref, rel=1e-12)
