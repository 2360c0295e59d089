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
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numba
import numpy as np
import sympy as sp

from poissonkit.errors import DimensionError, InputError
from poissonkit.numerics.jit import compile_generated, jit
from poissonkit.numerics.kernels import (
    Kernels,
    kahan_add,
    rotate_slot,
    rotate_slot_compensated,
    zero2,
)
from poissonkit.numerics.potentials import (
    compile_bound_potential,
    compile_potential,
    kernel_from_expr,
    radial_kernel,
)
from poissonkit.numerics.units import Scales
from poissonkit.plugin.contributions import PairPotential


class NonUnitAxisError(InputError):
    """A top's axis ``ν`` is not a unit vector (pass ``normalize=True`` to normalise it)."""


class OverlapError(InputError):
    """Two bodies (not both fixed) sit at exactly the same place, where pair forces are singular."""


def coincident_pair(positions: np.ndarray, fixed: np.ndarray) -> tuple[int, int] | None:
    """Indices of two bodies at exactly the same position, or ``None``.

    Pairs of two fixed bodies are ignored (they exert no force on any degree of freedom).
    Sorting makes this O(n log n), so it is cheap even for large systems.
    """
    if positions.shape[0] < 2:
        return None
    order = np.lexsort(positions.T[::-1])
    ordered = positions[order]
    same = np.all(ordered[1:] == ordered[:-1], axis=1)
    # identical rows are adjacent after sorting, so a group holding a moving body has an
    # adjacent pair with a moving member
    for k in np.nonzero(same)[0]:
        a, b = int(order[k]), int(order[k + 1])
        if not (fixed[a] and fixed[b]):
            return (min(a, b), max(a, b))
    return None


def evaluate_energy(system: Any, y: Any) -> float | np.ndarray:
    """``H(y)`` of a compiled system (``kernels.energy``); rows of a 2-D array give one value each.

    Shared by :class:`NBodySystem` and :class:`~poissonkit.numerics.twobody.TwoBodySystem`.
    A non-finite value or a division by zero inside a potential kernel is checked against
    coincident bodies and then raises :class:`OverlapError`.
    """
    y = np.asarray(y, dtype=float)
    w = system.work()
    energy = system.kernels.energy

    def one(row: np.ndarray) -> float:
        state = system._state(row)
        try:
            value = float(energy(state, system.data, w))
        except ZeroDivisionError:
            system.check_overlap(state)
            raise
        if not math.isfinite(value):
            system.check_overlap(state)
        return value

    if y.ndim == 2:
        return np.array([one(row) for row in y])
    return one(y)


def evaluate_rhs(system: Any, y: Any) -> np.ndarray:
    """``ẏ`` of a compiled system (``kernels.rhs``), raising :class:`OverlapError` at coincidences."""
    y = system._state(y)
    out = np.empty_like(y)
    try:
        system.kernels.rhs(y, system.data, system.work(), out)
    except ZeroDivisionError:
        system.check_overlap(y)
        raise
    if not np.all(np.isfinite(out)):
        system.check_overlap(y)
    return out


def _vector3(value: Any, what: str) -> tuple[float, float, float]:
    """``value`` as a finite 3-tuple of floats, else :class:`InputError` naming ``what``."""
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{what} must be three numbers, got {value!r}") from None
    if a.shape != (3,):
        raise InputError(f"{what} must have shape (3,), got shape {a.shape}: {value!r}")
    if not np.all(np.isfinite(a)):
        raise InputError(f"{what} must be finite, got {value!r}")
    return (float(a[0]), float(a[1]), float(a[2]))


@dataclass(frozen=True)
class Body:
    """A rigid body: symmetric top (``alpha`` given) or point mass (``alpha=None``).

    Parameters
    ----------
    name
        Unique name; coordinates are called ``name.r_x`` etc.
    mass
        Mass [kg] (or internal unit without scales), > 0.
    alpha
        ``1 / I_perp`` [1/(kg m²)], > 0, or ``None`` for a point mass.
    fixed
        Fixed bodies carry no degrees of freedom; they act through their pairs.
    position, axis
        Position [m] and unit axis of a fixed body (required when ``fixed``).
    attributes
        Further per-body quantities (SI) that pair potentials may take from the body, e.g.
        ``{"charge": 1e-9}`` or ``{"moment": 0.15}`` (see ``PairPotential.body_params``);
        stored as sorted ``(name, value)`` pairs. ``mass`` and ``alpha`` are always available.
    """

    name: str
    mass: float
    alpha: float | None = None
    fixed: bool = False
    position: tuple[float, float, float] | None = None
    axis: tuple[float, float, float] | None = None
    attributes: Any = ()

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name:
            raise InputError(f"body name must be a non-empty string, got {self.name!r}")
        for attr in ("mass",) + (("alpha",) if self.alpha is not None else ()):
            v = getattr(self, attr)
            try:
                v = float(v)
            except (TypeError, ValueError):
                raise InputError(f"body {self.name!r}: {attr} must be a number, got {v!r}") from None
            if not (math.isfinite(v) and v > 0):
                raise InputError(f"body {self.name!r}: {attr} must be positive and finite, got {v!r}")
            object.__setattr__(self, attr, v)
        if self.fixed and self.position is None:
            raise InputError(f"fixed body {self.name!r} needs a position")
        if self.fixed and self.alpha is not None and self.axis is None:
            raise InputError(f"fixed top {self.name!r} needs an axis")
        if self.position is not None:
            object.__setattr__(self, "position",
                               _vector3(self.position, f"body {self.name!r}: position"))
        if self.axis is not None:
            axis = _vector3(self.axis, f"body {self.name!r}: axis")
            if not any(axis):
                raise NonUnitAxisError(f"body {self.name!r}: axis must be non-zero, got {axis}")
            object.__setattr__(self, "axis", axis)
        attrs = self.attributes
        items = attrs.items() if isinstance(attrs, Mapping) else attrs
        try:
            items = [(str(k), v) for k, v in items]
        except (TypeError, ValueError):
            raise InputError(f"body {self.name!r}: attributes must be a mapping name -> number, "
                             f"got {attrs!r}") from None
        clean = []
        for k, v in sorted(items):
            try:
                v = float(v)
            except (TypeError, ValueError):
                raise InputError(f"body {self.name!r}: attribute {k!r} must be a number, "
                                 f"got {v!r}") from None
            if not math.isfinite(v):
                raise InputError(f"body {self.name!r}: attribute {k!r} must be finite, got {v!r}")
            if k in ("mass", "alpha"):
                raise InputError(f"body {self.name!r}: {k!r} is a field of the body, not an "
                                 "attribute")
            clean.append((k, v))
        object.__setattr__(self, "attributes", tuple(clean))

    def attribute(self, name: str) -> float:
        """Value of a per-body quantity (``mass``, ``alpha`` or one of :attr:`attributes`).

        Raises
        ------
        InputError
            If the body does not have it (the message names the body and the quantity).
        """
        if name == "mass":
            return float(self.mass)
        if name == "alpha" and self.alpha is not None:
            return float(self.alpha)
        for k, v in self.attributes:
            if k == name:
                return v
        raise InputError(f"body {self.name!r} has no {name!r}, which a pair potential takes from "
                         f"each body; give it (Body(..., attributes={{{name!r}: ...}}) or the "
                         "potential's parameter explicitly")

    @property
    def is_top(self) -> bool:
        """Whether the body carries an orientation (ν, m)."""
        return self.alpha is not None


