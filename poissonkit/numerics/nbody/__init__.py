"""Compiled N-body dynamics of symmetric tops and point masses with pair potentials.

State layout (internal, nondimensional units if ``scales`` is given; see
:mod:`poissonkit.conventions`): for the ``N`` moving bodies in the order given,
``r_1, p_1, …, r_N, p_N`` (6 numbers each), then for the ``K`` moving tops (bodies with
``alpha``) ``ν_1, m_1, …, ν_K, m_K`` (6 numbers each). Fixed bodies carry no state: their
position and axis are constants of the system, their pairs still act on the moving bodies.

Hamiltonian (seed 000 eq. 14): ``H = Σ p²/2M + Σ α m²/2 + Σ_pairs U_ij(r, c1, c2, c3)`` with
the bracket ``canonical(3)`` per body ⊕ ``e3()`` per top. Each pair (i, j), ``r = r_j − r_i``,
contributes (seed 000 eq. 20 generalised)::

    F   = −[U_r e + U_c1 (ν_i − c1 e)/r + U_c2 (ν_j − c2 e)/r]     ṗ_j += F,  ṗ_i −= F
    ṁ_i += U_c1 e × ν_i − U_c3 ν_i × ν_j,      ṁ_j += U_c2 e × ν_j + U_c3 ν_i × ν_j
    ν̇ = α m × ν,  ṙ = p/M

A test proves this equals ``ẋ = P∇H`` of the symbolic direct sum (``to_structure()``).

Pairs come from a list of :class:`Interaction` (one pair each) and/or :class:`AllPairs`
(every pair of a set of bodies, never materialised). With ``cutoff`` set, pairs farther apart
than the cutoff are skipped (the potential is truncated, not shifted) and :class:`AllPairs`
uses a compiled cell list, so one force evaluation costs O(N) at fixed density.

Modules, one job each:

* :mod:`~poissonkit.numerics.nbody.bodies` — the input model (:class:`Body`,
  :class:`Interaction`, :class:`AllPairs`) and its validation;
* :mod:`~poissonkit.numerics.nbody.data` — the named data and scratch every kernel reads;
* :mod:`~poissonkit.numerics.nbody.pairkernels` — a potential as given → compiled kernels in
  internal units → one dispatcher per system;
* :mod:`~poissonkit.numerics.nbody.pairterms` — energy, force and torques of one pair;
* :mod:`~poissonkit.numerics.nbody.celllists` — cell lists and the serial / parallel pair loop
  over them;
* :mod:`~poissonkit.numerics.nbody.verlet` — Verlet neighbour lists (``skin``) kept between
  evaluations and the pair loop that walks them;
* :mod:`~poissonkit.numerics.nbody.state` — compiled pieces independent of the potentials
  (gather, kick by stored forces, drift, distances);
* :mod:`~poissonkit.numerics.nbody.loops` — the pair-force term and the kernels built on it;
* :mod:`~poissonkit.numerics.nbody.assemble` — the one generator of ``rhs``, ``kick`` (plain and
  compensated), ``energy`` and ``forces`` from a layout and a sum of force terms;
* :mod:`~poissonkit.numerics.nbody.direct` — the point-mass layout and the direct-sum term;
* :mod:`~poissonkit.numerics.nbody.options`, :mod:`~poissonkit.numerics.nbody.scaling`,
  :mod:`~poissonkit.numerics.nbody.table` — the constructor's input checks, the bodies in
  internal units and the kernel table;
* :mod:`~poissonkit.numerics.nbody.evaluate` — energy and right-hand side with coincident
  bodies reported as :class:`OverlapError`;
* :mod:`~poissonkit.numerics.nbody.system` — :class:`NBodySystem`, the façade.
"""

from __future__ import annotations

from poissonkit.numerics.nbody.bodies import AllPairs, Body, Interaction, NonUnitAxisError
from poissonkit.numerics.nbody.celllists import cell_list, forward_cells
from poissonkit.numerics.nbody.evaluate import (OverlapError, coincident_pair, evaluate_energy,
                                                evaluate_rhs)
from poissonkit.numerics.nbody.pairkernels import _resolve_kernel  # noqa: F401 (former name)
from poissonkit.numerics.nbody.pairkernels import resolve_kernel
from poissonkit.numerics.nbody.state import apply_forces
from poissonkit.numerics.nbody.system import PARALLEL_MIN_BODIES, NBodySystem

# the errors keep the path they are raised and caught under (tracebacks, pickled exceptions)
NonUnitAxisError.__module__ = __name__
OverlapError.__module__ = __name__

__all__ = [
    "PARALLEL_MIN_BODIES", "AllPairs", "Body", "Interaction", "NBodySystem", "NonUnitAxisError",
    "OverlapError", "apply_forces", "cell_list", "coincident_pair", "evaluate_energy",
    "evaluate_rhs", "forward_cells", "resolve_kernel",
]
