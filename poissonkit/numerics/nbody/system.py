"""The N-body system: bodies and interactions assembled into compiled kernels and a state layout.

See :mod:`poissonkit.numerics.nbody` for the state layout and the Hamiltonian. The constructor
checks its input (:mod:`~poissonkit.numerics.nbody.options`), scales the bodies
(:mod:`~poissonkit.numerics.nbody.scaling`), builds the kernel table
(:mod:`~poissonkit.numerics.nbody.table`) and the named kernel data
(:mod:`~poissonkit.numerics.nbody.data`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from poissonkit import contracts
from poissonkit.contracts import CompiledFunction, KineticSplit
from poissonkit.errors import DimensionError, InputError
from poissonkit.numerics.integrators.base import HasLoopKernels, LoopKernels
from poissonkit.numerics.fields.base import CompiledField, FieldLike, compile_fields
from poissonkit.numerics.fields.compose import field_data, field_term
from poissonkit.numerics.kernels import Kernels
from poissonkit.numerics.nbody.bodies import (BODY_SYSTEM_TRAITS, AllPairs, Body, Interaction,
                                              NonUnitAxisError)
from poissonkit.numerics.nbody.data import (DirectData, Work, direct_data, empty_field_data,
                                            new_direct_work, new_work, system_data)
from poissonkit.numerics.nbody.evaluate import (OverlapError, coincident_pair, evaluate_energy,
                                                evaluate_rhs)
from poissonkit.numerics.nbody.loops import _build_kernels
from poissonkit.numerics.nbody.options import PARALLEL_MIN_BODIES, check_bodies, check_options
from poissonkit.numerics.nbody.pairkernels import _dispatcher
from poissonkit.numerics.nbody.scaling import body_arrays, units_of
from poissonkit.numerics.nbody.table import kernel_table
from poissonkit.numerics.nbody.user_units import UnitsLike, as_unit_system, interactions_in
from poissonkit.numerics.nbody.verlet import new_verlet_state
from poissonkit.numerics.units import Scales

__all__ = ["PARALLEL_MIN_BODIES", "NBodySystem"]

if TYPE_CHECKING:
    from poissonkit.structure.bivector import Bivector

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
    units
        The units every number of the system is given in, as REBOUND's ``sim.units``: a
        :class:`~poissonkit.numerics.unitsystem.UnitSystem`, three names in any order
        (``("AU", "yr", "Msun")``) or a ``[units]``-style mapping (``{"G": 1.0}``: N-body
        units). Masses, positions, momenta, the cutoff, external fields' parameters and the
        times of :func:`~poissonkit.numerics.solve` are then in those units and so are the
        solution's times, energies and orbital elements; gravity's ``G`` (and any other
        left-out dimensional parameter of a registered potential) defaults to its value in
        them (:mod:`~poissonkit.numerics.nbody.user_units`). Default SI. Not with ``scales``.

    Notes
    -----
    The object is immutable after construction; kernels are compiled on first use and shared
    between systems with the same potentials.
    """

    #: the contracts this class fulfils, declared once (:mod:`poissonkit.traits`)
    traits = BODY_SYSTEM_TRAITS.extended(contracts.HasExternalFields, contracts.HasBodies,
                                         contracts.HasGravity, contracts.DeclaresGravityOnly,
                                         HasLoopKernels)

    def __init__(self, bodies: Sequence[Body], interactions: Sequence[Interaction | AllPairs] = (),
                 cutoff: float | None = None, scales: Scales | None = None,
                 fast_path: bool = True, smooth_cutoff: float | None = None,
                 parallel: bool = True,
                 parallel_min_bodies: int | None = None,
                 skin: float | None = None,
                 fields: Sequence[FieldLike] = (), units: UnitsLike = None) -> None:
        bodies = check_bodies(bodies)
        self.units = as_unit_system(units)
        if scales is not None and not self.units.is_si:
            raise InputError("give units (numbers in your units, as they are) or scales (SI "
                             "numbers in internal units), not both")
        interactions = interactions_in(interactions, self.units)
        opts = check_options(cutoff, smooth_cutoff, skin, parallel, parallel_min_bodies)
        self.bodies = bodies
        self.interactions = tuple(interactions)
        self.cutoff = opts.cutoff
        self.smooth_cutoff = opts.smooth_cutoff
        self.skin = opts.skin
        self.parallel = opts.parallel
        self.parallel_min_bodies = opts.parallel_min_bodies
        self.scales = scales
        self._fast_path = bool(fast_path)
        units = units_of(scales)
        L, M, E, T = units
        arrays = body_arrays(bodies, units)
        self._moving = arrays.moving
        self._tops = arrays.tops
        kt = kernel_table(bodies, self.interactions, L, E, scales is not None, self._fast_path)
        self._kerns = tuple(kt.kerns)
        self._rkerns = tuple(kt.rkerns)
        # G in internal units (L³ / (M T²)) of a gravity interaction among all bodies, if any
        self._gravity = (kt.gravity_g[0] * M * T * T / L ** 3 if len(kt.gravity_g) == 1
                         else None)
        self._attributes = tuple(kt.attr_cols)
        self._energy_shift = 0.0
        cut = np.inf if self.cutoff is None else self.cutoff / L
        rs_int = np.inf if self.smooth_cutoff is None else self.smooth_cutoff / L
        self.fields = compile_fields(fields)
        self._field_kerns: tuple[CompiledFunction, ...] = ()
        fdata = empty_field_data(len(bodies))
        if self.fields:  # one-body terms: the data gains their tables (numerics/fields)
            fdata, self._field_kerns = field_data(self.fields, bodies, L, E)
        self.data = system_data(
            mass=arrays.mass, alpha=arrays.alpha, body_slot=arrays.body_slot,
            top_slot=arrays.top_slot, fixed_pos=arrays.fixed_pos, fixed_axis=arrays.fixed_axis,
            pairs=kt.pairs, set_members=kt.set_members, set_offsets=kt.set_offsets,
            set_kernel=kt.set_kernel, cutoff=cut, table=kt.table, radial_pairs=kt.radial_pairs,
            set_central=kt.set_central, any_tops=any(b.is_top for b in bodies),
            switch_start=rs_int, parallel_min=self.parallel_min_bodies, fields=fdata)
        # compile the parallel loop only for a system that may use it
        self._parallel = (self.cutoff is not None and self.parallel
                          and any(hi - lo >= max(2, self.parallel_min_bodies)
                                  for lo, hi in zip(kt.set_offsets, kt.set_offsets[1:])))
        self._kernels: Kernels | None = None
        self._fixed = np.array([b.fixed for b in bodies], dtype=bool)
        # the state that last passed check_overlap, and the axis tolerance it then passed
        # check_state with (None: not checked): solve and the integrator check one state twice
        self._cleared: tuple[bytes | None, float | None] = (None, None)
        # the direct-sum form (nbody/direct.py): moving point masses, orientation-free
        # all-pairs sets, no cutoff, no listed pairs. Anything else the general kernels
        # compute (a new kind of term) must turn it off, or loop_kernels would drop it.
        self._direct = (self.cutoff is None and not kt.pairs and not kt.radial_pairs
                        and not self._tops and len(self._moving) == len(bodies)
                        and all(kt.set_central) and not self.fields)
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
    def gravity_only(self) -> bool:
        """True when Newtonian gravity over all bodies is the only interaction (no cutoff, no
        external field)."""
        return (self._gravity is not None and len(self.interactions) == 1 and self.cutoff is None
                and not self.fields)

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
        # kept: the report asks for it several times, 1.3·10⁶ names for 10⁵ tops (~1 s each)
        kept = self.__dict__.get("_layout")
        if kept is not None and kept[0] is self.bodies:
            return kept[1]
        out: list[str] = []
        for k in self._moving:
            n = self.bodies[k].name
            out += [f"{n}.{v}_{a}" for v in ("r", "p") for a in "xyz"]
        for k in self._tops:
            n = self.bodies[k].name
            out += [f"{n}.{v}_{a}" for v in ("nu", "m") for a in "xyz"]
        self._layout = (self.bodies, tuple(out))
        return self._layout[1]

    @property
    def kernels(self) -> Kernels:
        """The compiled kernels (compiled on first access)."""
        if self._kernels is None:
            extra = (field_term(self._field_kerns),) if self.fields else ()
            self._kernels = _build_kernels(*_dispatcher(self._kerns, self._rkerns),
                                           parallel=self._parallel,
                                           verlet=self.skin is not None, extra=extra,
                                           cells=self.cutoff is not None)
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
                           skin=self.skin, fields=built, units=self.units)

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
            where = ("internal units" if self.units.is_si
                     else self.units.label("length"))  # a system in the user's units: theirs
            raise OverlapError(f"bodies {a!r} and {b!r} are at the same position "
                               f"{pos[hit[0]].tolist()} ({where}); every pair force is "
                               "singular there")

    def kinetic_split(self) -> KineticSplit:
        """``T = Σ |p_s|²/2M_s + Σ α_t |m_t|²/2`` over the momentum slots of the moving bodies,
        then of the tops (the state's order)."""
        mass = np.asarray(self.data.mass, float)
        alpha = np.asarray(self.data.alpha, float)
        nm = mass.shape[0]
        idx: list[int] = []
        w: list[float] = []
        for s in range(nm):
            idx += [6 * s + 3 + d for d in range(3)]
            w += [1 / mass[s]] * 3
        for t in range(alpha.shape[0]):
            idx += [6 * nm + 6 * t + 3 + d for d in range(3)]
            w += [alpha[t]] * 3
        return KineticSplit("bodies", np.array(idx, dtype=np.int64), np.array(w, dtype=float))

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
