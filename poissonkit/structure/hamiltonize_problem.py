"""The inputs of a Hamiltonisation search: the problem (``X``, ``H``, Casimirs, ``rho``) and the
ansatz for ``P`` (see :mod:`poissonkit.structure.hamiltonize` for the method)."""

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import sympy as sp

from poissonkit.errors import InputError
from poissonkit.structure._expr import as_expr

__all__ = ["Ansatz", "HamiltonizationProblem", "problem_from"]

# ------------------------------------------------------------------------------ inputs
@dataclass(frozen=True)
class HamiltonizationProblem:
    """What :func:`hamiltonize` is asked: a field, a Hamiltonian, Casimirs, a measure.

    Parameters
    ----------
    coords
        State coordinates, in order.
    field
        ``X``: one expression per coordinate (the equations of motion ``xdot = X``).
    hamiltonian
        ``H`` for the condition ``X = N P dH``; ``None`` drops that condition (then only the
        Casimir conditions and Jacobi are imposed, survey eq. (12)).
    casimirs
        ``{name: C}``: functions that must be Casimirs of ``P``.
    measure
        Invariant-measure density ``rho`` (``div(rho X) = 0``) or ``None``.
    name
        Label for reports.
    hamiltonian_span
        ``{name: I}``: instead of a fixed ``hamiltonian``, search ``H = sum c_k I_k`` with
        unknown constants ``c_k`` (not all zero). Excludes ``hamiltonian``.
    casimir_differentials
        ``{name: (a_1, ..., a_n)}``: closed 1-forms ``a = dC`` of Casimirs known only through
        their differential (``C`` itself may be a logarithm, an integral, a non-elementary
        function): the condition is ``P a = 0``, linear in ``P`` like any Casimir's. Closedness
        (``d_i a_j = d_j a_i``) is checked exactly, so ``a`` is locally ``dC``.
    """

    coords: tuple[sp.Symbol, ...]
    field: tuple[sp.Expr, ...]
    hamiltonian: sp.Expr | None = None
    casimirs: Mapping[str, sp.Expr] = field(default_factory=dict)
    measure: sp.Expr | None = None
    name: str = ""
    hamiltonian_span: Mapping[str, sp.Expr] = field(default_factory=dict)
    casimir_differentials: Mapping[str, tuple[sp.Expr, ...]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        put = object.__setattr__
        coords = tuple(self.coords)
        if not coords or not all(isinstance(c, sp.Symbol) for c in coords):
            raise InputError("HamiltonizationProblem.coords must be a non-empty sequence of "
                             "sympy symbols")
        if len(set(coords)) != len(coords):
            raise InputError("HamiltonizationProblem.coords repeats a coordinate")
        put(self, "coords", coords)
        fld = tuple(as_expr(e, f"field component {k}") for k, e in enumerate(self.field))
        if len(fld) != len(coords):
            raise InputError(f"HamiltonizationProblem.field has {len(fld)} components for "
                             f"{len(coords)} coordinates")
        put(self, "field", fld)
        if self.hamiltonian is not None:
            put(self, "hamiltonian", as_expr(self.hamiltonian, "hamiltonian"))
        if not isinstance(self.casimirs, Mapping):
            raise InputError("HamiltonizationProblem.casimirs must be a mapping name -> expression")
        put(self, "casimirs", {str(k): as_expr(v, f"Casimir {k!r}")
                               for k, v in self.casimirs.items()})
        if self.measure is not None:
            put(self, "measure", as_expr(self.measure, "measure"))
        if not isinstance(self.hamiltonian_span, Mapping) or \
                not isinstance(self.casimir_differentials, Mapping):
            raise InputError("HamiltonizationProblem.hamiltonian_span and casimir_differentials "
                             "must be mappings name -> expression / 1-form")
        span = {str(k): as_expr(v, f"integral {k!r}") for k, v in self.hamiltonian_span.items()}
        if span and self.hamiltonian is not None:
            raise InputError("give a Hamiltonian or a span of integrals to search it in, not "
                             "both")
        put(self, "hamiltonian_span", span)
        forms = {}
        for k, form in self.casimir_differentials.items():
            if isinstance(form, (str, sp.Basic)) or len(form) != len(coords):
                raise InputError(f"Casimir differential {k!r} must have {len(coords)} "
                                 "components, one per coordinate")
            forms[str(k)] = tuple(as_expr(a, f"component of d({k})") for a in form)
            _check_closed(forms[str(k)], coords, str(k))
        put(self, "casimir_differentials", forms)

    def casimir_forms(self) -> dict[str, tuple[sp.Expr, ...]]:
        """``{name: dC}`` for every Casimir condition: the given functions' gradients and the
        given differentials."""
        out = {k: tuple(sp.diff(C, x) for x in self.coords) for k, C in self.casimirs.items()}
        out.update(self.casimir_differentials)
        return out


def _check_closed(form: tuple[sp.Expr, ...], coords: tuple[sp.Symbol, ...], name: str) -> None:
    """Refuse a 1-form that is not closed: it is the differential of no function."""
    for i in range(len(coords)):
        for j in range(i + 1, len(coords)):
            curl = sp.cancel(sp.together(sp.diff(form[j], coords[i]) - sp.diff(form[i], coords[j])))
            if curl != 0:
                raise InputError(f"d({name}) is not closed: d{coords[i]} of component "
                                 f"{coords[j]} minus d{coords[j]} of component {coords[i]} is "
                                 f"{curl}, so it is the differential of no function")


def problem_from(system, *, hamiltonian=..., casimirs=None) -> HamiltonizationProblem:
    """A :class:`HamiltonizationProblem` from a system: field, Hamiltonian, Casimirs, measure.

    Parameters
    ----------
    system
        A :class:`HamiltonizationProblem` (returned as is, with overrides applied), a
        :class:`~poissonkit.structure.system.HamiltonianSystem` (its ``original`` equations of
        motion; only a system without them has its field computed as ``N P dH``, the one use
        of its bracket), or the name of a registered system (built with default parameters).
    hamiltonian
        Override of ``H`` (``None``: no ``X = N P dH`` condition).
    casimirs
        Override of the Casimirs: a mapping, or a sequence of names among the system's
        Casimirs and integrals.
    """
    from poissonkit.structure.system import HamiltonianSystem

    if isinstance(system, str):
        from poissonkit.plugin import system as registry_entry

        entry = registry_entry(system)
        system = entry.build(**entry.resolve_params({}))
    if isinstance(system, HamiltonizationProblem):
        prob = system
        known = dict(prob.casimirs)
    elif isinstance(system, HamiltonianSystem):
        coords = system.coords
        if system.original:
            fld = tuple(system.original[c] for c in coords)
        else:  # the field is the equations of motion, however the system states them
            fld = tuple(system.vector_field())
        H = system.hamiltonian if system.hamiltonian != 0 else None
        prob = HamiltonizationProblem(coords, fld, H, dict(system.casimirs), system.measure,
                                      system.name)
        known = {**dict(system.casimirs), **dict(system.integrals)}
    else:
        raise InputError(f"hamiltonize: system must be a HamiltonianSystem, a "
                         f"HamiltonizationProblem or a registered name, got "
                         f"{type(system).__name__}")
    H = prob.hamiltonian if hamiltonian is ... else hamiltonian
    cas = prob.casimirs
    if casimirs is not None:
        if isinstance(casimirs, Mapping):
            cas = dict(casimirs)
        else:
            try:
                cas = {str(k): known[str(k)] for k in casimirs}
            except KeyError as exc:
                from poissonkit.errors import UnknownNameError

                raise UnknownNameError("Casimir", str(exc.args[0]), known) from None
    return HamiltonizationProblem(prob.coords, prob.field, H, cas, prob.measure, prob.name,
                                  prob.hamiltonian_span if hamiltonian is ... else {},
                                  prob.casimir_differentials)


@dataclass(frozen=True)
class Ansatz:
    """The space searched: ``P = prefactor * Q``, each ``Q^{ij}`` polynomial with unknown
    coefficients (survey eq. (13) when ``momentum_terms="affine"``).

    Parameters
    ----------
    positions
        Coordinates in which the coefficients are polynomials (``gamma``).
    momenta
        Coordinates in which ``Q`` is affine / linear (``M``, ``K``, ``omega``).
    degree
        Maximal total degree of the coefficients in the positions.
    momentum_terms
        ``"affine"`` (``c^k_ij(pos) p_k + d_ij(pos)``, survey (13)), ``"linear"`` (no
        ``d_ij``) or ``"none"`` (coefficients only).
    prefactor
        Fixed scalar ``s(x)``; ``d log s`` must be rational (``s = g^{-1}`` with ``g^2``
        polynomial is fine).
    zero
        Index pairs ``(i, j)`` (0-based, coordinate order) forced to vanish, e.g. the
        ``{gamma_i, gamma_j}`` block.
    """

    positions: tuple[sp.Symbol, ...]
    momenta: tuple[sp.Symbol, ...] = ()
    degree: int = 1
    momentum_terms: str = "affine"
    prefactor: sp.Expr = sp.Integer(1)
    zero: frozenset[tuple[int, int]] = frozenset()

    def __post_init__(self) -> None:
        put = object.__setattr__
        put(self, "positions", tuple(self.positions))
        put(self, "momenta", tuple(self.momenta))
        if set(self.positions) & set(self.momenta):
            raise InputError("Ansatz: a coordinate cannot be both a position and a momentum")
        if isinstance(self.degree, bool) or not isinstance(self.degree, int) or self.degree < 0:
            raise InputError(f"Ansatz.degree must be an integer >= 0, got {self.degree!r}")
        if self.momentum_terms not in ("affine", "linear", "none"):
            raise InputError(f"Ansatz.momentum_terms must be 'affine', 'linear' or 'none', got "
                             f"{self.momentum_terms!r}")
        put(self, "prefactor", as_expr(self.prefactor, "Ansatz.prefactor"))
        if self.prefactor == 0:
            raise InputError("Ansatz.prefactor must not be zero")
        zero = set()
        for pair in self.zero:
            try:
                i, j = (int(k) for k in pair)
            except (TypeError, ValueError):
                raise InputError(f"Ansatz.zero: {pair!r} is not an index pair") from None
            zero.add((min(i, j), max(i, j)))
        put(self, "zero", frozenset(zero))

    def describe(self, coords: Sequence[sp.Symbol] = ()) -> str:
        """One line stating the searched space."""
        mom = {"affine": "affine in", "linear": "linear in", "none": "independent of"}[
            self.momentum_terms]
        poly = (f"polynomial of degree <= {self.degree} in "
                f"({', '.join(map(str, self.positions))})")
        text = (f"P = ({self.prefactor}) * Q, Q^ij {mom} ({', '.join(map(str, self.momenta))})"
                f" with coefficients {poly}") if self.momenta else \
            f"P = ({self.prefactor}) * Q, Q^ij {poly}"
        if self.zero and coords:
            names = ", ".join(f"{{{coords[i]},{coords[j]}}}" for i, j in sorted(self.zero))
            text += f"; forced zero: {names}"
        return text
