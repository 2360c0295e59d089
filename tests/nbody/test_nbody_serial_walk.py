"""The serial pair walks (cell list and Verlet list) run without reference counts (issue 33).

The serial walk is what ``parallel=False`` systems and systems below ``parallel_min_bodies``
run. It is the parallel loop's walk compiled a second time, as a separate function without
numba's reference counts (the cell or neighbour lists are built by its caller, which keeps
them). Checked here: the serial walks are compiled so and their machine code holds no reference
count; their forces, torques and energy are those of a direct sum of point dipoles truncated at
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
from poissonkit.numerics.nbody import AllPairs, Body, NBodySystem, assemble, loops
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



@pytest.mark.parametrize("skin", [None, 0.015], ids=["cell_list", "verlet_list"])
def test_the_serial_walk_is_compiled_without_reference_counts(skin, monkeypatch):
    # compiled here, not loaded from the disk cache (a walk loaded inside its caller has no
    # LLVM IR to read): no disk cache, and the in-memory caches of terms and kernels emptied
    # for the duration of the test
    monkeypatch.setenv(CACHE_ENV, "off")
    monkeypatch.setattr(loops, "_term_cache", {})
    monkeypatch.setattr(assemble, "_cache", {})
    pos, nu = _cluster(3)
    s = _system(len(pos), skin, False)
    zeros = np.zeros_like(pos)
    s.forces(s.pack(pos, zeros, nu, zeros, normalize=True))
    term = loops.pair_force_term(*_dispatcher(s._kerns, s._rkerns), parallel=False,
                                 verlet=skin is not None)
    walks = [d for d in _reachable(term.plain) if d.py_func.__name__ == "walk_py"]
    assert len(walks) == 1 and walks[0].targetoptions.get("_nrt") is False
    ir = "".join(walks[0].inspect_llvm().values())
    # the module also holds the callees it links: the walk's own functions are those named
    # after it. The potential is compiled with counts (a user's kernel may allocate) and keeps
    # one count of its table ``B`` per call, which LLVM may inline into the walk; no other
    # array is counted
    own = [f for f in re.findall(r"^define [^\n]*\n.*?^}", ir, re.MULTILINE | re.DOTALL)
           if "walk_py" in f.split("\n", 1)[0]]
    call = r"call \w+ @NRT_(?:incref|decref)\(ptr ([^)]*)\)"
    counted = [a for f in own for a in re.findall(call, f)]
    assert own and all(a.startswith("%arg.B.") for a in counted), counted
