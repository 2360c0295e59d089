"""The inputs of :func:`~poissonkit.structure.hamiltonize.hamiltonize` as a researcher writes
them: a vector field, coordinates, parameters, a Hamiltonian or integrals, Casimirs -- as sympy
expressions or as text read by the allow-list parser (never ``eval``/``sympify``)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import sympy as sp

from poissonkit.errors import InputError, UnknownNameError
from poissonkit.structure._expr import as_expr, as_symbols
from poissonkit.structure.hamiltonize_problem import HamiltonizationProblem, problem_from
from poissonkit.structure.parsing import declare_parameters, parse_expression
from poissonkit.structure.system import HamiltonianSystem

__all__ = ["build_problem", "read_text"]


class _Reader:
    """Text or sympy value -> expression in the declared coordinates and parameters."""

    def __init__(self, coords: tuple[sp.Symbol, ...], params) -> None:
        self.coords = coords
        self.names = {str(c): c for c in coords}
        self.names.update(declare_parameters(params, reserved=coords))

    def __call__(self, value: object, what: str) -> sp.Expr:
        if isinstance(value, str):
            return parse_expression(value, (), self.names)
        expr = as_expr(value, what)
        for s in expr.free_symbols:  # Symbol("x") is not the real coordinate x
            c = self.names.get(str(s))
            if c is not None and c != s:
                raise InputError(f"{what}: symbol {s} has the name of {c} but other "
                                 "assumptions; build it from the coordinate symbols or pass "
                                 "names as text")
        return expr


def _named(items, stem: str, read: _Reader, what: str,
           known: Mapping[str, sp.Expr] | None = None) -> dict[str, sp.Expr]:
    """``{name: expr}`` from a mapping, or a sequence (auto-named ``stem1, stem2, ...``); a
    string item of a sequence that names a ``known`` function is that function."""
    if isinstance(items, Mapping):
        return {str(k): read(v, f"{what} {k!r}") for k, v in items.items()}
    if isinstance(items, (str, sp.Basic)) or not isinstance(items, Sequence):
        raise InputError(f"{what}s must be a sequence or a mapping name -> expression, got "
                         f"{type(items).__name__}")
    out: dict[str, sp.Expr] = {}
    for k, v in enumerate(items, start=1):
        if isinstance(v, str) and known is not None and v in known:
            out[v] = known[v]
        else:
            out[f"{stem}{k}"] = read(v, f"{what} {k}")
    return out


def _casimirs(items, read: _Reader, known: Mapping[str, sp.Expr]):
    """``({name: C}, {name: dC})``: a mapping value that is a sequence is a differential."""
    if isinstance(items, Mapping):
        funcs, forms = {}, {}
        for k, v in items.items():
            if isinstance(v, (list, tuple)):
                forms[str(k)] = tuple(read(a, f"component of d({k})") for a in v)
            else:
                funcs[str(k)] = read(v, f"Casimir {k!r}")
        return funcs, forms
    return _named(items, "C", read, "Casimir", known), {}


def _field(field, coords) -> tuple[tuple[sp.Symbol, ...], list]:
    if isinstance(field, Mapping):
        keys = list(field)
        if coords is None:
            coords = keys
        syms = as_symbols(coords)
        by_name = {str(c): k for c, k in zip(syms, syms)}
        values = []
        for c in syms:
            hit = [v for k, v in field.items() if str(k) == str(c)]
            if not hit:
                raise InputError(f"field: no component for coordinate {c}")
            values.append(hit[0])
        extra = [str(k) for k in keys if str(k) not in by_name]
        if extra:
            raise UnknownNameError("coordinate", extra[0], list(by_name))
        return syms, values
    if coords is None:
        raise InputError("hamiltonize: give coords= (names or symbols) with a field sequence")
    if isinstance(field, (str, sp.Basic)) or not isinstance(field, Sequence):
        raise InputError("field must be a sequence of components or a mapping coordinate -> "
                         "component")
    syms = as_symbols(coords)
    if len(field) != len(syms):
        raise InputError(f"field has {len(field)} components for {len(syms)} coordinates")
    return syms, list(field)


def _resolved(system):
    """A registered name built with its default parameters; anything else as is."""
    if isinstance(system, str):
        from poissonkit.plugin import system as registry_entry

        entry = registry_entry(system)
        return entry.build(**entry.resolve_params({}))
    return system


def build_problem(system=None, *, field=None, coords=None, params=None, hamiltonian=...,
                  integrals=None, casimirs=None, measure=None, name: str = ""
                  ) -> tuple[HamiltonizationProblem, dict[str, sp.Expr]]:
    """The problem and the integrals (``{}`` if none) of a :func:`hamiltonize` call.

    Either ``system`` (a HamiltonianSystem, a HamiltonizationProblem or a registered name) or
    ``field`` with ``coords``. With ``integrals`` and no ``hamiltonian``, ``H`` is searched
    among their combinations; with both, ``H`` is fixed and the integrals are only reported
    (which combinations are Casimirs of the brackets found).
    """
    if field is None and isinstance(system, (list, tuple, Mapping)):
        system, field = None, system  # hamiltonize(field, coords=...): the field given first
    if (system is None) == (field is None):
        raise InputError("hamiltonize: give either a system or field= (with coords=), not "
                         "both or neither")
    if system is not None:
        if params is not None or measure is not None or coords is not None:
            raise InputError("hamiltonize: params=, coords= and measure= go with field=; a "
                             "system brings its own")
        system = _resolved(system)
        base = problem_from(system, hamiltonian=hamiltonian,
                            casimirs=None if isinstance(casimirs, Mapping) else casimirs)
        known = dict(base.casimirs)
        if isinstance(system, HamiltonianSystem):
            known = {**system.casimirs, **system.integrals}
        read = _Reader(base.coords, None)
        read.names.update({str(s): s for e in (*base.field, *known.values())
                           for s in e.free_symbols})
    else:
        syms, comps = _field(field, coords)
        read = _Reader(syms, params)
        fld = tuple(read(v, f"field component for {c}") for c, v in zip(syms, comps))
        known = {}
        H = None if hamiltonian is ... or hamiltonian is None else read(hamiltonian,
                                                                       "Hamiltonian")
        rho = None if measure is None else read(measure, "measure")
        base = HamiltonizationProblem(syms, fld, H, {}, rho, name)
    ints = {} if integrals is None else _named(integrals, "I", read, "integral", known)
    if isinstance(casimirs, Mapping) or (system is None and casimirs is not None):
        funcs, forms = _casimirs(casimirs, read, {**known, **ints})
    else:
        funcs, forms = dict(base.casimirs), {}
    H = base.hamiltonian
    span = ints if (hamiltonian is ... and ints) else {}
    if span:
        H = None
    if H is None and not span and not funcs and not forms:
        raise InputError("hamiltonize: nothing to search for; give hamiltonian=, integrals= "
                         "(H is searched among their combinations) or casimirs=")
    prob = HamiltonizationProblem(base.coords, base.field, H, funcs, base.measure,
                                  name or base.name, span, forms)
    return prob, ints


def read_text(problem: HamiltonizationProblem, text: str, what: str) -> sp.Expr:
    """``text`` read by the allow-list parser in the names of ``problem``: its coordinates and
    the parameters its field, Hamiltonian and measure use (e.g. a ``prefactor``)."""
    read = _Reader(problem.coords, None)
    exprs = [*problem.field, problem.hamiltonian, problem.measure,
             *problem.casimirs.values(), *problem.hamiltonian_span.values()]
    read.names.update({str(s): s for e in exprs if e is not None for s in e.free_symbols})
    return read(text, what)
