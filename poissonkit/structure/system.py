"""A (conformally) Hamiltonian system: bivector + Hamiltonian + multiplier + known invariants."""

from __future__ import annotations

import functools
import math
import numbers
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace
from typing import Any

import sympy as sp

from poissonkit._display import html_table, latex_aligned, latex_text, text_block
from poissonkit.errors import InputError, ParseError, UnknownNameError
from poissonkit.structure._expr import as_expr
from poissonkit.structure.bivector import Bivector

_NON_FINITE = (sp.nan, sp.oo, -sp.oo, sp.zoo)


def _param_value(name: str, value: Any) -> Any:
    """Check one parameter value: a finite number, a sympy expression, or a tuple of these.

    Strings are kept as opaque labels (never sympified here), e.g. a potential's text.
    """
    if isinstance(value, str):
        return value
    if isinstance(value, (tuple, list)):
        return tuple(_param_value(name, v) for v in value)
    if isinstance(value, bool) or not isinstance(value, (numbers.Number, sp.Basic)):
        raise InputError(f"parameter {name!r} must be a number or a sympy expression, "
                         f"got {type(value).__name__}")
    if isinstance(value, sp.Basic):
        if value.has(*_NON_FINITE):
            raise InputError(f"parameter {name!r} is not finite: {value}")
        return value
    if not all(math.isfinite(part) for part in (complex(value).real, complex(value).imag)):
        raise InputError(f"parameter {name!r} is not finite: {value!r}")
    return value


def _text_names(structure: Bivector, params: Mapping[str, object]) -> dict[str, sp.Symbol]:
    """Names a text expression of a system may use: coordinates, then the bivector's own
    parameters (so ``"a"`` in ``H`` is the ``a`` of the bracket), then the keys of ``params``."""
    names = {str(c): c for c in structure.coords}
    for e in structure.matrix:
        for s in sorted(e.free_symbols, key=str):
            names.setdefault(str(s), s)
    if isinstance(params, Mapping):
        for k in params:
            if isinstance(k, str) and k.isidentifier() and not k.startswith("_"):
                names.setdefault(k, sp.Symbol(k, real=True))
    return names


def _read(value: object, what: str, names: Callable[[], Mapping[str, sp.Symbol]]) -> sp.Expr:
    """A sympy value as is; a text through the allow-list parser with ``names()``."""
    if not isinstance(value, str):
        return as_expr(value, what)
    from poissonkit.structure.parsing import parse_expression

    try:
        return parse_expression(value, (), names())
    except ParseError as exc:  # say which field, and that text is only ever parsed
        raise ParseError(f"{what} (text read by parse_expression, names: coordinates, the "
                         f"bracket's parameters and the keys of params): {exc}") from None


