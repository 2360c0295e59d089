"""The N-body system: bodies and interactions assembled into compiled kernels and a state layout.

See :mod:`poissonkit.numerics.nbody` for the state layout and the Hamiltonian.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt
from numba.core.dispatcher import Dispatcher

from poissonkit.contracts import CompiledFunction
from poissonkit.errors import DimensionError, InputError
from poissonkit.numerics.integrators.base import LoopKernels
from poissonkit.numerics.fields.base import CompiledField, FieldLike, compile_fields
from poissonkit.numerics.fields.compose import field_data, field_term
from poissonkit.numerics.kernels import Kernels
from poissonkit.numerics.nbody.bodies import (
    AllPairs,
    Body,
    Interaction,
    NonUnitAxisError,
    PotentialLike,
)
from poissonkit.numerics.nbody.data import (
    DirectData,
    Work,
    direct_data,
    empty_field_data,
    new_direct_work,
    new_work,
    system_data,
)
from poissonkit.numerics.nbody.evaluate import (
    OverlapError,
    coincident_pair,
    evaluate_energy,
    evaluate_rhs,
)
from poissonkit.numerics.nbody.loops import _build_kernels
from poissonkit.numerics.nbody.pairkernels import (
    _dispatcher,
    _registry_entry,
    _wrapped,
    _wrapped_radial,
    resolve_runtime,
    unit_values,
)
from poissonkit.numerics.nbody.verlet import new_verlet_state
from poissonkit.numerics.units import Scales
from poissonkit.plugin.contributions import PairPotential

if TYPE_CHECKING:
    from poissonkit.structure.bivector import Bivector

#: Fewest members of a cell-listed :class:`AllPairs` for which the parallel pair loop is used
#: by default. On an idle 2-core machine the two loops break even near 1000 bodies and the
#: parallel one is 1.3× faster at 2200 (``benchmarks/bench_nbody_parallel.py``); the margin
#: keeps small systems off the thread pool.
PARALLEL_MIN_BODIES = 1500


def _count_option(value: object, what: str, low: int) -> int:
    """``value`` as an int ``>= low``, else :class:`InputError` naming ``what``."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise InputError(f"{what} must be an integer, got {value!r}")
    if value < low:
        raise InputError(f"{what} must be at least {low}, got {value!r}")
    return int(value)


