"""The :class:`Bivector`: an antisymmetric matrix of brackets on named coordinates.

Conventions (sign of the bracket and of Hamiltonian vector fields): :mod:`poissonkit.conventions`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import sympy as sp

from poissonkit._display import html_table, latex_aligned, text_block
from poissonkit.errors import DimensionError, InputError, ParseError, UnknownNameError
from poissonkit.structure._expr import as_expr, as_symbols, as_sympy

if TYPE_CHECKING:
    from poissonkit.structure.parsing import ParameterSpec

# Shared with schouten, blocks, poisson_map and checks (one implementation, one error text).
_as_symbols = as_symbols


def _has_radical(*items) -> bool:
    """Whether any expression (or matrix entry) contains a non-integer power."""
    for item in items:
        for e in (item if isinstance(item, sp.MatrixBase) else (item,)):
            for a in sp.preorder_traversal(e):
                if isinstance(a, sp.Pow) and not a.exp.is_Integer:
                    return True
    return False


def _reject_strings(matrix) -> None:
    """Matrices are never built from strings: sympy would ``eval`` them (use from_components)."""
    if isinstance(matrix, str):
        raise ParseError("a bivector matrix cannot be a string; use Bivector.from_components")
    if isinstance(matrix, (list, tuple)):
        for row in matrix:
            _reject_strings(row)
        return
    dtype = getattr(matrix, "dtype", None)
    if dtype is not None and getattr(dtype, "kind", "") in ("U", "S", "O"):
        for entry in getattr(matrix, "flat", ()):
            if isinstance(entry, str):
                raise ParseError("a bivector matrix cannot contain strings; use "
                                 "Bivector.from_components")


@dataclass(frozen=True)
class Bivector:
    """A bivector field ``P`` on ``R^n`` with named coordinates.

    ``matrix[i, j] = {x_i, x_j}`` (see :mod:`poissonkit.conventions`). Instances are immutable;
    operations return new objects.

    Parameters
    ----------
    coords
        The coordinate symbols ``x_1 .. x_n`` (names are block-qualified in direct sums,
        e.g. ``top1.nu_x``).
    matrix
        An ``n x n`` antisymmetric sympy matrix whose entries are expressions in ``coords``
        (and possibly parameters / undefined functions).
    blocks
        Optional ``(name, start, stop)`` triples recording the direct-sum block structure,
        used to make Jacobi checks block-local.

    Examples
    --------
    >>> from poissonkit.structure import Bivector
    >>> P = Bivector.from_components({(1, 2): "x3"}, ["x1", "x2", "x3"])
    >>> P.bracket(P.coords[0], P.coords[1])
    x3
    """

    coords: tuple[sp.Symbol, ...]
    matrix: sp.ImmutableMatrix
    blocks: tuple[tuple[str, int, int], ...] = field(default=())

    def __post_init__(self) -> None:
        if _is_matrix_like(self.coords):  # Bivector(matrix, coords): the order of sympy users
            raise InputError("Bivector takes (coords, matrix): the coordinates first, then the "
                             "matrix; the first argument given is a matrix (swap the two)")
        coords = _as_symbols(self.coords)
        object.__setattr__(self, "coords", coords)
        _reject_strings(self.matrix)
        try:
            mat = sp.ImmutableMatrix(self.matrix)
        except Exception as exc:  # noqa: BLE001 -- sympy raises many types on ragged/odd input
            raise InputError(f"cannot read bivector matrix: {type(exc).__name__}: {exc}") \
                from None
        n = len(coords)
        if mat.shape != (n, n):
            raise DimensionError(f"bivector matrix has shape {mat.shape}, expected ({n}, {n}) "
                                 f"for coordinates {tuple(map(str, coords))}")
        # non-finite entries first: NaN != -NaN would otherwise read as "not antisymmetric"
        for (i, j), e in zip(((i, j) for i in range(n) for j in range(n)), mat):
            if not isinstance(e, sp.Expr):  # a list inside an object array, a boolean, ...
                raise InputError(f"bivector matrix entry ({i},{j}) is not an expression: {e!r}")
            if e.has(sp.nan, sp.oo, -sp.oo, sp.zoo):
                raise InputError(f"bivector matrix entry ({i},{j}) is not finite: {e}")
        for i in range(n):
            if mat[i, i] != 0:
                raise InputError(f"bivector matrix is not antisymmetric: entry ({i},{i}) = {mat[i, i]}")
            for j in range(i + 1, n):
                if sp.expand(mat[i, j] + mat[j, i]) != 0:
                    raise InputError(
                        f"bivector matrix is not antisymmetric: P[{i},{j}] = {mat[i, j]} but "
                        f"P[{j},{i}] = {mat[j, i]}")
        # A symbol named like a coordinate but not equal to it (other assumptions, e.g. a plain
        # Symbol("x1") against the real coordinate x1) would silently act as a parameter.
        names = {str(c): c for c in coords}
        for s in mat.free_symbols:
            c = names.get(str(s))
            if c is not None and c != s:
                raise InputError(f"symbol {s} in the matrix is not the coordinate {c} (same name, "
                                 "different assumptions); build the entries from the coordinate "
                                 "symbols or pass the matrix's own symbols as coords")
        object.__setattr__(self, "matrix", mat)
        if not self.blocks:
            object.__setattr__(self, "blocks", (("", 0, n),))

    # ------------------------------------------------------------------ constructors
    @classmethod
    def from_matrix(cls, matrix, coords: Sequence[sp.Symbol | str]) -> Bivector:
        """Build from a full antisymmetric matrix (nested lists, numpy array or sympy Matrix)."""
        _reject_strings(matrix)
        try:
            mat = sp.ImmutableMatrix(matrix)
        except Exception as exc:  # noqa: BLE001 -- sympy raises many types on ragged/odd input
            raise InputError(f"cannot read bivector matrix: {type(exc).__name__}: {exc}") \
                from None
        return cls(tuple(_as_symbols(coords)), mat)

    @classmethod
    def from_components(cls, components: Mapping[tuple[int, int], object],
                        coords: Sequence[sp.Symbol | str], *, one_based: bool = True,
                        params: ParameterSpec = None) -> Bivector:
        """Build from upper-triangle components ``{(i, j): P^{ij}}``.

        Parameters
        ----------
        components
            Keys are index pairs (1-based by default, as in PoissonGeometry); values are sympy
            expressions or strings. Strings are parsed with an allow-list of names (the
            coordinates, the declared ``params`` and a fixed set of functions), never with
            ``eval``.
        coords
            Coordinate symbols or names.
        one_based
            Whether the index pairs start at 1.
        params
            Parameters the strings may name: ``["a", "b"]`` (real symbols),
            ``{"b": {"positive": True}}`` or sympy symbols (see
            :func:`poissonkit.structure.parsing.declare_parameters`). A name neither a
            coordinate nor declared is a :class:`~poissonkit.errors.ParseError` listing the
            allowed names.

        Examples
        --------
        >>> P = Bivector.from_components({(1, 2): "-a*x1*x2/b"}, ["x1", "x2"], params=["a", "b"])
        >>> P.matrix[0, 1]
        -a*x1*x2/b
        """
        from poissonkit.structure.parsing import declare_parameters, parse_expression

        syms = _as_symbols(coords)
        declared = declare_parameters(params, reserved=syms)
        n = len(syms)
        mat = sp.zeros(n, n)
        off = 1 if one_based else 0
        for key, value in components.items():
            try:
                i, j = (int(k) - off for k in key)
            except (TypeError, ValueError):
                raise InputError(f"bivector component key {key!r} is not a pair of indices") from None
            if not (0 <= i < n and 0 <= j < n):
                raise DimensionError(f"index pair {key} out of range for dimension {n}")
            if i == j:
                raise InputError(f"index pair {key} repeats an index")
            expr = parse_expression(value, syms, declared) if isinstance(value, str) \
                else as_expr(value, f"component {key!r}")
            if mat[i, j] != 0 or mat[j, i] != 0:
                raise InputError(f"index pair {key} given twice")
            mat[i, j] = expr
            mat[j, i] = -expr
        return cls(syms, sp.ImmutableMatrix(mat))

    # ------------------------------------------------------------------ basics
    @property
    def dim(self) -> int:
        """Dimension ``n`` of the manifold."""
        return len(self.coords)

    @property
    def names(self) -> tuple[str, ...]:
        """Coordinate names."""
        return tuple(str(c) for c in self.coords)

    def index(self, coord: sp.Symbol | str) -> int:
        """Position of a coordinate, by symbol or name."""
        name = str(coord)
        try:
            return self.names.index(name)
        except ValueError:
            raise UnknownNameError("coordinate", name, self.names) from None

    def symbol(self, name: str) -> sp.Symbol:
        """The coordinate symbol called ``name``."""
        return self.coords[self.index(name)]

    def gradient(self, F) -> sp.Matrix:
        """Column vector ``dF/dx``."""
        F = as_expr(F, "function")
        return sp.Matrix([sp.diff(F, x) for x in self.coords])

    def bracket(self, F, G) -> sp.Expr:
        """Poisson bracket ``{F, G} = dF . P . dG``.

        Expanded, except when ``P``, ``F`` or ``G`` contain fractional powers (square roots):
        expanding those costs seconds and gives no canonical form anyway (test zero with
        :func:`poissonkit.structure.jacobi.is_zero_expression`).
        """
        F, G = as_expr(F, "function F"), as_expr(G, "function G")
        dF, dG = self.gradient(F), self.gradient(G)
        value = (dF.T * self.matrix * dG)[0, 0]
        return value if _has_radical(self.matrix, F, G) else sp.expand(value)

    def hamiltonian_vector_field(self, H, multiplier=1) -> sp.Matrix:
        """``X = N P dH`` (column vector), i.e. ``xdot = N {x, H}``.

        Components are expanded unless ``P``, ``H`` or ``N`` contain fractional powers
        (square roots, as in the Chaplygin ball), see :meth:`bracket`.
        """
        H, N = as_expr(H, "Hamiltonian"), as_expr(multiplier, "multiplier")
        X = N * self.matrix * self.gradient(H)
        return X if _has_radical(self.matrix, H, N) else X.applyfunc(sp.expand)

    def equations_of_motion(self, H, multiplier=1) -> dict[sp.Symbol, sp.Expr]:
        """``{x_i: xdot_i}`` with ``xdot = N {x, H}``."""
        X = self.hamiltonian_vector_field(H, multiplier)
        return {x: X[i] for i, x in enumerate(self.coords)}

    def subs(self, *args, **kwargs) -> Bivector:
        """Substitute into every entry (parameters, functions); returns a new bivector."""
        # sympy's subs sympifies strings leniently (eval): convert every argument first
        args = tuple(as_sympy(a, "substitution") for a in args)
        return Bivector(self.coords, self.matrix.subs(*args, **kwargs), self.blocks)

    def __neg__(self) -> Bivector:
        return Bivector(self.coords, -self.matrix, self.blocks)

    def __mul__(self, factor) -> Bivector:
        if isinstance(factor, Bivector):
            return NotImplemented
        return Bivector(self.coords, self.matrix * as_expr(factor, "scalar factor"), ())

    __rmul__ = __mul__

    def __add__(self, other: Bivector) -> Bivector:
        if not isinstance(other, Bivector):
            return NotImplemented
        if other.coords != self.coords:
            raise DimensionError("cannot add bivectors on different coordinates")
        return Bivector(self.coords, self.matrix + other.matrix, ())

    def __sub__(self, other: Bivector) -> Bivector:
        return self + (-other)

    def __repr__(self) -> str:
        return f"Bivector(coords={self.names}, matrix={self.matrix.tolist()})"

    # ------------------------------------------------------------------ display
    def _nonzero(self) -> list[tuple[int, int]]:
        n = self.dim
        return [(i, j) for i in range(n) for j in range(i + 1, n) if self.matrix[i, j] != 0]

    def _title(self) -> str:
        parts = [f"{name}({stop - start})" for name, start, stop in self.blocks if name]
        blocks = f", blocks {' + '.join(parts)}" if len(parts) > 1 else ""
        return f"Bivector on R^{self.dim}{blocks}"

    def __str__(self) -> str:
        """The non-zero brackets of the coordinates, one per line."""
        rows = [(f"{{{self.coords[i]}, {self.coords[j]}}}", str(self.matrix[i, j]))
                for i, j in self._nonzero()]
        return text_block(f"{self._title()}: coordinates {', '.join(self.names)}",
                          rows or [("(all brackets zero)", "")])

    def _repr_pretty_(self, p, cycle: bool) -> None:
        p.text("Bivector(...)" if cycle else str(self))

    def _repr_html_(self) -> str:
        """HTML table of the non-zero brackets (Jupyter)."""
        rows = [(f"{{{self.coords[i]}, {self.coords[j]}}}", str(self.matrix[i, j]))
                for i, j in self._nonzero()]
        return html_table(f"{self._title()}: coordinates {', '.join(self.names)}", rows)

    def _repr_latex_(self) -> str:
        """The non-zero brackets as aligned LaTeX equations (Jupyter, Markdown renderers)."""
        rows = [(f"\\{{{sp.latex(self.coords[i])}, {sp.latex(self.coords[j])}\\}}",
                 sp.latex(self.matrix[i, j])) for i, j in self._nonzero()]
        return latex_aligned(rows or [("P", "0")])


def direct_sum(*parts: tuple[str, Bivector] | Bivector) -> Bivector:
    """Direct sum of bivectors, block-diagonal, coordinates renamed ``block.coord``.

    Parameters
    ----------
    parts
        Either bivectors or ``(name, bivector)`` pairs. Named blocks prefix their coordinate
        names with ``name.``; unnamed ones keep their names (which must then be distinct).

    Examples
    --------
    >>> from poissonkit.structure import canonical, e3, direct_sum
    >>> P = direct_sum(("orbit", canonical(3)), ("top1", e3()), ("top2", e3()))
    >>> P.dim
    18
    """
    coords: list[sp.Symbol] = []
    blocks: list[tuple[str, int, int]] = []
    mats = []
    for k, part in enumerate(parts):
        if isinstance(part, tuple):
            name, biv = part
        else:
            name, biv = "", part
        if not isinstance(biv, Bivector):
            raise InputError(f"direct_sum part {k} is not a Bivector: {biv!r}")
        if name:
            new = [sp.Symbol(f"{name}.{c}", **c.assumptions0) for c in biv.coords]
            mat = biv.matrix.subs(dict(zip(biv.coords, new)), simultaneous=True)
        else:
            new, mat = list(biv.coords), biv.matrix
        start = len(coords)
        coords.extend(new)
        mats.append(mat)
        blocks.append((name or f"block{k}", start, len(coords)))
    if len(set(coords)) != len(coords):
        raise InputError("direct_sum: coordinate names collide; give the blocks names")
    return Bivector(tuple(coords), sp.ImmutableMatrix(sp.diag(*mats)), tuple(blocks))


def _is_matrix_like(value: object) -> bool:
    """A sympy matrix, or a sequence of rows (what a matrix argument looks like)."""
    if isinstance(value, sp.MatrixBase) or getattr(value, "ndim", 1) == 2:
        return True
    if isinstance(value, (list, tuple)) and value:
        return all(isinstance(row, (list, tuple, sp.MatrixBase)) for row in value)
    return False
