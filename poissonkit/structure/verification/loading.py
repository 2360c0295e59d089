"""What ``poissonkit verify`` checks: a bivector from a JSON file or a registered entry.

A JSON structure file holds a bivector in PoissonGeometry's dict format::

    {"dim": 3, "bivector": {"1,2": "x3", "1,3": "-x2", "2,3": "x1"}}

with coordinates ``x1 .. xn`` (or an optional ``"coords": [...]`` list, and ``"params": [...]``
naming symbolic parameters the entries may use, or ``{"b": {"positive": true}}`` with
assumptions, as ``Bivector.from_components(..., params=...)`` takes them). Strings are parsed
with the allow-list parser, never evaluated. Parameters of registered entries are read as the
exact rationals their texts mean (:func:`exact_number`).
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from decimal import Decimal
from fractions import Fraction
from pathlib import Path
from typing import TYPE_CHECKING, Union

import sympy as sp

from poissonkit.errors import InputError, ParseError
from poissonkit.input_limits import check_strings, loads_json, read_text

if TYPE_CHECKING:
    from poissonkit.plugin import SystemEntry
    from poissonkit.structure.bivector import Bivector
    from poissonkit.structure.verification.claims import SystemClaim
    from poissonkit.structure.system import HamiltonianSystem

#: What a verify target builds.
Verifiable = Union["Bivector", "HamiltonianSystem"]
#: A ``--param`` value as written: one text, or the texts of a comma-separated vector.
ParamText = Union[str, tuple[str, ...]]

#: Keys a JSON structure file may contain.
JSON_KEYS = ("dim", "bivector", "coords", "variable", "params", "name")
#: Largest dimension a JSON structure may declare: the Jacobi identity has ``dim^3/6``
#: components, and ``"dim": 10**9`` must be refused, not allocated.
MAX_DIM = 200
#: Tag of registry entries whose bracket is deliberately not Poisson.
ALMOST_POISSON_TAG = "almost-poisson"

__all__ = ["ALMOST_POISSON_TAG", "JSON_KEYS", "MAX_DIM", "MAX_EXPONENT", "entry_claims",
           "exact_number", "is_almost_poisson", "load_structure_json", "load_target"]

def _parse_key(key: str | Sequence[int | str]) -> tuple[int, int]:
    if isinstance(key, (list, tuple)):
        parts = list(key)
    else:
        parts = [p for p in re.split(r"[\s,()]+", str(key)) if p]
    try:
        idx = tuple(int(p) for p in parts)
    except ValueError:
        raise InputError(f"bivector key {key!r} is not a pair of 1-based indices") from None
    if len(idx) != 2:
        raise InputError(f"bivector key {key!r} must name two indices")
    if min(idx) < 1:
        raise InputError(f"bivector key {key!r}: indices are 1-based (zero or negative given)")
    return idx  # type: ignore[return-value]


def load_structure_json(source: str | Path | dict) -> tuple[str, Bivector]:
    """Read a bivector in PoissonGeometry's dict format (a path or an already-loaded dict).

    Returns
    -------
    (name, Bivector)

    The file is read within the limits of :mod:`poissonkit.input_limits`:
    at most :data:`~poissonkit.input_limits.MAX_TEXT_BYTES` bytes, nesting
    :data:`~poissonkit.input_limits.MAX_DEPTH` levels deep,
    :data:`~poissonkit.input_limits.MAX_NUMBER_DIGITS` digits per number, valid Unicode
    (no lone surrogates such as ``"\\ud800"``).

    Raises
    ------
    InputError, ParseError, DimensionError
        Malformed file, unknown keys, unknown symbols or unsafe expressions; a limit above
        exceeded (:class:`~poissonkit.errors.ParseError` naming the limit).
    """
    from poissonkit.structure.bivector import Bivector
    from poissonkit.structure.parsing import declare_parameters, parse_expression

    if isinstance(source, dict):
        data, name = source, str(source.get("name", "structure"))
    else:
        path = Path(source)
        data = loads_json(read_text(path, "structure file"), str(path), ParseError)
        name = path.name
    if not isinstance(data, dict):
        raise InputError("structure file must hold a JSON object")
    check_strings(data, "structure", ParseError)  # a dict from Python skipped loads_json
    unknown = set(data) - set(JSON_KEYS)
    if unknown:
        raise InputError(f"unknown key(s) {sorted(unknown)}; allowed: {', '.join(JSON_KEYS)}")
    if "bivector" not in data or not isinstance(data["bivector"], dict):
        raise InputError('structure file needs a "bivector" object {"i,j": "expression"}')
    coords = data.get("coords")
    dim = data.get("dim")
    if coords is not None:
        if not isinstance(coords, list) or not all(isinstance(c, str) for c in coords):
            raise InputError('"coords" must be a list of names')
        for c in coords:
            if not re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", c):
                raise InputError(f'"coords": coordinate name {c!r} is not an identifier')
        if dim is not None and dim != len(coords):
            raise InputError(f'"dim" = {dim} but "coords" has {len(coords)} names')
        dim = len(coords)
        if not 2 <= dim <= MAX_DIM:
            raise InputError(f'"coords" must name 2 to {MAX_DIM} coordinates, got {dim}')
    if coords is None and dim is None:
        raise InputError('structure file needs "dim" (an integer) or "coords" (a list of names)')
    if not isinstance(dim, int) or isinstance(dim, bool) or not 2 <= dim <= MAX_DIM:
        raise InputError(f'"dim" must be an integer from 2 to {MAX_DIM}, got {dim!r}')
    if coords is None:
        var = data.get("variable", "x")
        if not isinstance(var, str) or not re.fullmatch(r"[A-Za-z][A-Za-z_]*", var):
            raise InputError(f'"variable" must be a name, got {var!r}')
        coords = [f"{var}{i}" for i in range(1, dim + 1)]
    syms = [sp.Symbol(c, real=True) for c in coords]
    params = data.get("params", [])
    # declared as in Bivector.from_components: names, or {name: {"positive": true}}
    if not (isinstance(params, list) and all(isinstance(p, str) for p in params)) and \
            not (isinstance(params, dict) and all(v is None or isinstance(v, dict)
                                                  for v in params.values())):
        raise InputError('"params" must be a list of names or an object {name: assumptions}')
    try:
        extra = declare_parameters(params, reserved=coords)
    except InputError as exc:
        raise InputError(f'"params": {exc}') from None
    comps = {}
    for key, value in data["bivector"].items():
        i, j = _parse_key(key)
        if isinstance(value, bool) or not isinstance(value, (str, int, float)):
            raise ParseError(f"component {key!r}: expected an expression string, got {value!r}")
        try:
            comps[(i, j)] = parse_expression(str(value), syms, extra)
        except ParseError as exc:  # name the component, not only the text
            hint = (f' (coordinates {coords[0]}..{coords[-1]} from "dim", "coords" or "variable"; '
                    'declare symbolic parameters in "params")') if "not allowed" in str(exc) \
                else ""
            raise ParseError(f"bivector component {key!r}: {exc}{hint}") from None
    try:
        return name, Bivector.from_components(comps, syms)
    except InputError as exc:  # DimensionError, ParseError, ...: keep the type
        raise type(exc)(f"bivector: {exc}") from None


def _coerce_param(text: str) -> tuple[str, ParamText]:
    if "=" not in text:
        raise InputError(f"--param expects NAME=VALUE, got {text!r}")
    key, value = text.split("=", 1)
    value = value.strip()
    if "," in value:
        return key.strip(), tuple(v.strip() for v in value.split(","))
    return key.strip(), value


#: Largest decimal exponent of a parameter value (``1e1000``); larger ones are refused.
MAX_EXPONENT = 1000
_FRACTION = re.compile(r"[+-]?\d+\s*/\s*\d+")


def exact_number(text: str, name: str = "parameter") -> sp.Rational:
    """The exact rational a decimal or fraction text means: ``"0.3333" -> 3333/10000``.

    Parameters are used as written, never as the rational of their binary float
    (``3333333333333333/10000000000000000`` for ``1/3``); ``"1/3"`` is one third.

    Raises
    ------
    InputError
        If ``text`` is not a finite decimal number or a fraction of integers.
    """
    t = str(text).strip()
    try:
        if _FRACTION.fullmatch(t):
            num, den = (int(x) for x in t.split("/"))
            if den == 0:
                raise ZeroDivisionError
            return sp.Rational(num, den)
        dec = Decimal(t)  # decimals and exponents exactly, without computing them yet
        if not dec.is_finite() or abs(dec.adjusted()) > MAX_EXPONENT:
            raise ValueError  # nan, inf, and 1e999999999999 (would take hours to expand)
        value = Fraction(dec)
    except (ValueError, ZeroDivisionError, ArithmeticError):
        raise InputError(f"{name} must be a finite decimal number or a fraction, got {text!r}") \
            from None
    return sp.Rational(value.numerator, value.denominator)


def _exact_params(entry: SystemEntry, given: dict[str, ParamText]) -> dict[str, object]:
    """Validate ``--param`` values with the entry's typed parameters, then hand the builder the
    exact rationals of the texts for ``float`` and ``vector`` parameters."""
    types = {p.name: p.type for p in entry.params}
    check: dict[str, object] = {}
    exact: dict[str, object] = {}
    for key, value in given.items():
        kind = types.get(key)
        if kind in ("float", "vector") and isinstance(value, (str, tuple)):
            items = value if isinstance(value, tuple) else (value,)
            nums = tuple(exact_number(v, f"{entry.name}: parameter {key!r}") for v in items)
            check[key] = tuple(float(v) for v in nums) if kind == "vector" else float(nums[0])
            exact[key] = nums if kind == "vector" else nums[0]
        else:
            check[key] = value
    values = entry.resolve_params(check)  # types, signs, finiteness, unknown names
    values.update(exact)
    return values


def load_target(target: str, params: Sequence[str] = ()) -> tuple[str, str, Verifiable]:
    """``(name, doc, Bivector | HamiltonianSystem)`` for a registry name or a JSON path."""
    from poissonkit.plugin import names, system

    if target.endswith(".json") or (Path(target).is_file() and target not in names("system")):
        name, obj = load_structure_json(target)
        return name, "bivector from " + Path(target).name, obj
    entry = system(target)
    given = dict(_coerce_param(p) for p in params)
    return entry.name, entry.doc, entry.build(**_exact_params(entry, given))


def entry_claims(name: str) -> tuple[SystemClaim, ...]:
    """The system-specific claims of the registered entry ``name`` (none for a JSON file)."""
    from poissonkit.plugin import names, system

    return tuple(system(name).claims) if name in names("system") else ()


def is_almost_poisson(name: str) -> bool:
    """Whether the registered entry ``name`` states that its bracket is not Poisson."""
    from poissonkit.plugin import names, system

    return name in names("system") and ALMOST_POISSON_TAG in system(name).tags
