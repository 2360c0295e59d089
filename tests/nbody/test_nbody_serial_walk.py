"""The serial pair walks (cell list and Verlet list) run without reference counts (issue 33).

The serial walk is what ``parallel=False`` systems and systems below ``parallel_min_bodies``
run. It is the parallel loop's walk compiled a second time, as a separate function without
numba's reference counts (the cell or neighbour lists are built by its caller, which keeps
them). Checked here: the serial walks are compiled so and their machine code holds no reference
count (and, since the potential dispatchers go without counts when no kernel allocates, no
count of the attribute table ``B`` either; a kernel that allocates keeps its counts); their
forces, torques and energy are those of a direct sum of point dipoles truncated at
the cutoff (independent truth, Jackson 5.56 and τ = m × B); and they are the parallel loop's
on one thread bit for bit.
"""

from __future__ import annotations

import re
from collections.abc import Iterator

import numba
import numpy as np
import pytest
from numba.core.dispatcher import Dispatcher

from poissonkit.numerics.jit import CACHE_ENV
from poissonkit.numerics.nbody import (AllPairs, Body, NBodySystem, assemble, loops,
                                       pairkernels)
from poissonkit.numerics.nbody.pairkernels import _dispatcher

MU0 = 4e-7 * np.pi
MOMENT = 0.2  # A m²
CUTOFF = 0.09  # m, about 1.5 lattice spacings: each body has ~18 neighbours in reach


def _cluster(side: int = 5) -> tuple[np.ndarray, np.ndarray]:
    """Positions (jittered lattice of 6 cm) and unit axes of ``side³`` dipoles."""
    rng = np.random.default_rng(3)
    g = np.arange(side, dtype=float) * 0.06
    pos = np.array(np.meshgrid(g, g, g, indexing="ij")).reshape(3, -1).T
    pos = pos + rng.uniform(-0.01, 0.01, size=pos.shape)
    nu = rng.normal(size=pos.shape)
    return pos, nu / np.linalg.norm(nu, axis=1)[:, None]


def _system(n: int, skin: float | None, parallel: bool) -> NBodySystem:
    return NBodySystem([Body(f"m{k}", 0.01, 1e-6) for k in range(n)],
                       [AllPairs("dipole", {"moment1": MOMENT, "moment2": MOMENT})],
                       cutoff=CUTOFF, skin=skin, parallel=parallel, parallel_min_bodies=0)