def _label(potential: PotentialLike) -> object:
    """How an error message names a potential: its registry name, else the potential itself."""
    return potential.name if isinstance(potential, PairPotential) else potential


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
    skin
        Optional Verlet skin ``s > 0`` [m] (needs ``cutoff``): the pairs of each
        :class:`AllPairs` closer than ``cutoff + s`` are listed once and later force
        evaluations of a run walk that list instead of building a cell list; it is rebuilt as
        soon as a body has moved more than ``s/2`` since (checked at every evaluation), so no
        pair within the cutoff is ever missed (:mod:`~poissonkit.numerics.nbody.verlet`).
        Serial and parallel stay bitwise equal; the last bits depend on when the list was
        built. ``None`` (default) builds a cell list at every evaluation.
    fields
        External fields (:func:`poissonkit.field`, or built
        :class:`~poissonkit.numerics.fields.CompiledField`): one-body energies acting on every
        moving body that has the attribute a field reads (``mass``, ``moment`` in
        ``attributes``, ...); see ``docs/fields.md``. A tabulated field given by name needs a
        ``region`` here (or use :meth:`with_fields` with a state).

    Notes
    -----
    The object is immutable after construction; kernels are compiled on first use and shared
    between systems with the same potentials.
    """

    def __init__(self, bodies: Sequence[Body], interactions: Sequence[Interaction | AllPairs] = (),
                 cutoff: float | None = None, scales: Scales | None = None,
                 fast_path: bool = True, smooth_cutoff: float | None = None,
                 parallel: bool = True,
                 parallel_min_bodies: int | None = None,
                 skin: float | None = None,
                 fields: Sequence[FieldLike] = ()) -> None:
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
        if skin is not None:
            if self.cutoff is None:
                raise InputError("skin needs a cutoff")
            if isinstance(skin, bool) or not isinstance(skin, (int, float, np.floating,
                                                               np.integer)):
                raise InputError(f"skin must be a positive number, got {skin!r}")
            if not (math.isfinite(float(skin)) and float(skin) > 0):
                raise InputError(f"skin must be positive and finite, got {skin!r}")
        self.skin = None if skin is None else float(skin)
        if not isinstance(parallel, (bool, np.bool_)):
            raise InputError(f"parallel must be True or False, got {parallel!r}")
        self.parallel = bool(parallel)
        self.parallel_min_bodies = _count_option(
            PARALLEL_MIN_BODIES if parallel_min_bodies is None else parallel_min_bodies,
            "parallel_min_bodies", 0)
        self.scales = scales
        self._fast_path = bool(fast_path)
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
        # parameters bound to body attributes are read per pair from the table B (SI values),
        # run-time parameters (SI) and the unit factors from an extra last row of B, so other
        # values compile nothing
        kern_ids: dict[tuple, int] = {}
        kerns: list[Dispatcher] = []
        rkerns: list[Dispatcher | None] = []
        attr_cols: dict[str, int] = {}
        param_cols: dict[int, float] = {}
        unit_col: list[int] = []
        inv_e = 1.0 / E

        def next_col() -> int:
            return len(attr_cols) + len(param_cols)

        def kernel_id(pot: PotentialLike, params: Mapping[str, object], i: int | None, j: int | None
                      ) -> tuple[int, str]:
            (kern, slots, values, array), orient = resolve_runtime(pot, params)
            needs_i = orient in ("both", "first")
            needs_j = orient in ("both", "second")
            for k, need in ((i, needs_i), (j, needs_j)):
                if k is not None and need and not bodies[k].is_top:
                    raise InputError(f"potential {_label(pot)!s} depends on the "
                                     f"axis of body {bodies[k].name!r}, which is a point mass")
            spec = tuple((attr_cols.setdefault(a, next_col()), w) for a, w in slots)
            # equal values share a kernel number (by bit pattern: -0.0 is not 0.0)
            key = (id(kern), spec, tuple(np.float64(v).tobytes() for v in values))
            if key not in kern_ids:
                kern_ids[key] = len(kerns)
                if scales and not unit_col:  # the units are data too (see unit_values)
                    unit_col.append(next_col())
                    for v in unit_values(L, inv_e):
                        param_cols[next_col()] = v
                pspec = None
                if values:
                    pspec = (next_col(), len(values), array)
                    for v in values:
                        param_cols[next_col()] = v
                ucol = unit_col[0] if scales else None
                kerns.append(_wrapped(kern, spec, 1.0, 1.0, pspec, ucol))
                rkerns.append(_wrapped_radial(kern, spec, 1.0, 1.0, pspec, ucol)
                              if orient == "none" else None)
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
        # rows: the bodies, then (with run-time parameters or units) one row of their values
        table = np.zeros((len(bodies) + (1 if param_cols else 0), max(1, next_col())))
        for a, c in attr_cols.items():
            for k, b in enumerate(bodies):
                table[k, c] = b.attribute(a)
        for c, v in param_cols.items():
            table[-1, c] = v
        self._kerns = tuple(kerns)
        self._rkerns = tuple(rkerns)
        # G in internal units (L³ / (M T²)) of a gravity interaction among all bodies, if any
        T = scales.time if scales else 1.0
        self._gravity = (gravity_g[0] * M * T * T / L ** 3 if len(gravity_g) == 1 else None)
        self._attributes = tuple(attr_cols)
        self._energy_shift = 0.0
        cut = np.inf if self.cutoff is None else self.cutoff / L
        rs_int = np.inf if self.smooth_cutoff is None else self.smooth_cutoff / L
        self.fields = compile_fields(fields)
        self._field_kerns: tuple[CompiledFunction, ...] = ()
        fdata = empty_field_data(len(bodies))
        if self.fields:  # one-body terms: the data gains their tables (numerics/fields)
            fdata, self._field_kerns = field_data(self.fields, bodies, L, E)
        self.data = system_data(
            mass=mass, alpha=alpha, body_slot=bslot, top_slot=tslot, fixed_pos=fpos,
            fixed_axis=fnu, pairs=pairs, set_members=cmembers, set_offsets=coffs,
            set_kernel=cgid, cutoff=cut, table=table, radial_pairs=rpairs,
            set_central=ccentral, any_tops=any(b.is_top for b in bodies),
            switch_start=rs_int, parallel_min=self.parallel_min_bodies, fields=fdata)
        # compile the parallel loop only for a system that may use it
        self._parallel = (self.cutoff is not None and self.parallel
                          and any(coffs[g + 1] - coffs[g] >= max(2, self.parallel_min_bodies)
                                  for g in range(len(cgid))))
        self._kernels: Kernels | None = None
        self._fixed = np.array([b.fixed for b in bodies], dtype=bool)
        # the state that last passed check_overlap, and the axis tolerance it then passed
        # check_state with (None: not checked): solve and the integrator check one state twice
        self._cleared: tuple[bytes | None, float | None] = (None, None)
        # the direct-sum form (nbody/direct.py): moving point masses, orientation-free
        # all-pairs sets, no cutoff, no listed pairs. Anything else the general kernels
        # compute (a new kind of term) must turn it off, or loop_kernels would drop it.
        self._direct = (self.cutoff is None and not pairs and not rpairs and not tops
                        and len(moving) == len(bodies) and all(ccentral) and not self.fields)
        self._loop: tuple[Kernels, DirectData] | None = None

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
    def external_fields(self) -> tuple[CompiledField, ...]:
        """The system's external fields (empty: a closed system, whose total linear and
        angular momentum are conserved)."""
        return self.fields

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
            extra = (field_term(self._field_kerns),) if self.fields else ()
            self._kernels = _build_kernels(*_dispatcher(self._kerns, self._rkerns),
                                           parallel=self._parallel,
                                           verlet=self.skin is not None, extra=extra)
        return self._kernels

    def with_fields(self, fields: Sequence[FieldLike], y: npt.ArrayLike | None = None,
                    attributes: Mapping[str, Mapping[str, float]] | None = None,
                    tol: float | None = None) -> NBodySystem:
        """A copy of this system with the external ``fields`` added to its own.

        Parameters
        ----------
        fields
            :func:`poissonkit.field` specs or built fields.
        y
            A state (internal units): a tabulated field without a ``region`` covers the
            positions of its moving bodies.
        attributes
            Per-body attributes to add, by body name (e.g. ``{"top": {"moment": 0.6}}``), for
            the fields to read.
        tol
            Default relative tolerance of tabulated fields.
        """
        extra = dict(attributes or {})
        bodies = [replace(b, attributes={**dict(b.attributes), **dict(extra.get(b.name, {}))})
                  for b in self.bodies]
        L = self.scales.length if self.scales else 1.0
        r = None if y is None else self._split(self._state(y))[0] * L

        def carriers(reads: str) -> np.ndarray:
            """Positions [m] of the moving bodies that carry the attribute a field reads."""
            if r is None:
                return np.zeros((0, 3))
            return r[[k for k, b in enumerate(bodies[i] for i in self._moving)
                      if reads == "mass" or reads in dict(b.attributes)]]
        built = self.fields + compile_fields(fields, carriers, tol)
        return NBodySystem(bodies, self.interactions, cutoff=self.cutoff, scales=self.scales,
                           fast_path=self._fast_path, smooth_cutoff=self.smooth_cutoff,
                           parallel=self.parallel, parallel_min_bodies=self.parallel_min_bodies,
                           skin=self.skin, fields=built)

    def work(self) -> Work:
        """Fresh scratch :class:`~poissonkit.numerics.nbody.data.Work` for the kernels
        (``pos, nu, F, T``), with a system's empty neighbour lists (see ``skin``) as ``lists``."""
        n = len(self.bodies)
        if self.skin is None:
            return new_work(n)
        L = self.scales.length if self.scales else 1.0
        return new_work(n, new_verlet_state(self.data.set_kernel.shape[0], self.skin / L))

    def loop_kernels(self) -> LoopKernels | None:
        """Direct-sum kernels for the compiled time loops, or ``None``.

        For moving point masses whose interactions are all orientation-free
        :class:`AllPairs` sets without cutoff (gravity, ``U(r)``), the kernels of
        :mod:`~poissonkit.numerics.nbody.direct` with their short data: the same numbers bit
        for bit as :attr:`kernels`, with less fixed work per step. ``None`` for any other
        system (tops, fixed bodies, a cutoff, listed pairs, orientation-dependent potentials).
        """
        if not self._direct:
            return None
        if self._loop is None:
            from poissonkit.numerics.nbody.direct import direct_kernels

            self._loop = (direct_kernels(*_dispatcher(self._kerns, self._rkerns)),
                          direct_data(self.data))
        return LoopKernels(*self._loop, new_direct_work(len(self.bodies)))

    def _state(self, y: npt.ArrayLike) -> np.ndarray:
        y = np.asarray(y, dtype=float)
        if y.ndim != 1 or y.shape[0] != self.dim:
            raise DimensionError(f"state has shape {y.shape}, expected ({self.dim},)")
        return np.ascontiguousarray(y)

    # ------------------------------------------------------------------ evaluation
    def rhs(self, t: float, y: npt.ArrayLike) -> np.ndarray:
        """``ẏ`` at state ``y`` (time ``t`` is ignored: the system is autonomous).

        Raises :class:`OverlapError` if two interacting bodies coincide.
        """
        return evaluate_rhs(self, y)

    def forces(self, y: npt.ArrayLike) -> tuple[np.ndarray, np.ndarray, float]:
        """Forces and torques on every body ``(F (n,3), T (n,3), U)`` (internal units)."""
        y = self._state(y)
        work = self.work()
        u = self.kernels.forces(y, self.data, work)
        return work.F, work.T, float(u)

    def energy(self, y: npt.ArrayLike) -> float | np.ndarray:
        """Total energy ``H(y)``; a 2-D array of states gives one value per row.

        Raises :class:`OverlapError` if two interacting bodies coincide.
        """
        return evaluate_energy(self, y)

    def _split(self, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        nm = self.n_moving
        rp = y[..., :6 * nm].reshape(y.shape[:-1] + (nm, 2, 3))
        nm_ = y[..., 6 * nm:].reshape(y.shape[:-1] + (self.n_tops, 2, 3))
        return rp[..., 0, :], rp[..., 1, :], nm_[..., 0, :], nm_[..., 1, :]

    def casimirs(self, y: npt.ArrayLike) -> np.ndarray:
        """Per top ``|ν|²`` and ``(ν, m)``, flattened ``[|ν_1|², (ν_1,m_1), …]`` (rows if 2-D)."""
        y = np.asarray(y, dtype=float)
        _, _, nu, m = self._split(y)
        out = np.stack([np.sum(nu * nu, axis=-1), np.sum(nu * m, axis=-1)], axis=-1)
        return out.reshape(y.shape[:-1] + (2 * self.n_tops,))

    def casimir_scales(self, y: npt.ArrayLike) -> np.ndarray:
        """Natural size of each Casimir at ``y`` (1 for ``|ν|²``, ``|m|`` for ``(ν, m)``)."""
        y = np.asarray(y, dtype=float)
        m = self._split(y)[3]
        s = np.stack([np.ones(m.shape[:-1]), np.linalg.norm(m, axis=-1)], axis=-1)
        return s.reshape(y.shape[:-1] + (2 * self.n_tops,))

    def linear_momentum(self, y: npt.ArrayLike) -> np.ndarray:
        """Total ``Σ p`` of the moving bodies (conserved without fixed bodies)."""
        _, p, _, _ = self._split(np.asarray(y, dtype=float))
        return p.sum(axis=-2)

    def angular_momentum(self, y: npt.ArrayLike) -> np.ndarray:
        """Total ``Σ r × p + Σ m`` about the origin (seed 000 eq. 21)."""
        r, p, _, m = self._split(np.asarray(y, dtype=float))
        return np.cross(r, p).sum(axis=-2) + m.sum(axis=-2)

    def min_distance(self, y: npt.ArrayLike) -> float:
        """Smallest distance between two bodies (internal units)."""
        return float(self.kernels.min_distance(self._state(y), self.data, self.work()))

    # ------------------------------------------------------------------ packing
    def pack(self, positions: npt.ArrayLike, momenta: npt.ArrayLike,
             axes: npt.ArrayLike | None = None, angular_momenta: npt.ArrayLike | None = None,
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

        def rows(a: npt.ArrayLike, wanted: tuple[int, ...], what: str) -> np.ndarray:
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

    def unpack(self, y: npt.ArrayLike, *, si: bool = False) -> dict[str, np.ndarray]:
        """Split a state (or rows of states) into ``r, p`` (moving bodies) and ``nu, m`` (tops)."""
        r, p, nu, m = self._split(np.asarray(y, dtype=float))
        s = self.scales if si else None
        if s:
            r, p, m = r * s.unit("length"), p * s.unit("momentum"), m * s.unit("angular_momentum")
        return {"r": r, "p": p, "nu": nu, "m": m}

    def _check_positions(self, r: np.ndarray) -> None:
        """:class:`OverlapError` if two bodies (moving rows ``r``, internal units) coincide."""
        if len(self._moving) == len(self.bodies):
            pos = r
        else:
            pos = self.data.fixed_pos.copy()
            pos[list(self._moving)] = r
        hit = coincident_pair(pos, self._fixed)
        if hit is not None:
            a, b = (self.bodies[k].name for k in hit)
            raise OverlapError(f"bodies {a!r} and {b!r} are at the same position "
                               f"{pos[hit[0]].tolist()} (internal units); every pair force is "
                               "singular there")

    def check_overlap(self, y: npt.ArrayLike) -> None:
        """Raise :class:`OverlapError` if two bodies of state ``y`` sit at the same place."""
        y = self._state(y)
        key = y.tobytes()
        if key == self._cleared[0]:  # the state last checked (solve, then the integrator)
            return
        self._check_positions(self._split(y)[0])
        self._cleared = (key, None)

    def check_state(self, y: npt.ArrayLike, tol: float = 1e-10) -> None:
        """Raise :class:`NonUnitAxisError` if some axis of ``y`` is not a unit vector and
        :class:`OverlapError` if two bodies coincide."""
        y = self._state(y)
        key = y.tobytes()
        if self._cleared == (key, tol):
            return
        self.check_overlap(y)
        if self.n_tops:
            c = self.casimirs(y)[0::2]
            bad = np.nonzero(np.abs(c - 1.0) > tol)[0]
            if bad.size:
                names = [self.bodies[self._tops[k]].name for k in bad]
                shown = ", ".join(f"{v:.3g} (off by {v - 1:.1e})" for v in c[bad])
                raise NonUnitAxisError(f"axes of {names} are not unit vectors (|ν|² = {shown}); "
                                       "normalise them (pack(..., normalize=True))")
        self._cleared = (key, tol)

    # ------------------------------------------------------------------ symbolic
    def to_structure(self) -> Bivector:
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
