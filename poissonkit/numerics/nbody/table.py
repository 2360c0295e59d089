"""The kernel table of an N-body system: which compiled potential each pair and set uses.

One kernel per distinct (potential, bound attributes, parameter values), in internal units.
Parameters bound to body attributes are read per pair from the table ``B`` (SI values);
run-time parameters (SI) and the unit factors sit in an extra last row of ``B``, so a system
with other values compiles nothing new (:mod:`~poissonkit.numerics.nbody.pairkernels`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
from numba.core.dispatcher import Dispatcher

from poissonkit.errors import InputError, UnknownNameError
from poissonkit.numerics.nbody.bodies import AllPairs, Body, Interaction, PotentialLike
from poissonkit.numerics.nbody.pairkernels import (_registry_entry, _wrapped, _wrapped_radial,
                                                   resolve_runtime, unit_values)
from poissonkit.plugin.contributions import PairPotential

Pair = tuple[int, int, int]


def _label(potential: PotentialLike) -> object:
    """How an error message names a potential: its registry name, else the potential itself."""
    return potential.name if isinstance(potential, PairPotential) else potential


@dataclass
class KernelTable:
    """The pairs, all-pairs sets and compiled kernels of a system (see the module docstring)."""

    #: the general kernel of each kernel number
    kerns: list[Dispatcher] = field(default_factory=list)
    #: the orientation-free kernel of each kernel number (``None``: it reads axes)
    rkerns: list[Dispatcher | None] = field(default_factory=list)
    #: listed pairs ``(i, j, kernel)`` for the general pair term
    pairs: list[Pair] = field(default_factory=list)
    #: listed orientation-free pairs (the fast path)
    radial_pairs: list[Pair] = field(default_factory=list)
    #: members of every all-pairs set, end to end, and where each set starts
    set_members: list[int] = field(default_factory=list)
    set_offsets: list[int] = field(default_factory=lambda: [0])
    #: kernel number of each set and whether it is orientation-free (1) or not (0)
    set_kernel: list[int] = field(default_factory=list)
    set_central: list[int] = field(default_factory=list)
    #: ``G`` (SI) of every gravity set over all bodies
    gravity_g: list[float] = field(default_factory=list)
    #: column of each body attribute read by a potential
    attr_cols: dict[str, int] = field(default_factory=dict)
    #: run-time parameter values and units in the last row, by column
    param_cols: dict[int, float] = field(default_factory=dict)
    #: the table ``B`` (built by :meth:`finish`)
    table: np.ndarray = field(default_factory=lambda: np.zeros((0, 1)))


class _Builder:
    """Fills a :class:`KernelTable` interaction by interaction."""

    def __init__(self, bodies: Sequence[Body], length: float, energy: float, scaled: bool,
                 fast_path: bool) -> None:
        self.bodies = bodies
        self.index = {b.name: k for k, b in enumerate(bodies)}
        self.length, self.inv_e, self.scaled = length, 1.0 / energy, scaled
        self.fast_path = fast_path
        self.out = KernelTable()
        self.kern_ids: dict[tuple, int] = {}
        self.unit_col: list[int] = []

    def idx(self, v: int | str) -> int:
        """Index of body ``v`` given by name or index."""
        if isinstance(v, str):
            if v not in self.index:
                raise UnknownNameError("body", v, self.index)
            return self.index[v]
        k = int(v)
        if not 0 <= k < len(self.bodies):
            raise InputError(f"body index {v} out of range 0..{len(self.bodies) - 1}")
        return k

    def next_col(self) -> int:
        return len(self.out.attr_cols) + len(self.out.param_cols)

    def kernel_id(self, pot: PotentialLike, params: Mapping[str, object], i: int | None,
                  j: int | None) -> tuple[int, str]:
        """Kernel number of ``pot`` with ``params`` (compiled once per distinct kernel) and
        which axes it reads; ``i``, ``j``: the bodies of a listed pair (checked for axes)."""
        out = self.out
        (kern, slots, values, array), orient = resolve_runtime(pot, params)
        needs_i = orient in ("both", "first")
        needs_j = orient in ("both", "second")
        for k, need in ((i, needs_i), (j, needs_j)):
            if k is not None and need and not self.bodies[k].is_top:
                raise InputError(f"potential {_label(pot)!s} depends on the axis of body "
                                 f"{self.bodies[k].name!r}, which is a point mass")
        spec = tuple((out.attr_cols.setdefault(a, self.next_col()), w) for a, w in slots)
        # equal values share a kernel number (by bit pattern: -0.0 is not 0.0)
        key = (id(kern), spec, tuple(np.float64(v).tobytes() for v in values))
        if key not in self.kern_ids:
            self.kern_ids[key] = len(out.kerns)
            if self.scaled and not self.unit_col:  # the units are data too (see unit_values)
                self.unit_col.append(self.next_col())
                for v in unit_values(self.length, self.inv_e):
                    out.param_cols[self.next_col()] = v
            pspec = None
            if values:
                pspec = (self.next_col(), len(values), array)
                for v in values:
                    out.param_cols[self.next_col()] = v
            ucol = self.unit_col[0] if self.scaled else None
            out.kerns.append(_wrapped(kern, spec, 1.0, 1.0, pspec, ucol))
            out.rkerns.append(_wrapped_radial(kern, spec, 1.0, 1.0, pspec, ucol)
                              if orient == "none" else None)
        return self.kern_ids[key], orient

    def add_pair(self, it: Interaction) -> None:
        i, j = self.idx(it.i), self.idx(it.j)
        if i == j:
            raise InputError(f"interaction of body {self.bodies[i].name!r} with itself")
        if self.bodies[i].fixed and self.bodies[j].fixed:
            return  # constant energy, no force on any degree of freedom
        gid, orient = self.kernel_id(it.potential, it.params, i, j)
        fast = orient == "none" and self.fast_path
        (self.out.radial_pairs if fast else self.out.pairs).append((i, j, gid))

    def add_set(self, it: AllPairs) -> None:
        bodies, out = self.bodies, self.out
        mem = list(range(len(bodies))) if it.members is None else [self.idx(v) for v in it.members]
        if len(set(mem)) != len(mem):
            raise InputError("AllPairs members repeat a body")
        point = [bodies[k].name for k in mem if not bodies[k].is_top]
        gid, orient = self.kernel_id(it.potential, it.params, None, None)
        if point and orient != "none":
            raise InputError(f"potential depends on axes but AllPairs includes point "
                             f"masses {point}")
        entry = _registry_entry(it.potential)
        if (entry is not None and entry.name == "gravity"
                and sorted(mem) == list(range(len(bodies)))
                and not {"mass1", "mass2"} & set(it.params)):
            out.gravity_g.append(float(entry.resolve_params(
                dict(it.params.items()) | {"mass1": 1.0, "mass2": 1.0})["G"]))
        out.set_members.extend(mem)
        out.set_offsets.append(len(out.set_members))
        out.set_kernel.append(gid)
        out.set_central.append(1 if orient == "none" and self.fast_path else 0)

    def finish(self) -> KernelTable:
        """The table ``B``: rows the bodies, then (with run-time parameters or units) one row
        of their values."""
        out = self.out
        table = np.zeros((len(self.bodies) + (1 if out.param_cols else 0),
                          max(1, self.next_col())))
        for a, c in out.attr_cols.items():
            for k, b in enumerate(self.bodies):
                table[k, c] = b.attribute(a)
        for c, v in out.param_cols.items():
            table[-1, c] = v
        out.table = table
        return out


def kernel_table(bodies: Sequence[Body], interactions: Sequence[Interaction | AllPairs],
                 length: float, energy: float, scaled: bool, fast_path: bool) -> KernelTable:
    """The :class:`KernelTable` of ``interactions`` among ``bodies``.

    ``length``, ``energy``: the internal units (SI) when ``scaled``; ``fast_path`` sends
    orientation-free potentials to the pair terms without axes.

    Raises
    ------
    InputError
        If an entry is neither an :class:`Interaction` nor an :class:`AllPairs`, names an
        unknown body, pairs a body with itself, repeats a member, or puts a potential that
        reads axes on a point mass.
    """
    builder = _Builder(bodies, length, energy, scaled, fast_path)
    for it in interactions:
        if isinstance(it, Interaction):
            builder.add_pair(it)
        elif isinstance(it, AllPairs):
            builder.add_set(it)
        else:
            raise InputError(f"interactions must be Interaction or AllPairs, got "
                             f"{type(it).__name__}")
    return builder.finish()
