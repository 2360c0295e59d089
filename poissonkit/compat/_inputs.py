"""Reading PoissonGeometry-style inputs safely, and writing its output formats.

Inputs are dicts of 1-based index tuples to expression strings, e.g.
``{(1, 2): "x3", (1, 3): "-x2", (2, 3): "x1"}``. Strings are parsed with
:func:`poissonkit.structure.parsing.parse_expression` — never ``eval``/``sympify`` — with the
coordinates ``x1 .. xn`` and free parameter names (``a1``, ``L12``, ...) as the only allowed
names besides the parser's fixed table of functions and constants. A name that looks like a
coordinate but is out of range (``x7`` in dimension 3, ``x0``) is rejected.
"""

from __future__ import annotations

import ast
import operator
import re
from collections.abc import Mapping

import sympy as sp

from poissonkit.compat.errors import DiferentialFormError, MultivectorError
from poissonkit.errors import DimensionError, InputError, ParseError

Key = tuple[int, ...]


def validate_dimension(dimension: object) -> int:
    """PoissonGeometry's rule: an ``int`` at least 2, else :class:`DimensionError`."""
    if isinstance(dimension, bool) or not isinstance(dimension, int):
        raise DimensionError(f"dimension must be an int, got {dimension!r}")
    if dimension < 2:
        raise DimensionError(f"dimension must be at least 2, got {dimension}")
    return dimension


class _ListMatrix:
    """Nested lists seen through the ``tolist()`` interface of numpy / sympy matrices."""

    def __init__(self, rows: list) -> None:
        self._rows = rows

    def tolist(self) -> list:
        return list(self._rows)