def _truth(pos: np.ndarray, nu: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """Forces, torques and energy of point dipoles, every pair within the cutoff, in numpy."""
    n = len(pos)
    F, T, u = np.zeros((n, 3)), np.zeros((n, 3)), 0.0
    k = MU0 / (4 * np.pi)
    for i in range(n):
        for j in range(i + 1, n):
            d = pos[j] - pos[i]
            r = np.linalg.norm(d)
            if r > CUTOFF:
                continue
            e = d / r
            mi, mj = MOMENT * nu[i], MOMENT * nu[j]
            u += k / r**3 * (mi @ mj - 3 * (mi @ e) * (mj @ e))
            fj = 3 * k / r**4 * ((mi @ e) * mj + (mj @ e) * mi + (mi @ mj) * e
                                 - 5 * (mi @ e) * (mj @ e) * e)
            F[j] += fj
            F[i] -= fj
            T[j] += np.cross(mj, k / r**3 * (3 * (mi @ e) * e - mi))
            T[i] += np.cross(mi, k / r**3 * (3 * (mj @ e) * e - mj))
    return F, T, u


def _reachable(d: Dispatcher, seen: set[int] | None = None) -> Iterator[Dispatcher]:
    """``d`` and every compiled function its closure (and theirs) holds."""
    seen = set() if seen is None else seen
    if id(d) in seen:
        return
    seen.add(id(d))
    yield d
    for cell in d.py_func.__closure__ or ():
        v = cell.cell_contents
        if isinstance(v, Dispatcher):
            yield from _reachable(v, seen)


@pytest.mark.parametrize("skin", [None, 0.015], ids=["cell_list", "verlet_list"])
def test_the_serial_walk_gives_a_direct_sum_and_the_parallel_walk_bit_for_bit(skin):
    pos, nu = _cluster()
    serial, par = _system(len(pos), skin, False), _system(len(pos), skin, True)
    zeros = np.zeros_like(pos)
    y = serial.pack(pos, zeros, nu, zeros, normalize=True)
    got = [serial.forces(y)]
    before = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        got.append(par.forces(y))
    finally:
        numba.set_num_threads(before)
    for a, b in zip(*got):
        assert np.asarray(a).tobytes() == np.asarray(b).tobytes()

    F, T, u = got[0]
    f_ref, t_ref, u_ref = _truth(pos, nu)
    assert np.abs(f_ref).max() > 0 and np.abs(t_ref).max() > 0
    np.testing.assert_allclose(F, f_ref, rtol=0, atol=1e-12 * np.abs(f_ref).max())
    np.testing.assert_allclose(T, t_ref, rtol=0, atol=1e-12 * np.abs(t_ref).max())
    assert u == pytest.approx(u_ref, rel=1e-12)



def _allocating_dipole() -> Dispatcher:
    """The point-dipole kernel (SI, both moments ``MOMENT``) through an array: it allocates.
    A new one each time: a kernel already compiled with counts is called as it is, and the
    dispatcher calling it then goes without (as the pair loops call a counted one)."""

    @numba.njit
    def kernel(r, c1, c2, c3):
        w = np.array([MU0 / (4 * np.pi) * MOMENT * MOMENT / r**3, c3 - 3.0 * c1 * c2])
        return (w[0] * w[1], -3.0 * w[0] * w[1] / r, -3.0 * w[0] * c2, -3.0 * w[0] * c1, w[0])

    return kernel


def _own_counts(s: NBodySystem, skin: float | None) -> tuple[list[str], tuple[bool, ...]]:
    """The arrays the serial walk's own functions count, and whether the potential
    dispatchers ``(kern_any, kern_r)`` were compiled with counts."""
    pos, nu = _cluster(3)
    zeros = np.zeros_like(pos)
    s.forces(s.pack(pos, zeros, nu, zeros, normalize=True))
    dispatchers = _dispatcher(s._kerns, s._rkerns)
    term = loops.pair_force_term(*dispatchers, parallel=False, verlet=skin is not None)
    walks = [d for d in _reachable(term.plain) if d.py_func.__name__ == "walk_py"]
    assert len(walks) == 1 and walks[0].targetoptions.get("_nrt") is False
    ir = "".join(walks[0].inspect_llvm().values())
    # the module also holds the callees it links: the walk's own functions are those named
    # after it (LLVM may inline the potential into them)
    own = [f for f in re.findall(r"^define [^\n]*\n.*?^}", ir, re.MULTILINE | re.DOTALL)
           if "walk_py" in f.split("\n", 1)[0]]
    assert own
    call = r"call \w+ @NRT_(?:incref|decref)\(ptr ([^)]*)\)"
    return ([a for f in own for a in re.findall(call, f)],
            tuple(d.targetoptions.get("_nrt") is not False for d in dispatchers))


@pytest.fixture
def compiled_here(monkeypatch):
    """Compiled in the test, not loaded from the disk cache (a walk loaded inside its caller
    has no LLVM IR to read): no disk cache, the in-memory caches of terms, kernels and
    dispatchers emptied for the duration of the test."""
    monkeypatch.setenv(CACHE_ENV, "off")
    monkeypatch.setattr(loops, "_term_cache", {})
    monkeypatch.setattr(assemble, "_cache", {})
    monkeypatch.setattr(pairkernels, "_dispatch_cache", {})


@pytest.mark.parametrize("skin", [None, 0.015], ids=["cell_list", "verlet_list"])
def test_the_serial_walk_is_compiled_without_reference_counts(skin, compiled_here):
    # the registry's dipole allocates nothing: its dispatchers go without counts too, and the
    # walk counts no array at all (before, one count of the table ``B`` per pair)
    counted, with_counts = _own_counts(_system(27, skin, False), skin)
    assert counted == [] and with_counts == (False, False)


@pytest.mark.parametrize("skin", [None, 0.015], ids=["cell_list", "verlet_list"])
def test_a_potential_that_allocates_keeps_its_counts_and_its_forces(skin, compiled_here):
    s = NBodySystem([Body(f"m{k}", 0.01, 1e-6) for k in range(27)],
                    [AllPairs(_allocating_dipole())], cutoff=CUTOFF, skin=skin,
                    parallel=False, parallel_min_bodies=0)
    _, with_counts = _own_counts(s, skin)
    # the dispatcher that reaches it keeps the counts (numba needs them to allocate; the
    # radial one reaches no kernel: it depends on orientation), the walk still goes without
    assert with_counts == (True, False)
    pos, nu = _cluster(3)
    zeros = np.zeros_like(pos)
    F, T, u = s.forces(s.pack(pos, zeros, nu, zeros, normalize=True))
    f_ref, t_ref, u_ref = _truth(pos, nu)
    np.testing.assert_allclose(F, f_ref, rtol=0, atol=1e-12 * np.abs(f_ref).max())
    np.testing.assert_allclose(T, t_ref, rtol=0, atol=1e-12 * np.abs(t_ref).max())
    assert u == pytest.approx(u_ref, rel=1e-12)
