"""A system without cutoff compiles no cell-list loop (its first run compiles seconds less),
and its energy is still the pair sum worked out by hand; with a cutoff the cell loop is there."""

from __future__ import annotations

import inspect

import numpy as np

from poissonkit.numerics.nbody import AllPairs, Body, NBodySystem, loops
from poissonkit.numerics.units import Scales

UNIT = Scales(length=1.0, mass=1.0, time=1.0)


def _system(**kw: object) -> NBodySystem:
    # a fixed body takes the general kernels (the pair loop of loops.py), not the direct sum
    bodies = [Body("a", 2.0, position=(0.0, 0.0, 0.0)),
              Body("b", 3.0, position=(2.0, 0.0, 0.0)),
              Body("c", 5.0, fixed=True, position=(0.0, 4.0, 0.0))]
    return NBodySystem(bodies, [AllPairs("gravity", {"G": 1.0})], scales=UNIT, **kw)


def _set_pairs(system: NBodySystem) -> object:
    assert system.kernels is not None  # built now: the pair term is in the cache
    kern = [t for k, t in loops._term_cache.items() if k[3] is (system.cutoff is not None)]
    return [inspect.getclosurevars(t.plain.py_func).nonlocals["set_pairs"] for t in kern]


def test_no_cutoff_leaves_the_cell_loop_out_and_keeps_the_pair_sum():
    s = _system()
    assert all(sp is loops._no_cell_loop for sp in _set_pairs(s))
    y = s.pack([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0]], [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
    by_hand = -(2.0 * 3.0 / 2.0 + 2.0 * 5.0 / 4.0 + 3.0 * 5.0 / np.hypot(2.0, 4.0))
    assert np.isclose(float(s.energy(y)), by_hand, rtol=1e-14)


def test_a_cutoff_keeps_the_cell_loop():
    s = _system(cutoff=10.0)
    assert _set_pairs(s) and not any(sp is loops._no_cell_loop for sp in _set_pairs(s))