class Reader:
    """Parses expressions and index dicts for one space ``R^n`` with coordinates ``{variable}1..n``.

    Parameters
    ----------
    dim
        Dimension ``n``.
    variable
        Coordinate prefix (PoissonGeometry's ``variable``, default ``"x"``).
    """

    def __init__(self, dim: int, variable: str = "x") -> None:
        if not isinstance(variable, str) or not re.fullmatch(r"[A-Za-z][A-Za-z]*", variable):
            raise InputError(f"variable must be a name made of letters, got {variable!r}")
        self.dim = dim
        self.variable = variable
        # Plain symbols, exactly as PoissonGeometry's sym.symbols('x1:n+1'), so outputs print alike.
        self.coords: tuple[sp.Symbol, ...] = tuple(sp.Symbol(f"{variable}{i}")
                                                   for i in range(1, dim + 1))
        self._coord_like = re.compile(rf"{re.escape(variable)}(\d+)")
        self._params: dict[str, sp.Symbol] = {}

    # ------------------------------------------------------------------ expressions
    def _free_names(self, text: str) -> set[str]:
        """Bare names in ``text`` that are not called (candidates for parameters)."""
        try:
            tree = ast.parse(text.replace("^", "**").strip(), mode="eval")
        except SyntaxError:
            return set()  # parse_expression reports the syntax error
        called = {id(n.func) for n in ast.walk(tree) if isinstance(n, ast.Call)}
        return {n.id for n in ast.walk(tree) if isinstance(n, ast.Name) and id(n) not in called}

    def expr(self, value: object, what: str = "expression") -> sp.Expr:
        """A sympy expression from a string, a number or a sympy object.

        Raises
        ------
        ParseError
            Syntax errors, disallowed names/constructs, out-of-range coordinates, other types.
        """
        from poissonkit.structure.parsing import ALLOWED_FUNCTIONS, parse_expression

        if isinstance(value, sp.Basic):
            # a symbol named like a coordinate (say x1 with real=True) *is* that coordinate
            by_name = {str(c): c for c in self.coords}
            rename = {s: by_name[s.name] for s in value.free_symbols
                      if isinstance(s, sp.Symbol) and s.name in by_name and s != by_name[s.name]}
            return sp.sympify(value.xreplace(rename) if rename else value)
        if isinstance(value, bool):
            raise ParseError(f"{what}: a bool is not an expression")
        if isinstance(value, int):
            return sp.Integer(value)
        if isinstance(value, float):
            return sp.Float(value)
        if not isinstance(value, str):
            raise ParseError(f"{what}: expected a string expression, got {type(value).__name__}")
        extra: dict[str, object] = {}
        coord_names = {str(c) for c in self.coords}
        for name in self._free_names(value):
            if name in coord_names or name in ALLOWED_FUNCTIONS or name.startswith("_"):
                continue  # the parser knows these (or rejects dunders itself)
            if self._coord_like.fullmatch(name):
                raise ParseError(
                    f"{what} {value!r} uses {name!r}, which is not a coordinate of this "
                    f"{self.dim}-dimensional space ({self.variable}1..{self.variable}{self.dim})")
            extra[name] = self._params.setdefault(name, sp.Symbol(name))
        return parse_expression(value, self.coords, extra)

    # ------------------------------------------------------------------ index dicts
    def _key(self, key: object, error: type[InputError], container: object) -> Key:
        if isinstance(key, int) and not isinstance(key, bool):
            key = (key,)
        if not isinstance(key, tuple) or not key:
            raise error(f"invalid key {key!r} in {container}: keys are tuples of 1-based indices")
        try:
            # operator.index accepts int and numpy integers, rejects floats and strings
            idx = tuple(operator.index(k) for k in key)
        except TypeError:
            raise error(f"invalid key {key!r} in {container}: indices must be integers") from None
        if any(isinstance(k, bool) for k in key):
            raise error(f"invalid key {key!r} in {container}: indices must be integers")
        if len(set(idx)) < len(idx):
            raise error(f"repeated indexes {key} in {container}")
        if any(i <= 0 for i in idx):
            raise error(f"invalid key {key} in {container}: indices start at 1")
        if any(i > self.dim for i in idx):
            raise DimensionError(f"index in {key} out of range 1..{self.dim} in {container}")
        return idx

    def _mapping(self, obj: object, what: str, error: type[InputError]) -> Mapping:
        if not isinstance(obj, Mapping):
            raise error(f"{what} must be a dict of index tuples to expressions, "
                        f"got {type(obj).__name__}")
        return obj

    def multivector(self, obj: object, what: str = "multivector"):
        """A :class:`~poissonkit.structure.schouten.Multivector` (0-based, sorted keys).

        Keys may come in any order (``(2, 1)`` means ``-(1, 2)``); all keys must have the same
        length. An empty dict is not accepted here (callers handle PoissonGeometry's ``{}``).
        """
        from poissonkit.structure.schouten import Multivector

        d = self._mapping(obj, what, MultivectorError)
        if not d:
            raise MultivectorError(f"{what} {d} is empty")
        comps: dict[Key, sp.Expr] = {}
        seen: set[Key] = set()
        lengths = set()
        for key, value in d.items():
            idx = self._key(key, MultivectorError, what)
            lengths.add(len(idx))
            zero_based = tuple(i - 1 for i in idx)
            if tuple(sorted(zero_based)) in seen:
                raise MultivectorError(f"component {key} of {what} given twice")
            seen.add(tuple(sorted(zero_based)))
            comps[zero_based] = self.expr(value, f"{what} component {key}")
        if len(lengths) > 1:
            raise MultivectorError(f"keys with different lengths in {what}: {sorted(lengths)}")
        degree = lengths.pop()
        return Multivector(degree, self.coords, comps)

    def bivector(self, obj: object, what: str = "bivector"):
        """A :class:`~poissonkit.structure.Bivector` from ``{(i, j): P^{ij}}``.

        Also accepted (poissonkit extensions): a :class:`~poissonkit.structure.Bivector` of the
        right dimension, or a full ``n x n`` matrix (nested lists, numpy array, sympy Matrix) of
        expressions/strings, which must be antisymmetric.
        """
        from poissonkit.structure import Bivector

        if isinstance(obj, Bivector):
            if obj.dim != self.dim:
                raise DimensionError(f"{what} has dimension {obj.dim}, expected {self.dim}")
            return Bivector(self.coords, obj.matrix.subs(dict(zip(obj.coords, self.coords)),
                                                         simultaneous=True))
        if isinstance(obj, list):
            obj = _ListMatrix(obj)
        if isinstance(obj, (sp.MatrixBase, _ListMatrix)) or type(obj).__module__ == "numpy":
            # an extension: a full matrix (entries parsed like dict values); the core checks
            # its size (DimensionError) and antisymmetry (InputError)
            raw = obj.tolist()
            if not all(isinstance(row, (list, tuple)) for row in raw):
                raise DimensionError(f"{what} given as a matrix must be a list of {self.dim} rows")
            n_rows, n_cols = len(raw), {len(row) for row in raw}
            if n_cols != {n_rows}:
                raise DimensionError(f"{what} matrix must be square, got {n_rows} rows of "
                                     f"lengths {sorted(n_cols)}")
            if n_rows != self.dim:
                raise DimensionError(f"{what} matrix is {n_rows} x {n_rows}, expected "
                                     f"{self.dim} x {self.dim}")
            # entries parsed one by one: never hand strings to sympy.Matrix (it sympifies them)
            rows = [[self.expr(v, f"{what} entry") for v in row] for row in raw]
            return Bivector.from_matrix(rows, self.coords)
        d = self._mapping(obj, what, MultivectorError)
        if not d:
            return Bivector(self.coords, sp.zeros(self.dim, self.dim))
        M = self.multivector(d, what)
        if M.degree != 2:
            raise MultivectorError(f"{what} must have keys (i, j); got keys of length {M.degree}")
        return M.to_bivector()

    def one_form(self, obj: object, what: str = "one_form") -> sp.Matrix:
        """Column vector ``(alpha_1, .., alpha_n)`` from ``{(i,): alpha_i}``."""
        d = self._mapping(obj, what, DiferentialFormError)
        vec = sp.zeros(self.dim, 1)
        seen = set()
        for key, value in d.items():
            idx = self._key(key, DiferentialFormError, what)
            if len(idx) != 1:
                raise DiferentialFormError(f"invalid key {key} in {what}: a 1-form has keys (i,)")
            if idx in seen:
                raise DiferentialFormError(f"component {key} of {what} given twice")
            seen.add(idx)
            vec[idx[0] - 1] = self.expr(value, f"{what} component {key}")
        return vec

    def vector_field(self, obj: object, what: str = "vector_field"):
        """A degree-1 :class:`~poissonkit.structure.schouten.Multivector` from ``{(i,): X^i}``."""
        from poissonkit.structure.schouten import Multivector

        col = self.one_form(obj, what) if isinstance(obj, Mapping) else None
        if col is None:
            raise MultivectorError(f"{what} must be a dict {{(i,): expression}}")
        return Multivector(1, self.coords, {(i,): col[i] for i in range(self.dim)})

    def gradient(self, f: sp.Expr) -> sp.Matrix:
        """Column vector ``df``."""
        return sp.Matrix([sp.diff(f, x) for x in self.coords])


