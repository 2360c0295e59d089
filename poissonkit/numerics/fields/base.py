"""What an external field is once built, what it is built for, and how users name one.

A field is compiled to an SI kernel ``f(x, y, z, ν_x, ν_y, ν_z, c, P) -> (U, U_x, U_y, U_z,
U_νx, U_νy, U_νz)``: the one-body energy of a body at ``r = (x, y, z)`` with axis ``ν`` and
coupling ``c`` (its mass, its moment, ...; the attribute the field ``reads``) and the partial
derivatives of ``U``; ``P`` is the field's data (a float array: a uniform vector, a table).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from dataclasses import field as dc_field
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from poissonkit.contracts import CompiledFunction
from poissonkit.errors import InputError
from poissonkit.numerics.fields.solids import Solid

if TYPE_CHECKING:
    from poissonkit.plugin.contributions import ExternalField


@dataclass(frozen=True)
class FieldRequest:
    """What a field is built for: where it is needed and how accurately.

    Attributes
    ----------
    points
        ``(n, 3)`` SI positions [m] of the bodies that read the field at t = 0 (empty when
        unknown); a tabulated field covers a box around them unless given a ``region``.
    tol
        Default relative tolerance of a tabulated field (its own ``tol`` parameter wins).
    """

    points: np.ndarray = dc_field(default_factory=lambda: np.zeros((0, 3)))
    tol: float | None = None


@dataclass(frozen=True)
class CompiledField:
    """An external field ready for the numerics.

    Attributes
    ----------
    name
        The registry name of the field (``"gravity"``, ``"magpylib"``, ...).
    kernel
        The compiled SI kernel ``f(x, y, z, ν_x, ν_y, ν_z, c, P)`` (module docstring).
    data
        ``P``: the field's data, a contiguous float64 array.
    reads
        The body attribute that couples to the field (``"mass"``, ``"moment"``).
    orientation
        True if ``U`` depends on the axis (bodies that read it must be tops).
    info
        What a report shows: parameters, the tabulation grid and its measured error, ...
    solids
        The space the source occupies (:class:`~poissonkit.numerics.fields.solids.Solid`
        pieces: magnets, wires), for drawing, contact and the start check; empty for fields
        without a shape (gravity, a uniform field).
    regrow
        For a tabulated field: ``regrow(lo, hi)`` builds the same kind of table over the box
        ``[lo, hi]`` [m] (:mod:`~poissonkit.numerics.fields.growth`); ``None``: fixed region.
    capacity
        Floats the system reserves for :attr:`data` so that a regrown table fits in place
        (0: only the table's own size).
    """

    name: str
    kernel: CompiledFunction
    data: np.ndarray
    reads: str
    orientation: bool = False
    info: Mapping[str, Any] = dc_field(default_factory=dict)
    solids: tuple[Solid, ...] = ()
    regrow: Callable[[np.ndarray, np.ndarray], CompiledField] | None = dc_field(
        default=None, compare=False, repr=False)
    capacity: int = dc_field(default=0, compare=False)

    def __getstate__(self) -> dict[str, Any]:
        """Pickled without :attr:`regrow` (it holds the source's own field function, which
        need not pickle): a copy in another process keeps its region."""
        state = dict(self.__dict__)
        state["regrow"] = None
        return state

    def energy(self, r: npt.ArrayLike, nu: npt.ArrayLike, coupling: float
               ) -> tuple[float, np.ndarray, np.ndarray]:
        """``(U, ∂U/∂r, ∂U/∂ν)`` [SI] of one body at ``r`` with axis ``nu`` and coupling
        ``coupling`` (a direct evaluation of the kernel, for checks)."""
        r = np.asarray(r, dtype=float).reshape(3)
        n = np.asarray(nu, dtype=float).reshape(3)
        out = self.kernel(r[0], r[1], r[2], n[0], n[1], n[2], float(coupling), self.data)
        return float(out[0]), np.array(out[1:4]), np.array(out[4:7])

    def force_torque(self, r: npt.ArrayLike, nu: npt.ArrayLike, coupling: float
                     ) -> tuple[np.ndarray, np.ndarray]:
        """Force ``−∂U/∂r`` [N] and torque ``ν × (−∂U/∂ν)`` [N m] on one body (SI)."""
        _, gr, gn = self.energy(r, nu, coupling)
        return -gr, np.cross(np.asarray(nu, dtype=float).reshape(3), -gn)


@dataclass(frozen=True)
class FieldSpec:
    """A field as a user names it: a registered field's name or a Python source object
    (e.g. a magpylib source), and its parameters. Build one with :func:`poissonkit.field`."""

    source: object
    params: Mapping[str, Any] = dc_field(default_factory=dict)

    def entry(self) -> ExternalField:
        """The registered field that builds this one (by name, or the first that accepts the
        source object)."""
        from poissonkit.plugin.contributions import ExternalField
        from poissonkit.plugin.registry import external_field, external_fields

        if isinstance(self.source, str):
            return external_field(self.source)
        found = [e for e in external_fields().values()
                 if isinstance(e, ExternalField) and e.accepts is not None
                 and e.accepts(self.source)]
        if not found:
            raise InputError(f"no registered field accepts a {type(self.source).__name__}; "
                             f"give a field name ({', '.join(sorted(external_fields()))}) "
                             "or a source a field plugin accepts (e.g. a magpylib source)")
        return found[0]

    def compile(self, request: FieldRequest | None = None) -> CompiledField:
        """Build the field (tabulating it if its entry does) for ``request``."""
        request = request or FieldRequest()
        entry = self.entry()
        obj = None if isinstance(self.source, str) else self.source
        params = entry.resolve_params(self.params)
        built = entry.build(params, request, obj)
        if not isinstance(built, CompiledField):
            raise InputError(f"field {entry.name!r} built a {type(built).__name__}, not a "
                             "CompiledField")
        return built


FieldLike = FieldSpec | CompiledField


def field(source: object, **params: Any) -> FieldSpec:
    """An external field for :class:`~poissonkit.numerics.nbody.NBodySystem` (``fields=``).

    Parameters
    ----------
    source
        A registered field's name (``"gravity"``, ``"uniform"``, ``"magpylib"``,
        ``"current_loop"``, or one a plugin adds) or a Python source object a field plugin
        accepts (a magpylib source or ``Collection``).
    **params
        The field's parameters (SI), e.g. ``g=(0, 0, -9.81)`` for gravity, or ``tol`` and
        ``region`` of a tabulated magpylib field.

    Returns
    -------
    FieldSpec
        Built when the system is (a tabulated field covers the bodies' initial positions
        unless given a ``region``).

    Examples
    --------
    >>> import poissonkit as pk
    >>> pk.field("gravity", g=(0.0, 0.0, -9.81)).compile().info["g"]
    (0.0, 0.0, -9.81)
    """
    return FieldSpec(source, dict(params))


def compile_fields(fields: Sequence[FieldLike],
                   points: npt.ArrayLike | Callable[[str], np.ndarray] | None = None,
                   tol: float | None = None) -> tuple[CompiledField, ...]:
    """Build every field of ``fields`` (already compiled ones are kept).

    ``points`` are the ``(n, 3)`` SI positions of the bodies a field acts on, or a function
    ``points(reads)`` giving those of the bodies that carry the attribute ``reads``.
    """
    def where(spec: FieldSpec) -> np.ndarray:
        if points is None:
            return np.zeros((0, 3))
        pts = points(spec.entry().reads) if callable(points) else points
        return np.asarray(pts, dtype=float).reshape(-1, 3)

    out = []
    for f in fields:
        if isinstance(f, CompiledField):
            out.append(f)
        elif isinstance(f, FieldSpec):
            out.append(f.compile(FieldRequest(where(f), tol)))
        else:
            raise InputError(f"fields must be built with pk.field(...), got {type(f).__name__}")
    return tuple(out)