@dataclass(frozen=True)
class HamiltonianSystem:
    """``xdot = N(x) P(x) dH(x)`` with its claimed invariants.

    Parameters
    ----------
    structure
        The Poisson bivector ``P``.
    hamiltonian
        ``H`` as a sympy expression in ``structure.coords`` and parameters, or as text
        (``"(x1**2 + x2**2)/2 + a*x3"``). Text is read by the allow-list parser
        (:func:`~poissonkit.structure.parsing.parse_expression`, never ``eval``) and may name
        the coordinates, the parameters of ``structure`` (the same symbols, with their
        assumptions) and the keys of ``params``; any other name is a
        :class:`~poissonkit.errors.ParseError` listing the allowed ones. The same holds for
        ``multiplier``, ``casimirs``, ``integrals``, ``measure``, ``constraints`` and the
        values of ``original``.
    multiplier
        Conformal factor ``N`` (1 for Hamiltonian systems; ``-1/g`` for the survey's body-frame
        systems, see :mod:`poissonkit.conventions`).
    casimirs, integrals
        Claimed Casimirs of ``P`` and first integrals of the flow, by name.
    measure
        Claimed invariant-measure density ``rho`` (``div(rho X) = 0``), or ``None``.
    params
        Numerical values of symbolic parameters, by symbol name.
    name, doc
        Identification for reports.
    original
        Optional: the original equations of motion ``{x_i: xdot_i}`` the representation must
        reproduce (e.g. survey (34) for the Chaplygin ball).
    constraints
        Expressions that vanish on the physical phase space (e.g. ``|gamma|^2 - 1``), used when
        an identity only holds there.
    """

    structure: Bivector
    hamiltonian: sp.Expr
    multiplier: sp.Expr = sp.Integer(1)
    casimirs: Mapping[str, sp.Expr] = field(default_factory=dict)
    integrals: Mapping[str, sp.Expr] = field(default_factory=dict)
    measure: sp.Expr | None = None
    params: Mapping[str, Any] = field(default_factory=dict)
    name: str = ""
    doc: str = ""
    original: Mapping[sp.Symbol, sp.Expr] | None = None
    constraints: tuple[sp.Expr, ...] = ()

    def __post_init__(self) -> None:
        # Everything is converted through as_expr: strings are refused (sympify would eval them).
        if not isinstance(self.structure, Bivector):
            raise InputError(f"HamiltonianSystem.structure must be a Bivector, got "
                             f"{type(self.structure).__name__}")
        put = object.__setattr__  # frozen dataclass
        # built on the first text only: systems given as sympy pay nothing
        names = functools.cache(lambda: _text_names(self.structure, self.params))
        put(self, "hamiltonian", _read(self.hamiltonian, "Hamiltonian", names))
        put(self, "multiplier", _read(self.multiplier, "multiplier", names))
        for attr, what in (("casimirs", "Casimir"), ("integrals", "first integral")):
            items = getattr(self, attr)
            if not isinstance(items, Mapping):
                raise InputError(f"{attr} must be a mapping name -> expression, got "
                                 f"{type(items).__name__}")
            put(self, attr, {str(k): _read(v, f"{what} {k!r}", names) for k, v in items.items()})
        if self.measure is not None:
            put(self, "measure", _read(self.measure, "invariant measure", names))
        if isinstance(self.constraints, (str, sp.Basic)):
            raise InputError("constraints must be a sequence of expressions")
        put(self, "constraints", tuple(_read(c, "constraint", names) for c in self.constraints))
        if not isinstance(self.params, Mapping):
            raise InputError(f"params must be a mapping name -> value, got "
                             f"{type(self.params).__name__}")
        put(self, "params", {str(k): _param_value(str(k), v) for k, v in self.params.items()})
        if self.original is not None:
            if not isinstance(self.original, Mapping):
                raise InputError("original must be a mapping coordinate -> expression")
            put(self, "original", {k: _read(v, f"original equation for {k}", names)
                                   for k, v in self.original.items()})

    @property
    def coords(self) -> tuple[sp.Symbol, ...]:
        """The state coordinates, in order."""
        return self.structure.coords

    def parameter_names(self) -> set[str]:
        """Names of the symbolic parameters: free symbols of ``P``, ``H``, ``N`` but not coordinates."""
        free = set(self.hamiltonian.free_symbols) | set(self.multiplier.free_symbols)
        for e in self.structure.matrix:
            free |= e.free_symbols
        return {str(s) for s in free} - set(self.structure.names)

    def vector_field(self) -> sp.Matrix:
        """``X = N P dH`` as a column of sympy expressions."""
        return self.structure.hamiltonian_vector_field(self.hamiltonian, self.multiplier)

    def with_params(self, **values: Any) -> HamiltonianSystem:
        """A copy with some parameter values replaced.

        Raises
        ------
        UnknownNameError
            For a name that is neither in ``params`` nor a symbolic parameter of the system
            (a free symbol of ``P``, ``H`` or ``N`` other than a coordinate).
        """
        known = set(self.params) | self.parameter_names()
        for name in values:
            if name not in known:
                raise UnknownNameError("parameter", name, known)
        merged = dict(self.params)
        merged.update(values)
        return replace(self, params=merged)

    # ------------------------------------------------------------------ display
    def _rows(self, fmt) -> list[tuple[str, str]]:
        rows = [("H", fmt(self.hamiltonian))]
        if self.multiplier != 1:
            rows.append(("N", fmt(self.multiplier)))
        rows += [(f"Casimir {k}", fmt(v)) for k, v in self.casimirs.items()]
        rows += [(f"integral {k}", fmt(v)) for k, v in self.integrals.items()]
        if self.measure is not None:
            rows.append(("measure", fmt(self.measure)))
        rows += [(f"constraint {i + 1}", fmt(c)) for i, c in enumerate(self.constraints)]
        rows += [(f"param {k}", str(v)) for k, v in self.params.items()]
        return rows

    def _title(self) -> str:
        name = f" {self.name!r}" if self.name else ""
        doc = f" — {self.doc}" if self.doc else ""
        return (f"HamiltonianSystem{name} on R^{self.structure.dim} "
                f"({', '.join(self.structure.names)}){doc}")

    def __str__(self) -> str:
        """Name, coordinates, ``H``, ``N`` and the claimed invariants, one per line."""
        return text_block(self._title(), self._rows(str))

    def _repr_pretty_(self, p, cycle: bool) -> None:
        p.text("HamiltonianSystem(...)" if cycle else str(self))

    def _repr_html_(self) -> str:
        """HTML table of ``H``, ``N`` and the claimed invariants (Jupyter)."""
        return html_table(self._title(), self._rows(str))

    def _repr_latex_(self) -> str:
        """``H``, ``N`` and the claimed invariants as aligned LaTeX equations."""
        rows = [("H", sp.latex(self.hamiltonian))]
        if self.multiplier != 1:
            rows.append(("N", sp.latex(self.multiplier)))
        rows += [(f"C_{{{latex_text(k)}}}", sp.latex(v)) for k, v in self.casimirs.items()]
        rows += [(f"I_{{{latex_text(k)}}}", sp.latex(v)) for k, v in self.integrals.items()]
        if self.measure is not None:
            rows.append(("\\rho", sp.latex(self.measure)))
        return latex_aligned(rows)