# ---------------------------------------------------------------------- outputs
def is_zero(e: sp.Expr) -> bool:
    """Exact zero test (poissonkit's radical-aware test, simplify as a last resort)."""
    from poissonkit.structure.jacobi import is_zero_expression

    e = sp.sympify(e)
    if sp.expand(e) == 0:
        return True
    if e.is_rational_function():
        # exact and cheaper than the general test: the numerator over a common denominator
        return sp.expand(sp.together(e).as_numer_denom()[0]) == 0
    return bool(is_zero_expression(e))


def tidy(e: sp.Expr) -> sp.Expr:
    """A short, equivalent form of ``e`` for output (no heavy simplification of big terms)."""
    e = sp.sympify(e)
    if e.is_number:
        return e
    if e.is_rational_function():
        # the shorter of the expanded sum and the cancelled fraction
        return min(sp.expand(e), sp.factor_terms(sp.cancel(e)), key=sp.count_ops)
    if sp.count_ops(e) <= 150:
        return sp.simplify(e)
    return sp.expand(e)


def one_based(key: Key) -> Key:
    return tuple(i + 1 for i in key)


def render(entries: Mapping[Key, sp.Expr], latex: bool):
    """PoissonGeometry's output: ``{key: "expr"}`` or ``sympy.latex`` of ``{key: expr}``."""
    tidy_entries = {k: tidy(v) for k, v in entries.items()}
    if latex:
        return sp.latex(tidy_entries)
    return {k: str(v) for k, v in tidy_entries.items()}


_KEY_TEXT = re.compile(r"\s*[\(\[]?\s*(\d+(?:\s*,\s*\d+)*)\s*,?\s*[\)\]]?\s*")


def _key_from_text(key: object) -> object:
    """``"1,2"``, ``"(1, 2)"`` or ``"[1, 2]"`` (JSON object keys) as ``(1, 2)``; others unchanged."""
    if not isinstance(key, str):
        return key
    m = _KEY_TEXT.fullmatch(key)
    if m is None:
        raise MultivectorError(f"invalid key {key!r}: expected indices like '1,2' or '(1, 2)'")
    return tuple(int(k) for k in m.group(1).split(","))


def read_bivector(components: Mapping, dim: int | None = None, variable: str = "x"):
    """A :class:`~poissonkit.structure.Bivector` from a PoissonGeometry-format dict.

    Parameters
    ----------
    components
        ``{(i, j): "expr"}`` with 1-based indices; keys may also be strings such as ``"1,2"`` or
        ``"(1, 2)"`` (what a JSON file can hold). Values are parsed with the allow-list parser.
    dim
        Dimension; default: the largest index that occurs.
    variable
        Coordinate prefix (coordinates ``{variable}1 .. {variable}n``).

    Examples
    --------
    >>> P = read_bivector({"1,2": "x3", "(1, 3)": "-x2", "[2, 3]": "x1"})
    >>> P.dim, P.names
    (3, ('x1', 'x2', 'x3'))
    """
    if not isinstance(components, Mapping):
        raise MultivectorError(f"expected a dict of index pairs to expressions, got "
                               f"{type(components).__name__}")
    parsed = {_key_from_text(k): v for k, v in components.items()}
    if dim is None:
        indices = [i for k in parsed for i in (k if isinstance(k, tuple) else (k,))
                   if isinstance(i, int)]
        dim = max(indices, default=2)
    return Reader(validate_dimension(dim), variable).bivector(parsed)