@dataclass(frozen=True)
class Interaction:
    """One interacting pair ``(i, j)`` (indices or names of bodies) with its potential.

    ``potential`` is a :class:`~poissonkit.plugin.PairPotential`, a registry name, a sympy
    expression in ``r, c1, c2, c3`` or a compiled kernel ``f(r, c1, c2, c3) -> (U, U_r, U_c1,
    U_c2, U_c3)``; ``params`` are the potential's parameters (SI).
    """

    i: int | str
    j: int | str
    potential: Any
    params: Mapping[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class AllPairs:
    """Every pair of ``members`` (default: all bodies) interacting through one potential.

    Never builds the O(N²) pair list; with a system cutoff it uses a compiled cell list.
    """

    potential: Any
    params: Mapping[str, Any] = field(default_factory=dict)
    members: Sequence[int | str] | None = None


# ----------------------------------------------------------------------------- kernels
def _resolve_kernel(potential: Any, params: Mapping[str, Any]) -> tuple[Any, str]:
    """(SI kernel, orientation) of one interaction's potential."""
    if isinstance(potential, str):
        from poissonkit.plugin import potential as lookup

        potential = lookup(potential)
    if isinstance(potential, PairPotential):
        return compile_potential(potential, params), potential.orientation
    if isinstance(potential, numba.core.registry.CPUDispatcher):
        return potential, "both"
    if isinstance(potential, sp.Basic):
        names = {s.name for s in potential.free_symbols}
        has1, has2 = bool(names & {"c1", "c3"}), bool(names & {"c2", "c3"})
        orient = {(True, True): "both", (True, False): "first", (False, True): "second",
                  (False, False): "none"}[(has1, has2)]
        return kernel_from_expr(potential, "expr"), orient
    raise InputError(f"cannot use {type(potential).__name__} as a pair potential; give a "
                     "PairPotential, a registry name, a sympy expression or a numba kernel")


def _resolve_bound(potential: Any, params: Mapping[str, Any]
                   ) -> tuple[Any, tuple[tuple[str, int], ...], str]:
    """(SI kernel, bound slots, orientation) of one interaction's potential.

    Parameters of a :class:`PairPotential` listed in its ``body_params`` and not given in
    ``params`` are taken from the two bodies of each pair: the kernel then has one extra
    argument per ``(attribute, which body)`` slot.
    """
    if isinstance(potential, str):
        from poissonkit.plugin import potential as lookup

        potential = lookup(potential)
    if isinstance(potential, PairPotential) and potential.body_params:
        bound = {p: (attr, int(w)) for p, attr, w in potential.body_params if p not in params}
        if bound:
            kern, slots = compile_bound_potential(potential, params, bound)
            return kern, slots, potential.orientation
    kern, orient = _resolve_kernel(potential, params)
    return kern, (), orient


def _registry_entry(potential: Any) -> PairPotential | None:
    """The :class:`PairPotential` behind a registry name or entry (``None`` otherwise)."""
    if isinstance(potential, str):
        from poissonkit.plugin import potential as lookup

        return lookup(potential)
    return potential if isinstance(potential, PairPotential) else None


_wrap_cache: dict[tuple, tuple[Any, Any]] = {}


def _compile_wrapper(source: str, name: str, namespace: dict[str, Any]) -> Any:
    """Execute generated ``source`` (a small kernel wrapper) and compile it with numba."""
    return compile_generated(source, name, namespace)


def _wrapped(kern: Any, spec: tuple[tuple[int, int], ...], L: float, inv_e: float) -> Any:
    """``w(r, c1, c2, c3, B, i, j)``: the SI kernel in internal units, bound slots read from ``B``.

    ``spec`` lists ``(column of B, 1 or 2)`` per extra argument of ``kern``: row ``i`` (first
    body) or ``j`` (second body). ``U/E`` as a function of ``r/L``: ``U_r`` gains ``L/E``, the
    angular partials ``1/E``.
    """
    key = (id(kern), spec, L, inv_e)
    hit = _wrap_cache.get(key)
    if hit is not None:
        return hit[0]
    extra = "".join(f", B[{'i' if w == 1 else 'j'}, {c}]" for c, w in spec)
    if L == 1.0 and inv_e == 1.0:
        src = ("def wrapped(r, c1, c2, c3, B, i, j):\n"
               f"    return base(r, c1, c2, c3{extra})")
    else:
        src = ("def wrapped(r, c1, c2, c3, B, i, j):\n"
               f"    u, ur, u1, u2, u3 = base(r * {L!r}, c1, c2, c3{extra})\n"
               f"    return (u * {inv_e!r}, ur * {L * inv_e!r}, u1 * {inv_e!r}, u2 * {inv_e!r}, "
               f"u3 * {inv_e!r})")
    fn = _compile_wrapper(src, "wrapped", {"base": kern})
    _wrap_cache[key] = (fn, kern)  # keep kern alive so its id stays unique
    return fn


def _wrapped_radial(kern: Any, spec: tuple[tuple[int, int], ...], L: float, inv_e: float) -> Any:
    """``w(q, B, i, j) -> (U, U_r/r)`` in internal units, ``q = 1/r``: the fast-path kernel.

    With ``r = r_int L``: ``q_SI = q / L``, ``U_int = U/E``, ``(U_r/r)_int = (U_r/r) L²/E``.
    """
    key = ("radial", id(kern), spec, L, inv_e)
    hit = _wrap_cache.get(key)
    if hit is not None:
        return hit[0]
    base = radial_kernel(kern)
    extra = "".join(f", B[{'i' if w == 1 else 'j'}, {c}]" for c, w in spec)
    if L == 1.0 and inv_e == 1.0:
        src = f"def wrapped_r(q, B, i, j):\n    return base(q{extra})"
    else:
        src = ("def wrapped_r(q, B, i, j):\n"
               f"    u, f = base(q * {1.0 / L!r}{extra})\n"
               f"    return (u * {inv_e!r}, f * {L * L * inv_e!r})")
    fn = _compile_wrapper(src, "wrapped_r", {"base": base})
    _wrap_cache[key] = (fn, kern)
    return fn


_dispatch_cache: dict[tuple[int, ...], tuple[Any, ...]] = {}


def _dispatcher(kerns: Sequence[Any], rkerns: Sequence[Any]) -> tuple[Any, Any]:
    """``(kern_any, kern_r)`` calling wrapped kernel number ``g``; cached per kernel tuple.

    ``kern_any(g, r, c1, c2, c3, B, i, j) -> (U, U_r, U_c1, U_c2, U_c3)``;
    ``kern_r(g, q, B, i, j) -> (U, U_r/r)`` (``q = 1/r``) for the orientation-free fast path;
    ``rkerns[g]`` is ``None`` for a kernel that depends on orientation.
    """
    key = tuple(id(k) for k in kerns)
    hit = _dispatch_cache.get(key)
    if hit is not None:
        return hit[0], hit[1]
    ns: dict[str, Any] = {f"k{g}": k for g, k in enumerate(kerns)}
    ns.update({f"q{g}": k for g, k in enumerate(rkerns) if k is not None})
    radial = [g for g, k in enumerate(rkerns) if k is not None]
    if not kerns:
        src_any = ("def kern_any(g, r, c1, c2, c3, B, i, j):\n"
                   "    return (0.0, 0.0, 0.0, 0.0, 0.0)")
    else:
        la = ["def kern_any(g, r, c1, c2, c3, B, i, j):"]
        last = len(kerns) - 1
        for g in range(last):
            la.append(f"    if g == {g}:\n        return k{g}(r, c1, c2, c3, B, i, j)")
        la.append(f"    return k{last}(r, c1, c2, c3, B, i, j)")
        src_any = "\n".join(la)
    if not radial:
        src_r = "def kern_r(g, q, B, i, j):\n    return (0.0, 0.0)"
    else:
        lr = ["def kern_r(g, q, B, i, j):"]
        for g in radial[:-1]:
            lr.append(f"    if g == {g}:\n        return q{g}(q, B, i, j)")
        lr.append(f"    return q{radial[-1]}(q, B, i, j)")
        src_r = "\n".join(lr)
    fa = _compile_wrapper(src_any, "kern_any", ns)
    fr = _compile_wrapper(src_r, "kern_r", ns)
    _dispatch_cache[key] = (fa, fr, tuple(kerns), tuple(rkerns))  # keep kernels (and ids) alive
    return fa, fr


# ----------------------------------------------------------------------------- cell list
@numba.njit(cache=True, error_model="numpy")
def apply_forces(y, h, data, work):
    """Kick every moving body's ``p`` and top's ``m`` by ``h`` times the forces ``work[2]`` and
    torques ``work[3]`` (left there by the force loop)."""
    F = work[2]
    T = work[3]
    nm = data[0].shape[0]
    bslot = data[2]
    tslot = data[3]
    for b in range(bslot.shape[0]):
        s = bslot[b]
        if s >= 0:
            for d in range(3):
                y[6 * s + 3 + d] += h * F[b, d]
        t = tslot[b]
        if t >= 0:
            q = 6 * nm + 6 * t + 3
            for d in range(3):
                y[q + d] += h * T[b, d]


@numba.njit(cache=True, error_model="numpy")
def cell_list(members, pos, nu, cutoff):
    """Bin ``members`` into cubic cells of side ≥ ``cutoff``.

    Returns ``(nc, start, cell, p, n, body)``: cells per axis, slot offsets of each cell
    (``start[c]:start[c + 1]``, cells numbered row-major ``(cx·nc_y + cy)·nc_z + cz``), the
    cell of each slot, positions and axes copied in slot order (neighbours sit next to each
    other in memory) and the original body index of each slot.
    """
    n = members.shape[0]
    lo = np.empty(3)
    hi = np.empty(3)
    for d in range(3):
        lo[d] = np.inf
        hi[d] = -np.inf
    for a in range(n):
        b = members[a]
        for d in range(3):
            v = pos[b, d]
            lo[d] = min(lo[d], v)
            hi[d] = max(hi[d], v)
    side = cutoff
    nc = np.empty(3, dtype=np.int64)
    while True:
        total = 1
        for d in range(3):
            nc[d] = int((hi[d] - lo[d]) / side) + 1
            total *= nc[d]
        if total <= 4 * n + 64:  # sparse, far-flung bodies: coarser cells, same result
            break
        side *= 1.5
    ncell = nc[0] * nc[1] * nc[2]
    cell_of = np.empty(n, dtype=np.int64)
    count = np.zeros(ncell + 1, dtype=np.int64)
    for a in range(n):
        b = members[a]
        cx = min(int((pos[b, 0] - lo[0]) / side), nc[0] - 1)
        cy = min(int((pos[b, 1] - lo[1]) / side), nc[1] - 1)
        cz = min(int((pos[b, 2] - lo[2]) / side), nc[2] - 1)
        c = (cx * nc[1] + cy) * nc[2] + cz
        cell_of[a] = c
        count[c + 1] += 1
    for c in range(ncell):
        count[c + 1] += count[c]
    start = count.copy()
    order = np.empty(n, dtype=np.int64)
    for a in range(n):
        c = cell_of[a]
        order[start[c]] = a
        start[c] += 1
    sp_ = np.empty((n, 3))
    sn_ = np.empty((n, 3))
    body = np.empty(n, dtype=np.int64)
    cell = np.empty(n, dtype=np.int64)
    for q in range(n):
        b = members[order[q]]
        body[q] = b
        cell[q] = cell_of[order[q]]
        for d in range(3):
            sp_[q, d] = pos[b, d]
            sn_[q, d] = nu[b, d]
    return nc, count, cell, sp_, sn_, body


@numba.njit(cache=True, error_model="numpy")
def forward_cells(c, nc, out):
    """The "forward" neighbours of cell ``c`` (higher index, up to 13) into ``out``, in
    increasing index; returns how many. Each pair of adjacent cells is one cell's forward pair."""
    cx = c // (nc[1] * nc[2])
    cy = (c // nc[2]) % nc[1]
    cz = c % nc[2]
    k = 0
    for ddx in range(2):
        nx = cx + ddx
        if nx >= nc[0]:
            continue
        for ddy in range(-1, 2):
            if ddx == 0 and ddy < 0:
                continue
            ny = cy + ddy
            if ny < 0 or ny >= nc[1]:
                continue
            for ddz in range(-1, 2):
                if ddx == 0 and ddy == 0 and ddz <= 0:
                    continue
                nz = cz + ddz
                if nz < 0 or nz >= nc[2]:
                    continue
                out[k] = (nx * nc[1] + ny) * nc[2] + nz
                k += 1
    return k


_kernel_cache: dict[tuple[int, bool], Kernels] = {}


def _build_kernels(kern_any, kern_r, parallel: bool = False) -> Kernels:
    """Compile the N-body kernels around one pair of potential dispatchers (cached).

    ``parallel`` adds the multi-threaded cell-list loop (chosen at run time by the number of
    members, ``data[16]``); without it only the serial loop exists.
    """
    hit = _kernel_cache.get((id(kern_any), parallel))
    if hit is not None:
        return hit
    if parallel:
        # OpenMP's default active wait spins at every barrier: when another process holds
        # the other core, a force evaluation of 10⁴ tops took 4× the serial time instead of
        # the same (benchmarks/bench_nbody_parallel.py). Read once, at the first parallel
        # launch; a value the user set wins.
        os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

    @jit(inline="always")
    def switch(r, cut):
        """``(S, S')`` of the C² switching function, 1 below ``r_s``, 0 at the cutoff."""
        x = (r - cut[2]) * cut[3]
        return (1.0 - x * x * x * (10.0 - 15.0 * x + 6.0 * x * x),
                -30.0 * x * x * (1.0 - x) * (1.0 - x) * cut[3])

    @jit(inline="always")
    def pair_one(g, i, j, pos, nu, cut, B, bi, bj):
        """``(U, f, τ_i, τ_j)`` of pair (i, j): ``f`` is the force on j (−f on i).

        The serial and the parallel loop both evaluate a pair through this one function with
        the lower slot as ``i``, so a pair's numbers are bit-for-bit the same in both.
        """
        dx = pos[j, 0] - pos[i, 0]
        dy = pos[j, 1] - pos[i, 1]
        dz = pos[j, 2] - pos[i, 2]
        r2 = dx * dx + dy * dy + dz * dz
        if r2 > cut[0]:
            return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
        r = math.sqrt(r2)
        inv = 1.0 / r
        ex = dx * inv
        ey = dy * inv
        ez = dz * inv
        a0 = nu[i, 0]
        a1 = nu[i, 1]
        a2 = nu[i, 2]
        b0 = nu[j, 0]
        b1 = nu[j, 1]
        b2 = nu[j, 2]
        c1 = ex * a0 + ey * a1 + ez * a2
        c2 = ex * b0 + ey * b1 + ez * b2
        c3 = a0 * b0 + a1 * b1 + a2 * b2
        u, ur, u1, u2, u3 = kern_any(g, r, c1, c2, c3, B, bi, bj)
        if r2 > cut[1]:  # smooth cutoff: U S(r), S' adds to the radial partial only
            sw, dsw = switch(r, cut)
            ur = sw * ur + dsw * u
            u *= sw
            u1 *= sw
            u2 *= sw
            u3 *= sw
        # force on j (seed 000 eq. 20); the projections (ν − c e)/r come from ∂c/∂r_j
        f0 = -(ur * ex + (u1 * (a0 - c1 * ex) + u2 * (b0 - c2 * ex)) * inv)
        f1 = -(ur * ey + (u1 * (a1 - c1 * ey) + u2 * (b1 - c2 * ey)) * inv)
        f2 = -(ur * ez + (u1 * (a2 - c1 * ez) + u2 * (b2 - c2 * ez)) * inv)
        w0 = a1 * b2 - a2 * b1
        w1 = a2 * b0 - a0 * b2
        w2 = a0 * b1 - a1 * b0
        return (u, f0, f1, f2,
                u1 * (ey * a2 - ez * a1) - u3 * w0,
                u1 * (ez * a0 - ex * a2) - u3 * w1,
                u1 * (ex * a1 - ey * a0) - u3 * w2,
                u2 * (ey * b2 - ez * b1) + u3 * w0,
                u2 * (ez * b0 - ex * b2) + u3 * w1,
                u2 * (ex * b1 - ey * b0) + u3 * w2)

    @jit
    def pair_term(g, i, j, pos, nu, F, T, cut, B, bi, bj):
        u, f0, f1, f2, ti0, ti1, ti2, tj0, tj1, tj2 = pair_one(g, i, j, pos, nu, cut, B, bi, bj)
        F[j, 0] += f0
        F[j, 1] += f1
        F[j, 2] += f2
        F[i, 0] -= f0
        F[i, 1] -= f1
        F[i, 2] -= f2
        T[i, 0] += ti0
        T[i, 1] += ti1
        T[i, 2] += ti2
        T[j, 0] += tj0
        T[j, 1] += tj1
        T[j, 2] += tj2
        return u

    @jit(inline="always")
    def pair_r_one(g, i, j, pos, cut, B, bi, bj):
        """``(U, (U_r/r) d)`` of an orientation-free pair, ``d = r_j − r_i`` (the fast path):
        the force on j is minus the vector part, on i plus it."""
        dx = pos[j, 0] - pos[i, 0]
        dy = pos[j, 1] - pos[i, 1]
        dz = pos[j, 2] - pos[i, 2]
        r2 = dx * dx + dy * dy + dz * dz
        if r2 > cut[0]:
            return 0.0, 0.0, 0.0, 0.0
        q = 1.0 / math.sqrt(r2)
        u, s = kern_r(g, q, B, bi, bj)
        if r2 > cut[1]:  # smooth cutoff: (U S)_r / r = S U_r/r + S' U / r
            sw, dsw = switch(r2 * q, cut)
            s = sw * s + dsw * u * q
            u *= sw
        return u, s * dx, s * dy, s * dz

    @jit(inline="always")
    def pair_r(g, i, j, pos, F, cut, B, bi, bj):
        """Orientation-free pair: no axes, no c1, c2, c3, no torques (the fast path)."""
        u, g0, g1, g2 = pair_r_one(g, i, j, pos, cut, B, bi, bj)
        F[j, 0] -= g0
        F[j, 1] -= g1
        F[j, 2] -= g2
        F[i, 0] += g0
        F[i, 1] += g1
        F[i, 2] += g2
        return u

    @jit(inline="always")
    def all_pairs_r(g, members, lo, hi, pos, F, B):
        """Every pair of ``members[lo:hi]`` with an orientation-free potential, no cutoff."""
        u = 0.0
        for a in range(lo, hi):
            ia = members[a]
            xa = pos[ia, 0]
            ya = pos[ia, 1]
            za = pos[ia, 2]
            fx = 0.0
            fy = 0.0
            fz = 0.0
            for b in range(a + 1, hi):
                ib = members[b]
                dx = pos[ib, 0] - xa
                dy = pos[ib, 1] - ya
                dz = pos[ib, 2] - za
                uu, s = kern_r(g, 1.0 / math.sqrt(dx * dx + dy * dy + dz * dz), B, ia, ib)
                u += uu
                F[ib, 0] -= s * dx
                F[ib, 1] -= s * dy
                F[ib, 2] -= s * dz
                fx += s * dx
                fy += s * dy
                fz += s * dz
            F[ia, 0] += fx
            F[ia, 1] += fy
            F[ia, 2] += fz
        return u

    @jit(inline="always")
    def slab_pairs(x, g, central, nc, count, sp_, sn_, body, W, V, cut, B, cut2):
        """Pairs of the cell list whose first cell lies in x-slab ``x`` (cells of one ``cx``).

        Newton's third law: each pair is evaluated once and added to both bodies, the lower
        slot as ``i``. Slots are visited in cell order; for each slot its own cell's later
        slots, then the 13 "forward" neighbour cells in increasing index. A body's share goes
        to ``W[q, 0]`` (forces) / ``V[q, 0]`` (torques) when the pair's first cell is in the
        body's own slab and to ``W[q, 1]`` / ``V[q, 1]`` when it is in the slab before, so
        two slabs never write the same numbers: the slabs can run on any threads, in any
        order, and every sum is still formed in one fixed order.
        """
        fwd = np.empty(13, dtype=np.int64)
        per_slab = nc[1] * nc[2]
        first_next = (x + 1) * per_slab
        u = 0.0
        for c in range(x * per_slab, first_next):
            if count[c] == count[c + 1]:
                continue
            nf = forward_cells(c, nc, fwd)
            for qa in range(count[c], count[c + 1]):
                xa, ya, za = sp_[qa, 0], sp_[qa, 1], sp_[qa, 2]
                ua = 0.0
                for k in range(-1, nf):
                    c2 = c if k < 0 else fwd[k]
                    h = 1 if c2 >= first_next else 0  # j's cell in the next slab
                    for qb in range(qa + 1 if k < 0 else count[c2], count[c2 + 1]):
                        # cheap distance test before the pair term
                        dx = sp_[qb, 0] - xa
                        dy = sp_[qb, 1] - ya
                        dz = sp_[qb, 2] - za
                        if dx * dx + dy * dy + dz * dz > cut2:
                            continue
                        if central:
                            uu, g0, g1, g2 = pair_r_one(g, qa, qb, sp_, cut, B,
                                                        body[qa], body[qb])
                            W[qa, 0, 0] += g0
                            W[qa, 0, 1] += g1
                            W[qa, 0, 2] += g2
                            W[qb, h, 0] -= g0
                            W[qb, h, 1] -= g1
                            W[qb, h, 2] -= g2
                        else:
                            (uu, f0, f1, f2, ti0, ti1, ti2,
                             tj0, tj1, tj2) = pair_one(g, qa, qb, sp_, sn_, cut, B,
                                                       body[qa], body[qb])
                            W[qa, 0, 0] -= f0
                            W[qa, 0, 1] -= f1
                            W[qa, 0, 2] -= f2
                            W[qb, h, 0] += f0
                            W[qb, h, 1] += f1
                            W[qb, h, 2] += f2
                            V[qa, 0, 0] += ti0
                            V[qa, 0, 1] += ti1
                            V[qa, 0, 2] += ti2
                            V[qb, h, 0] += tj0
                            V[qb, h, 1] += tj1
                            V[qb, h, 2] += tj2
                        ua += uu
                u += ua
        return u

    @jit(inline="always")
    def cell_gather(n, body, W, V, us, F, T):
        """Add the slot sums to the bodies' rows; total energy, summed slab by slab."""
        for q in range(n):
            b = body[q]
            for d in range(3):
                F[b, d] += W[q, 1, d] + W[q, 0, d]
                T[b, d] += V[q, 1, d] + V[q, 0, d]
        u = 0.0
        for x in range(us.shape[0]):
            u += us[x]
        return u

    @jit(inline="always")
    def cell_setup(members, pos, nu, cutoff):
        """The cell list of ``members`` and zeroed per-slab accumulators (see ``slab_pairs``)."""
        n = members.shape[0]
        nc, count, cell_of, sp_, sn_, body = cell_list(members, pos, nu, cutoff)
        return (nc, count, sp_, sn_, body, np.zeros((n, 2, 3)), np.zeros((n, 2, 3)),
                np.empty(nc[0]))

    @jit
    def cell_pairs(g, central, members, pos, nu, F, T, cutoff, B, cut):
        """All pairs of ``members`` closer than ``cutoff``, via a cell list (O(n)), one thread."""
        if members.shape[0] < 2:
            return 0.0
        nc, count, sp_, sn_, body, W, V, us = cell_setup(members, pos, nu, cutoff)
        for x in range(nc[0]):
            us[x] = slab_pairs(x, g, central, nc, count, sp_, sn_, body, W, V, cut, B,
                               cutoff * cutoff)
        return cell_gather(members.shape[0], body, W, V, us, F, T)

    @jit(parallel=True)
    def cell_pairs_par(g, central, members, pos, nu, F, T, cutoff, B, cut):
        """:func:`cell_pairs` with the x-slabs shared out between threads; the same numbers
        bit for bit on any number of threads (see ``slab_pairs``: no two slabs write the same
        sum, no atomics, no reduction whose order depends on the threads)."""
        if members.shape[0] < 2:
            return 0.0
        nc, count, sp_, sn_, body, W, V, us = cell_setup(members, pos, nu, cutoff)
        half = (nc[0] + 1) // 2
        for k in numba.prange(nc[0]):
            # even slabs first, then odd ones: prange hands out contiguous blocks of
            # iterations, and this way the lighter last slab (no slab after it) goes to the
            # block that has one slab more; any order gives the same numbers
            x = 2 * k if k < half else 2 * (k - half) + 1
            us[x] = slab_pairs(x, g, central, nc, count, sp_, sn_, body, W, V, cut, B,
                               cutoff * cutoff)
        return cell_gather(members.shape[0], body, W, V, us, F, T)

    if parallel:
        @jit
        def cells(g, central, members, pos, nu, F, T, cutoff, B, cut, min_n):
            """The cell-list pairs on numba's threads once there are ``min_n`` members.

            The thread count is numba's (``numba.set_num_threads``); it is not read here:
            ``numba.get_num_threads`` in compiled code would keep every kernel that calls
            this one out of the disk cache, and on one thread the parallel loop does the
            serial loop's work anyway.
            """
            if members.shape[0] >= min_n:
                return cell_pairs_par(g, central, members, pos, nu, F, T, cutoff, B, cut)
            return cell_pairs(g, central, members, pos, nu, F, T, cutoff, B, cut)
    else:
        # no parallel loop compiled at all: compiling it costs seconds that small systems
        # (and systems told to stay serial) never get back
        @jit(inline="always")
        def cells(g, central, members, pos, nu, F, T, cutoff, B, cut, min_n):
            return cell_pairs(g, central, members, pos, nu, F, T, cutoff, B, cut)

    def forces_py(pos, nu, data, F, T):
        pairs = data[6]
        cmembers = data[7]
        coffs = data[8]
        cgid = data[9]
        cutoff = data[10]
        B = data[11]
        rpairs = data[12]
        ccentral = data[13]
        axes = data[14]
        for b in range(F.shape[0]):
            F[b, 0] = 0.0
            F[b, 1] = 0.0
            F[b, 2] = 0.0
        if axes:
            zero2(T)
        cut2 = cutoff * cutoff if np.isfinite(cutoff) else np.inf
        rs = data[15]
        # (cutoff², switch start², switch start, 1 / switch width); no switch: start = inf
        cut = (cut2, rs * rs, rs, 1.0 / (cutoff - rs) if rs < cutoff else 0.0)
        u = 0.0
        for k in range(pairs.shape[0]):
            i = pairs[k, 0]
            j = pairs[k, 1]
            u += pair_term(pairs[k, 2], i, j, pos, nu, F, T, cut, B, i, j)
        for k in range(rpairs.shape[0]):
            i = rpairs[k, 0]
            j = rpairs[k, 1]
            u += pair_r(rpairs[k, 2], i, j, pos, F, cut, B, i, j)
        for g in range(cgid.shape[0]):
            gid = cgid[g]
            central = ccentral[g] != 0
            lo = coffs[g]
            hi = coffs[g + 1]
            if np.isfinite(cutoff):
                u += cells(gid, central, cmembers[lo:hi], pos, nu, F, T, cutoff, B, cut,
                           data[16])
            elif central:
                u += all_pairs_r(gid, cmembers, lo, hi, pos, F, B)
            else:
                for a in range(lo, hi):
                    for b in range(a + 1, hi):
                        ia = cmembers[a]
                        ib = cmembers[b]
                        u += pair_term(gid, ia, ib, pos, nu, F, T, cut, B, ia, ib)
        return u

    def gather_py(y, data, pos, nu):
        mass = data[0]
        bslot = data[2]
        tslot = data[3]
        fpos = data[4]
        fnu = data[5]
        nm = mass.shape[0]
        axes = data[14]
        for b in range(bslot.shape[0]):
            s = bslot[b]
            if s >= 0:
                for d in range(3):
                    pos[b, d] = y[6 * s + d]
            else:
                for d in range(3):
                    pos[b, d] = fpos[b, d]
            if not axes:  # point masses only: ν and torques are never read
                continue
            t = tslot[b]
            if t >= 0:
                for d in range(3):
                    nu[b, d] = y[6 * nm + 6 * t + d]
            else:
                for d in range(3):
                    nu[b, d] = fnu[b, d]

    # two compilations of each: inlined into the hot kick (numba does not inline calls between
    # separately compiled functions, and the call costs as much as a small system's pair loop)
    # and a plain one for the other kernels (inlining everywhere only lengthens compilation)
    forces = jit(forces_py)
    gather = jit(gather_py)
    forces_inl = jit(inline="always")(forces_py)
    gather_inl = jit(inline="always")(gather_py)

    @jit
    def rhs(y, data, work, out):
        pos, nu, F, T = work
        mass = data[0]
        alpha = data[1]
        bslot = data[2]
        tslot = data[3]
        nm = mass.shape[0]
        gather(y, data, pos, nu)
        forces(pos, nu, data, F, T)
        for b in range(bslot.shape[0]):
            s = bslot[b]
            if s >= 0:
                for d in range(3):
                    out[6 * s + d] = y[6 * s + 3 + d] / mass[s]
                    out[6 * s + 3 + d] = F[b, d]
            t = tslot[b]
            if t >= 0:
                q = 6 * nm + 6 * t
                a = alpha[t]
                n0, n1, n2 = y[q], y[q + 1], y[q + 2]
                m0, m1, m2 = y[q + 3], y[q + 4], y[q + 5]
                out[q] = a * (m1 * n2 - m2 * n1)
                out[q + 1] = a * (m2 * n0 - m0 * n2)
                out[q + 2] = a * (m0 * n1 - m1 * n0)
                for d in range(3):
                    out[q + 3 + d] = T[b, d]

    @jit
    def kick(y, h, data, work):
        pos, nu, F, T = work
        gather_inl(y, data, pos, nu)
        forces_inl(pos, nu, data, F, T)
        apply_forces(y, h, data, work)

    @jit
    def drift(y, h, data):
        mass = data[0]
        alpha = data[1]
        nm = mass.shape[0]
        for s in range(nm):
            c = h / mass[s]
            for d in range(3):
                y[6 * s + d] += c * y[6 * s + 3 + d]
        for t in range(alpha.shape[0]):
            q = 6 * nm + 6 * t
            rotate_slot(y, q, q + 3, alpha[t] * h)

    @jit
    def kick_compensated(y, c, h, data, work):
        # as kick, every increment added with Kahan summation (c: rounding errors so far)
        pos, nu, F, T = work
        mass = data[0]
        bslot = data[2]
        tslot = data[3]
        nm = mass.shape[0]
        gather_inl(y, data, pos, nu)
        forces_inl(pos, nu, data, F, T)
        for b in range(bslot.shape[0]):
            s = bslot[b]
            if s >= 0:
                for d in range(3):
                    kahan_add(y, c, 6 * s + 3 + d, h * F[b, d])
            t = tslot[b]
            if t >= 0:
                q = 6 * nm + 6 * t + 3
                for d in range(3):
                    kahan_add(y, c, q + d, h * T[b, d])

    @jit
    def drift_compensated(y, c, h, data):
        mass = data[0]
        alpha = data[1]
        nm = mass.shape[0]
        for s in range(nm):
            cc = h / mass[s]
            for d in range(3):
                kahan_add(y, c, 6 * s + d, cc * y[6 * s + 3 + d])
        for t in range(alpha.shape[0]):
            q = 6 * nm + 6 * t
            rotate_slot_compensated(y, c, q, q + 3, alpha[t] * h)

    @jit
    def energy(y, data, work):
        pos, nu, F, T = work
        mass = data[0]
        alpha = data[1]
        nm = mass.shape[0]
        gather(y, data, pos, nu)
        e = forces(pos, nu, data, F, T)
        for s in range(nm):
            p2 = y[6 * s + 3] ** 2 + y[6 * s + 4] ** 2 + y[6 * s + 5] ** 2
            e += 0.5 * p2 / mass[s]
        for t in range(alpha.shape[0]):
            q = 6 * nm + 6 * t + 3
            e += 0.5 * alpha[t] * (y[q] ** 2 + y[q + 1] ** 2 + y[q + 2] ** 2)
        return e

    @jit
    def min_distance(y, data, work):
        pos = work[0]
        nu = work[1]
        gather(y, data, pos, nu)
        bslot = data[2]
        n = pos.shape[0]
        best = np.inf
        for a in range(n):
            for b in range(a + 1, n):
                if bslot[a] < 0 and bslot[b] < 0:
                    continue
                d2 = ((pos[a, 0] - pos[b, 0]) ** 2 + (pos[a, 1] - pos[b, 1]) ** 2
                      + (pos[a, 2] - pos[b, 2]) ** 2)
                best = min(best, d2)
        return math.sqrt(best)

    @jit
    def max_radius(y, data):
        mass = data[0]
        nm = mass.shape[0]
        mt = 0.0
        c = np.zeros(3)
        for s in range(nm):
            mt += mass[s]
            for d in range(3):
                c[d] += mass[s] * y[6 * s + d]
        best = 0.0
        for s in range(nm):
            d2 = 0.0
            for d in range(3):
                d2 += (y[6 * s + d] - c[d] / mt) ** 2
            best = max(best, d2)
        return math.sqrt(best)

    @jit(inline="always")
    def forces_of(y, data, work):
        """Forces and torques into ``work[2]``, ``work[3]`` (rows: all bodies); returns U."""
        pos, nu, F, T = work
        gather_inl(y, data, pos, nu)
        return forces_inl(pos, nu, data, F, T)

    out = Kernels(rhs=rhs, drift=drift, kick=kick, energy=energy, min_distance=min_distance,
                  max_radius=max_radius, jac=None, splittable=True, forces=forces_of,
                  drift_compensated=drift_compensated, kick_compensated=kick_compensated)
    _kernel_cache[(id(kern_any), parallel)] = out
    return out


# ----------------------------------------------------------------------------- the system
#: Fewest members of a cell-listed :class:`AllPairs` for which the parallel pair loop is used
#: by default. On an idle 2-core machine the two loops break even near 1000 bodies and the
#: parallel one is 1.3× faster at 2200 (``benchmarks/bench_nbody_parallel.py``); the margin
#: keeps small systems off the thread pool.
PARALLEL_MIN_BODIES = 1500


def _count_option(value: Any, what: str, low: int) -> int:
    """``value`` as an int ``>= low``, else :class:`InputError` naming ``what``."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise InputError(f"{what} must be an integer, got {value!r}")
    if value < low:
        raise InputError(f"{what} must be at least {low}, got {value!r}")
    return int(value)


class NBodySystem:
    """Interacting symmetric tops and point masses (see the module docstring for the layout).

    Parameters
    ----------
    bodies
        The bodies, in state order.
    interactions
        :class:`Interaction` (one pair) and/or :class:`AllPairs` entries.
    cutoff
        Optional interaction radius [m] (pairs farther apart are skipped).
    scales
        Optional :class:`~poissonkit.numerics.units.Scales`: then masses, ``alpha``, fixed
        positions, the cutoff and the potentials are given in SI and the state is internal
        (``r/L``, ``p/(M L/T)``, ``m/(M L²/T)``); :meth:`pack` / :meth:`unpack` convert with
        ``si=True``. Without scales every number is used as given.
    smooth_cutoff
        Optional start ``r_s < cutoff`` [m] of a smooth cutoff: every pair energy is multiplied
        by the switching function ``S = 1 − 10x³ + 15x⁴ − 6x⁵``, ``x = (r − r_s)/(cutoff −
        r_s)`` (C², so energy and forces are continuous when a pair crosses the cutoff and a
        splitting's energy error stays bounded); ``None`` truncates at the cutoff.
    fast_path
        Evaluate orientation-free potentials (gravity, ``U(r)``) in the specialised pair loop
        without axes and torques (default). ``False`` sends them through the general loop;
        the results agree to round-off (a test checks it), only the speed differs.
    parallel
        Run the cell-list pair loop (needs ``cutoff``) of an :class:`AllPairs` with at least
        ``parallel_min_bodies`` members on numba's threads (default). Their number is
        numba's: ``numba.set_num_threads(k)`` (at most ``NUMBA_NUM_THREADS``, which defaults
        to the number of cores). ``False`` always runs the serial loop and does not compile
        the parallel one (a few seconds saved on the first use of a potential). Forces,
        torques and energy are bit-for-bit the same either way and on any number of threads:
        the cell list's x-slabs are shared out between threads, each pair is evaluated once,
        and every sum is formed in one fixed order (no atomics, no thread-dependent
        reduction).
    parallel_min_bodies
        Fewest members of an :class:`AllPairs` for which the parallel loop is used
        (default :data:`PARALLEL_MIN_BODIES`); smaller sets run the serial loop.

    Notes
    -----
    The object is immutable after construction; kernels are compiled on first use and shared
    between systems with the same potentials.
    """

    def __init__(self, bodies: Sequence[Body], interactions: Sequence[Interaction | AllPairs] = (),
                 cutoff: float | None = None, scales: Scales | None = None,
                 fast_path: bool = True, smooth_cutoff: float | None = None,
                 parallel: bool = True,
                 parallel_min_bodies: int | None = None) -> None:
        bodies = tuple(bodies)
        if not bodies:
            raise InputError("NBodySystem needs at least one body")
        for b in bodies:
            if not isinstance(b, Body):
                raise InputError(f"bodies must be Body objects, got {type(b).__name__}")
        names = [b.name for b in bodies]
        if len(set(names)) != len(names):
            raise InputError(f"body names must be unique, got {names}")
        if cutoff is not None and not (math.isfinite(float(cutoff)) and float(cutoff) > 0):
            raise InputError(f"cutoff must be positive and finite, got {cutoff!r}")
        self.bodies = bodies
        self.interactions = tuple(interactions)
        self.cutoff = None if cutoff is None else float(cutoff)
        if smooth_cutoff is not None:
            if self.cutoff is None:
                raise InputError("smooth_cutoff needs a cutoff")
            rs = float(smooth_cutoff)
            if not (math.isfinite(rs) and 0 < rs < self.cutoff):
                raise InputError(f"smooth_cutoff must be in (0, cutoff = {self.cutoff}), got "
                                 f"{smooth_cutoff!r}")
        self.smooth_cutoff = None if smooth_cutoff is None else float(smooth_cutoff)
        if not isinstance(parallel, (bool, np.bool_)):
            raise InputError(f"parallel must be True or False, got {parallel!r}")
        self.parallel = bool(parallel)
        self.parallel_min_bodies = _count_option(
            PARALLEL_MIN_BODIES if parallel_min_bodies is None else parallel_min_bodies,
            "parallel_min_bodies", 0)
        self.scales = scales
        index = {b.name: k for k, b in enumerate(bodies)}

        def idx(v: int | str) -> int:
            if isinstance(v, str):
                if v not in index:
                    from poissonkit.errors import UnknownNameError

                    raise UnknownNameError("body", v, index)
                return index[v]
            k = int(v)
            if not 0 <= k < len(bodies):
                raise InputError(f"body index {v} out of range 0..{len(bodies) - 1}")
            return k

        L = scales.length if scales else 1.0
        M = scales.mass if scales else 1.0
        E = scales.energy if scales else 1.0
        moving = [k for k, b in enumerate(bodies) if not b.fixed]
        tops = [k for k in moving if bodies[k].is_top]
        self._moving = tuple(moving)
        self._tops = tuple(tops)
        bslot = np.full(len(bodies), -1, dtype=np.int64)
        tslot = np.full(len(bodies), -1, dtype=np.int64)
        bslot[moving] = np.arange(len(moving))
        tslot[tops] = np.arange(len(tops))
        mass = np.array([bodies[k].mass / M for k in moving], dtype=float)
        alpha = np.array([bodies[k].alpha * M * L * L for k in tops], dtype=float)
        fpos = np.zeros((len(bodies), 3))
        fnu = np.zeros((len(bodies), 3))
        for k, b in enumerate(bodies):
            if b.fixed:
                fpos[k] = np.asarray(b.position, dtype=float) / L
                if b.is_top:
                    ax = np.asarray(b.axis, dtype=float)
                    n = np.linalg.norm(ax)
                    if not n > 0:
                        raise InputError(f"fixed top {b.name!r} has a zero axis")
                    fnu[k] = ax / n

        # kernels: one per distinct (potential, params, bound slots), in internal units;
        # parameters bound to body attributes are read per pair from the table B (SI values)
        kern_ids: dict[tuple, int] = {}
        kerns: list[Any] = []
        rkerns: list[Any] = []
        attr_cols: dict[str, int] = {}
        inv_e = 1.0 / E

        def kernel_id(pot: Any, params: Mapping[str, Any], i: int | None, j: int | None
                      ) -> tuple[int, str]:
            kern, slots, orient = _resolve_bound(pot, params)
            needs_i = orient in ("both", "first")
            needs_j = orient in ("both", "second")
            for k, need in ((i, needs_i), (j, needs_j)):
                if k is not None and need and not bodies[k].is_top:
                    raise InputError(f"potential {getattr(pot, 'name', pot)!s} depends on the "
                                     f"axis of body {bodies[k].name!r}, which is a point mass")
            spec = tuple((attr_cols.setdefault(a, len(attr_cols)), w) for a, w in slots)
            key = (id(kern), spec)
            if key not in kern_ids:
                kern_ids[key] = len(kerns)
                lu, eu = (L, inv_e) if scales else (1.0, 1.0)
                kerns.append(_wrapped(kern, spec, lu, eu))
                rkerns.append(_wrapped_radial(kern, spec, lu, eu) if orient == "none" else None)
            return kern_ids[key], orient

        pairs: list[tuple[int, int, int]] = []
        rpairs: list[tuple[int, int, int]] = []
        gravity_g: list[float] = []
        cmembers: list[int] = []
        coffs = [0]
        cgid: list[int] = []
        ccentral: list[int] = []
        for it in self.interactions:
            if isinstance(it, Interaction):
                i, j = idx(it.i), idx(it.j)
                if i == j:
                    raise InputError(f"interaction of body {bodies[i].name!r} with itself")
                if bodies[i].fixed and bodies[j].fixed:
                    continue  # constant energy, no force on any degree of freedom
                gid, orient = kernel_id(it.potential, it.params, i, j)
                (rpairs if orient == "none" and fast_path else pairs).append((i, j, gid))
            elif isinstance(it, AllPairs):
                mem = list(range(len(bodies))) if it.members is None else [idx(v) for v in it.members]
                if len(set(mem)) != len(mem):
                    raise InputError("AllPairs members repeat a body")
                point = [bodies[k].name for k in mem if not bodies[k].is_top]
                gid, orient = kernel_id(it.potential, it.params, None, None)
                if point and orient != "none":
                    raise InputError(f"potential depends on axes but AllPairs includes point "
                                     f"masses {point}")
                entry = _registry_entry(it.potential)
                if (entry is not None and entry.name == "gravity"
                        and sorted(mem) == list(range(len(bodies)))
                        and not {"mass1", "mass2"} & set(it.params)):
                    gravity_g.append(float(entry.resolve_params(
                        {k: v for k, v in it.params.items()} | {"mass1": 1.0, "mass2": 1.0}
                    )["G"]))
                cmembers.extend(mem)
                coffs.append(len(cmembers))
                cgid.append(gid)
                ccentral.append(1 if orient == "none" and fast_path else 0)
            else:
                raise InputError(f"interactions must be Interaction or AllPairs, got "
                                 f"{type(it).__name__}")
        table = np.zeros((len(bodies), max(1, len(attr_cols))))
        for a, c in attr_cols.items():
            for k, b in enumerate(bodies):
                table[k, c] = b.attribute(a)
        self._kerns = tuple(kerns)
        self._rkerns = tuple(rkerns)
        # G in internal units (L³ / (M T²)) of a gravity interaction among all bodies, if any
        T = scales.time if scales else 1.0
        self._gravity = (gravity_g[0] * M * T * T / L ** 3 if len(gravity_g) == 1 else None)
        self._attributes = tuple(attr_cols)
        self._energy_shift = 0.0
        cut = np.inf if self.cutoff is None else self.cutoff / L
        rs_int = np.inf if self.smooth_cutoff is None else self.smooth_cutoff / L
        self.data = (mass, alpha, bslot, tslot, fpos, fnu,
                     np.array(pairs, dtype=np.int64).reshape(-1, 3),
                     np.array(cmembers, dtype=np.int64), np.array(coffs, dtype=np.int64),
                     np.array(cgid, dtype=np.int64), float(cut), table,
                     np.array(rpairs, dtype=np.int64).reshape(-1, 3),
                     np.array(ccentral, dtype=np.int64),
                     any(b.is_top for b in bodies), float(rs_int),
                     int(self.parallel_min_bodies))
        # compile the parallel loop only for a system that may use it
        self._parallel = (self.cutoff is not None and self.parallel
                          and any(coffs[g + 1] - coffs[g] >= max(2, self.parallel_min_bodies)
                                  for g in range(len(cgid))))
        self._kernels: Kernels | None = None

    # ------------------------------------------------------------------ structure
    def gravity_constant(self) -> float:
        """``G`` in internal units, from the one ``AllPairs("gravity")`` over all bodies.

        Raises
        ------
        InputError
            If there is no such interaction (or more than one), e.g. for Wisdom–Holman.
        """
        if self._gravity is None:
            raise InputError("the system needs exactly one AllPairs('gravity', ...) over all "
                             "bodies (the Kepler part of a Wisdom–Holman splitting)")
        return self._gravity

    @property
    def n_moving(self) -> int:
        """Number of moving bodies (with ``r, p`` in the state)."""
        return len(self._moving)

    @property
    def n_tops(self) -> int:
        """Number of moving tops (with ``ν, m`` in the state)."""
        return len(self._tops)

    @property
    def dim(self) -> int:
        """Length of the state vector."""
        return 6 * (self.n_moving + self.n_tops)

    @property
    def layout(self) -> tuple[str, ...]:
        """Names of the state slots, e.g. ``('a.r_x', …, 'a.p_z', …, 'a.nu_x', …, 'a.m_z')``."""
        out: list[str] = []
        for k in self._moving:
            n = self.bodies[k].name
            out += [f"{n}.{v}_{a}" for v in ("r", "p") for a in "xyz"]
        for k in self._tops:
            n = self.bodies[k].name
            out += [f"{n}.{v}_{a}" for v in ("nu", "m") for a in "xyz"]
        return tuple(out)

    @property
    def kernels(self) -> Kernels:
        """The compiled kernels (compiled on first access)."""
        if self._kernels is None:
            self._kernels = _build_kernels(*_dispatcher(self._kerns, self._rkerns),
                                           parallel=self._parallel)
        return self._kernels

    def work(self) -> tuple[np.ndarray, ...]:
        """Fresh scratch arrays ``(pos, nu, F, T)`` for the kernels."""
        n = len(self.bodies)
        return (np.zeros((n, 3)), np.zeros((n, 3)), np.zeros((n, 3)), np.zeros((n, 3)))

    def _state(self, y: Any) -> np.ndarray:
        y = np.asarray(y, dtype=float)
        if y.ndim != 1 or y.shape[0] != self.dim:
            raise DimensionError(f"state has shape {y.shape}, expected ({self.dim},)")
        return np.ascontiguousarray(y)

    # ------------------------------------------------------------------ evaluation
    def rhs(self, t: float, y: Any) -> np.ndarray:
        """``ẏ`` at state ``y`` (time ``t`` is ignored: the system is autonomous).

        Raises :class:`OverlapError` if two interacting bodies coincide.
        """
        return evaluate_rhs(self, y)

    def forces(self, y: Any) -> tuple[np.ndarray, np.ndarray, float]:
        """Forces and torques on every body ``(F (n,3), T (n,3), U)`` (internal units)."""
        y = self._state(y)
        work = self.work()
        u = self.kernels.forces(y, self.data, work)
        return work[2], work[3], float(u)

    def energy(self, y: Any) -> float | np.ndarray:
        """Total energy ``H(y)``; a 2-D array of states gives one value per row.

        Raises :class:`OverlapError` if two interacting bodies coincide.
        """
        return evaluate_energy(self, y)

    def _split(self, y: np.ndarray):
        nm = self.n_moving
        rp = y[..., :6 * nm].reshape(y.shape[:-1] + (nm, 2, 3))
        nm_ = y[..., 6 * nm:].reshape(y.shape[:-1] + (self.n_tops, 2, 3))
        return rp[..., 0, :], rp[..., 1, :], nm_[..., 0, :], nm_[..., 1, :]

    def casimirs(self, y: Any) -> np.ndarray:
        """Per top ``|ν|²`` and ``(ν, m)``, flattened ``[|ν_1|², (ν_1,m_1), …]`` (rows if 2-D)."""
        y = np.asarray(y, dtype=float)
        _, _, nu, m = self._split(y)
        out = np.stack([np.sum(nu * nu, axis=-1), np.sum(nu * m, axis=-1)], axis=-1)
        return out.reshape(y.shape[:-1] + (2 * self.n_tops,))

    def casimir_scales(self, y: Any) -> np.ndarray:
        """Natural size of each Casimir at ``y`` (1 for ``|ν|²``, ``|m|`` for ``(ν, m)``)."""
        y = np.asarray(y, dtype=float)
        m = self._split(y)[3]
        s = np.stack([np.ones(m.shape[:-1]), np.linalg.norm(m, axis=-1)], axis=-1)
        return s.reshape(y.shape[:-1] + (2 * self.n_tops,))

    def linear_momentum(self, y: Any) -> np.ndarray:
        """Total ``Σ p`` of the moving bodies (conserved without fixed bodies)."""
        _, p, _, _ = self._split(np.asarray(y, dtype=float))
        return p.sum(axis=-2)

    def angular_momentum(self, y: Any) -> np.ndarray:
        """Total ``Σ r × p + Σ m`` about the origin (seed 000 eq. 21)."""
        r, p, _, m = self._split(np.asarray(y, dtype=float))
        return np.cross(r, p).sum(axis=-2) + m.sum(axis=-2)

    def min_distance(self, y: Any) -> float:
        """Smallest distance between two bodies (internal units)."""
        return float(self.kernels.min_distance(self._state(y), self.data, self.work()))

    # ------------------------------------------------------------------ packing
    def pack(self, positions: Any, momenta: Any, axes: Any = None, angular_momenta: Any = None,
             *, si: bool = False, normalize: bool = False) -> np.ndarray:
        """Build a state vector.

        Parameters
        ----------
        positions, momenta
            ``(n, 3)`` arrays for all bodies (rows of fixed bodies are ignored) or for the moving
            bodies only.
        axes, angular_momenta
            ``(n, 3)`` for all bodies (rows of point masses / fixed bodies ignored) or for the
            moving tops only. Required if there are tops.
        si
            Inputs are SI and are converted with the system's scales.
        normalize
            Normalise the axes; otherwise an axis with ``| |ν| − 1 | > 1e-12`` raises
            :class:`NonUnitAxisError`.
        """
        s = self.scales if si else None
        fL = s.unit("length") if s else 1.0
        fP = s.unit("momentum") if s else 1.0
        fA = s.unit("angular_momentum") if s else 1.0

        def rows(a: Any, wanted: tuple[int, ...], what: str) -> np.ndarray:
            a = np.asarray(a, dtype=float)
            if a.ndim == 1 and a.size == 3 and len(wanted) == 1:
                a = a[None, :]
            if a.ndim != 2 or a.shape[1] != 3:
                raise DimensionError(f"{what} must have shape (n, 3), got {a.shape}")
            if a.shape[0] == len(self.bodies):
                a = a[list(wanted)]
            elif a.shape[0] != len(wanted):
                raise DimensionError(f"{what}: {a.shape[0]} rows, expected {len(self.bodies)} "
                                     f"(all bodies) or {len(wanted)}")
            if not np.all(np.isfinite(a)):
                raise InputError(f"{what} contain non-finite values")
            return a

        r = rows(positions, self._moving, "positions") / fL
        p = rows(momenta, self._moving, "momenta") / fP
        self._check_positions(r)
        parts = [np.concatenate([r, p], axis=1).ravel()]
        if self.n_tops:
            if axes is None or angular_momenta is None:
                raise InputError("the system has tops: give axes and angular_momenta")
            nu = rows(axes, self._tops, "axes")
            m = rows(angular_momenta, self._tops, "angular momenta") / fA
            norms = np.linalg.norm(nu, axis=1)
            if normalize:
                if np.any(norms == 0):
                    raise NonUnitAxisError("cannot normalise a zero axis")
                nu = nu / norms[:, None]
            elif np.any(np.abs(norms - 1.0) > 1e-12):
                bad = [self.bodies[self._tops[k]].name for k in np.nonzero(np.abs(norms - 1) > 1e-12)[0]]
                bad_norms = ", ".join(f"{v:.3g} (off by {v - 1:.1e})"
                                      for v in norms[np.abs(norms - 1) > 1e-12])
                raise NonUnitAxisError(f"axes of {bad} are not unit vectors (|ν| = "
                                       f"{bad_norms}); pass normalize=True")
            parts.append(np.concatenate([nu, m], axis=1).ravel())
        return np.concatenate(parts)

    def unpack(self, y: Any, *, si: bool = False) -> dict[str, np.ndarray]:
        """Split a state (or rows of states) into ``r, p`` (moving bodies) and ``nu, m`` (tops)."""
        r, p, nu, m = self._split(np.asarray(y, dtype=float))
        s = self.scales if si else None
        if s:
            r, p, m = r * s.unit("length"), p * s.unit("momentum"), m * s.unit("angular_momentum")
        return {"r": r, "p": p, "nu": nu, "m": m}

    def _check_positions(self, r: np.ndarray) -> None:
        """:class:`OverlapError` if two bodies (moving rows ``r``, internal units) coincide."""
        pos = self.data[4].copy()
        pos[list(self._moving)] = r
        fixed = np.array([b.fixed for b in self.bodies], dtype=bool)
        hit = coincident_pair(pos, fixed)
        if hit is not None:
            a, b = (self.bodies[k].name for k in hit)
            raise OverlapError(f"bodies {a!r} and {b!r} are at the same position "
                               f"{pos[hit[0]].tolist()} (internal units); every pair force is "
                               "singular there")

    def check_overlap(self, y: Any) -> None:
        """Raise :class:`OverlapError` if two bodies of state ``y`` sit at the same place."""
        y = self._state(y)
        self._check_positions(self._split(y)[0])

    def check_state(self, y: Any, tol: float = 1e-10) -> None:
        """Raise :class:`NonUnitAxisError` if some axis of ``y`` is not a unit vector and
        :class:`OverlapError` if two bodies coincide."""
        self.check_overlap(y)
        c = self.casimirs(self._state(y))[0::2]
        bad = np.nonzero(np.abs(c - 1.0) > tol)[0]
        if bad.size:
            names = [self.bodies[self._tops[k]].name for k in bad]
            shown = ", ".join(f"{v:.3g} (off by {v - 1:.1e})" for v in c[bad])
            raise NonUnitAxisError(f"axes of {names} are not unit vectors (|ν|² = {shown}); "
                                   "normalise them (pack(..., normalize=True))")

    # ------------------------------------------------------------------ symbolic
    def to_structure(self):
        """The symbolic Poisson structure: ``canonical(3)`` per moving body ⊕ ``e3()`` per top.

        Coordinates are named ``<body>.q_x … <body>.p_z`` and ``<body>_top.nu_x … .m_z``,
        in exactly the state order.
        """
        from poissonkit.structure import canonical, direct_sum, e3

        parts = [(self.bodies[k].name, canonical(3)) for k in self._moving]
        parts += [(f"{self.bodies[k].name}_top", e3()) for k in self._tops]
        return direct_sum(*parts)

    def __repr__(self) -> str:
        return (f"NBodySystem({len(self.bodies)} bodies, {self.n_moving} moving, {self.n_tops} "
                f"tops, {len(self.interactions)} interaction entries, cutoff={self.cutoff})")
