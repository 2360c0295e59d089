"""Sparse multivector fields and the Schouten–Nijenhuis bracket.

Sign conventions (stated once in :mod:`poissonkit.conventions`, survey eq. (4)):

* for bivectors ``[A, B]^{ijk} = -sum_m (B^{mk} d_m A^{ij} + A^{mk} d_m B^{ij}) + cyclic(i, j, k)``,
  so ``[P, P]^{ijk} = 2 Jac^{ijk}``;
* for vector fields ``[X, Y]`` is the Lie bracket ``X(Y) - Y(X)``;
* ``[P, X] = -L_X P`` and ``[P, f] = P df = X_f`` (our Hamiltonian vector field).

All of these come from one formula. Write a ``k``-vector as a polynomial in odd variables
``xi_1 .. xi_n``, ``A = sum_{i_1 < .. < i_k} A^{i_1..i_k} xi_{i_1} .. xi_{i_k}``, and use right
derivatives in ``xi``::

    [A, B] = sum_m (A <d/dxi_m) (d_m B) - (-1)^{(a-1)(b-1)} (B <d/dxi_m) (d_m A)

This is the standard graded (super) Schouten bracket; the tests pin it against the survey's
formula, the oracle of docs/conventions.md and the Lie derivative.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from itertools import combinations

import sympy as sp

from poissonkit.errors import DimensionError, InputError
from poissonkit.structure._expr import as_expr
from poissonkit.structure.bivector import Bivector, _as_symbols

Key = tuple[int, ...]


def _expr(value) -> sp.Expr:
    """A multivector component (strings refused: parse them with parse_expression)."""
    return as_expr(value, "multivector component")


def _sort_sign(idx: Sequence[int]) -> tuple[int, Key] | None:
    """Sign of the permutation sorting ``idx`` and the sorted tuple; ``None`` if an index repeats."""
    if len(set(idx)) != len(idx):
        return None
    inversions = sum(1 for a, b in combinations(idx, 2) if a > b)
    return (-1 if inversions % 2 else 1), tuple(sorted(idx))


def _merge(J: Key, K: Key) -> tuple[int, Key] | None:
    """``xi_J xi_K = sign * xi_sorted``; ``None`` when the two share an index."""
    return _sort_sign(J + K)


@dataclass(frozen=True)
class Multivector:
    """A sparse multivector field of fixed degree on named coordinates.

    Parameters
    ----------
    degree
        ``0`` (function), ``1`` (vector field), ``2`` (bivector), ...
    coords
        The coordinate symbols ``x_1 .. x_n``.
    components
        ``{sorted 0-based index tuple: expression}``; unsorted keys are accepted and sorted with
        the antisymmetric sign, zero entries dropped. A function has the single key ``()``.

    Examples
    --------
    >>> import sympy as sp
    >>> x = sp.symbols("x1:4")
    >>> Q = Multivector(2, x, {(1, 0): x[2]})
    >>> Q.component(0, 1), Q.component(1, 0)
    (-x3, x3)
    """

    degree: int
    coords: tuple[sp.Symbol, ...]
    components: Mapping[Key, sp.Expr] = field(default_factory=dict)

    def __post_init__(self) -> None:
        coords = _as_symbols(self.coords)
        object.__setattr__(self, "coords", coords)
        if not isinstance(self.degree, int) or self.degree < 0:
            raise InputError(f"multivector degree must be a non-negative int, got {self.degree!r}")
        n = len(coords)
        if self.degree > n and any(_expr(v) != 0 for v in dict(self.components).values()):
            # a k-vector with k > n is identically zero; only the empty one is allowed
            raise DimensionError(f"degree {self.degree} exceeds the dimension {n}")
        clean: dict[Key, sp.Expr] = {}
        for key, value in dict(self.components).items():
            try:
                idx = tuple(int(k) for k in key)
            except (TypeError, ValueError):
                raise InputError(f"multivector key {key!r} is not a tuple of indices") from None
            if len(idx) != self.degree:
                raise DimensionError(f"key {key!r} has {len(idx)} indices, degree is {self.degree}")
            if any(not 0 <= i < n for i in idx):
                raise DimensionError(f"index in {key!r} out of range 0..{n - 1}")
            sorted_ = _sort_sign(idx)
            if sorted_ is None:
                raise InputError(f"multivector key {key!r} repeats an index")
            sign, skey = sorted_
            if skey in clean:
                raise InputError(f"multivector component {skey} given twice")
            expr = _expr(value)
            if expr != 0:
                clean[skey] = sign * expr
        object.__setattr__(self, "components", clean)

    # ------------------------------------------------------------------ constructors
    @classmethod
    def function(cls, f, coords: Sequence[sp.Symbol | str]) -> Multivector:
        """A function as a 0-vector."""
        return cls(0, tuple(coords), {(): _expr(f)})

    @classmethod
    def vector_field(cls, components: Sequence | Mapping[int, object],
                     coords: Sequence[sp.Symbol | str]) -> Multivector:
        """A vector field from its list of components ``X^i`` (or ``{i: X^i}``, 0-based)."""
        if isinstance(components, Mapping):
            items = components.items()
        else:
            comps = list(components)
            if len(comps) != len(coords):
                raise DimensionError(f"vector field has {len(comps)} components for "
                                     f"{len(coords)} coordinates")
            items = enumerate(comps)
        return cls(1, tuple(coords), {(int(i),): v for i, v in items})

    @classmethod
    def from_bivector(cls, P: Bivector) -> Multivector:
        """The bivector ``P`` as a sparse 2-vector (upper triangle of its matrix)."""
        n = P.dim
        return cls(2, P.coords, {(i, j): P.matrix[i, j] for i in range(n) for j in range(i + 1, n)
                                 if P.matrix[i, j] != 0})

    @classmethod
    def coerce(cls, obj, coords: Sequence[sp.Symbol] | None = None) -> Multivector:
        """Accept a Multivector, a Bivector, or (with ``coords``) a function / component list."""
        if isinstance(obj, Multivector):
            return obj
        if isinstance(obj, Bivector):
            return cls.from_bivector(obj)
        if coords is None:
            raise InputError(f"cannot read {type(obj).__name__} as a multivector without coordinates")
        if isinstance(obj, (list, tuple)):
            return cls.vector_field(list(obj), coords)
        if isinstance(obj, sp.MatrixBase):
            if 1 not in obj.shape:
                raise InputError(f"a {obj.shape} matrix is not a vector field; use a Bivector")
            return cls.vector_field(list(obj), coords)
        return cls.function(obj, coords)

    # ------------------------------------------------------------------ queries
    @property
    def dim(self) -> int:
        """Dimension of the manifold."""
        return len(self.coords)

    def is_zero(self) -> bool:
        """True if every component expands to zero."""
        return all(sp.expand(v) == 0 for v in self.components.values())

    def component(self, *idx: int) -> sp.Expr:
        """Component ``A^{i_1 .. i_k}`` for any index order (antisymmetric sign; 0 if repeated)."""
        if len(idx) == 1 and isinstance(idx[0], (tuple, list)):
            idx = tuple(idx[0])
        if len(idx) != self.degree:
            raise DimensionError(f"{len(idx)} indices given for a {self.degree}-vector")
        if any(not 0 <= int(i) < self.dim for i in idx):
            raise DimensionError(f"index in {idx} out of range 0..{self.dim - 1}")
        sorted_ = _sort_sign(tuple(int(i) for i in idx))
        if sorted_ is None:
            return sp.Integer(0)
        sign, key = sorted_
        return sign * self.components.get(key, sp.Integer(0))

    def subs(self, *args, **kwargs) -> Multivector:
        """Substitute into every component; returns a new multivector."""
        return Multivector(self.degree, self.coords,
                           {k: v.subs(*args, **kwargs) for k, v in self.components.items()})

    def expand(self) -> Multivector:
        """Expand every component (drops the ones that cancel)."""
        return Multivector(self.degree, self.coords,
                           {k: sp.expand(v) for k, v in self.components.items()})

    def to_bivector(self) -> Bivector:
        """A 2-vector as a :class:`Bivector`."""
        if self.degree != 2:
            raise InputError(f"only a 2-vector is a bivector, this has degree {self.degree}")
        mat = sp.zeros(self.dim, self.dim)
        for (i, j), v in self.components.items():
            mat[i, j], mat[j, i] = v, -v
        return Bivector(self.coords, sp.ImmutableMatrix(mat))

    def __add__(self, other: Multivector) -> Multivector:
        if not isinstance(other, Multivector):
            return NotImplemented
        _check_same(self, other, same_degree=True)
        out = dict(self.components)
        for k, v in other.components.items():
            out[k] = out.get(k, 0) + v
        return Multivector(self.degree, self.coords, out)

    def __neg__(self) -> Multivector:
        return Multivector(self.degree, self.coords, {k: -v for k, v in self.components.items()})

    def __sub__(self, other: Multivector) -> Multivector:
        return self + (-other)

    def __repr__(self) -> str:
        return (f"Multivector(degree={self.degree}, coords={tuple(map(str, self.coords))}, "
                f"components={dict(self.components)})")


def _check_same(A: Multivector, B: Multivector, same_degree: bool = False) -> None:
    if A.coords != B.coords:
        raise DimensionError(f"multivectors live on different coordinates: "
                             f"{tuple(map(str, A.coords))} vs {tuple(map(str, B.coords))}")
    if same_degree and A.degree != B.degree:
        raise DimensionError(f"degrees differ: {A.degree} vs {B.degree}")


def _right_derivatives(A: Multivector) -> dict[int, dict[Key, sp.Expr]]:
    """``m -> A <d/dxi_m`` as sparse dicts (degree ``a - 1``)."""
    out: dict[int, dict[Key, sp.Expr]] = {}
    a = A.degree
    for key, v in A.components.items():
        for p, m in enumerate(key):
            # move xi_m to the right end: it passes a - 1 - p odd factors
            sign = -1 if (a - 1 - p) % 2 else 1
            rest = key[:p] + key[p + 1:]
            d = out.setdefault(m, {})
            d[rest] = d.get(rest, 0) + sign * v
    return out


def _coordinate_derivatives(A: Multivector) -> dict[int, dict[Key, sp.Expr]]:
    """``m -> d_m A`` as sparse dicts; only coordinates an entry depends on are differentiated."""
    out: dict[int, dict[Key, sp.Expr]] = {}
    pos = {c: i for i, c in enumerate(A.coords)}
    for key, v in A.components.items():
        for s in v.free_symbols:
            m = pos.get(s)
            if m is None:
                continue
            dv = sp.diff(v, s)
            if dv != 0:
                out.setdefault(m, {})[key] = dv
    return out


def _accumulate(target: dict[Key, sp.Expr], left: Mapping[Key, sp.Expr],
                right: Mapping[Key, sp.Expr], factor: int) -> None:
    """``target += factor * left * right`` in the odd-variable algebra."""
    for J, u in left.items():
        for K, w in right.items():
            merged = _merge(J, K)
            if merged is None:
                continue
            sign, key = merged
            target[key] = target.get(key, 0) + factor * sign * u * w


def schouten_bracket(A, B, coords: Sequence[sp.Symbol] | None = None) -> Multivector:
    """Schouten–Nijenhuis bracket ``[A, B]`` of two multivector fields.

    Parameters
    ----------
    A, B
        :class:`Multivector` or :class:`~poissonkit.structure.Bivector` (functions / vector fields
        may be given as expressions / component lists when ``coords`` is given or the other
        argument carries coordinates).
    coords
        Coordinates for arguments that do not carry their own.

    Returns
    -------
    Multivector
        Of degree ``deg A + deg B - 1``, components expanded. Sign conventions: module docstring
        and :mod:`poissonkit.conventions` (``[P, P] = 2 Jac``, ``[P, X] = -L_X P``,
        ``[X, Y]`` = Lie bracket).

    Examples
    --------
    >>> from poissonkit.structure import so3
    >>> schouten_bracket(so3(), so3()).is_zero()
    True
    """
    if coords is None:
        for obj in (A, B):
            if isinstance(obj, (Multivector, Bivector)):
                coords = obj.coords
                break
    A = Multivector.coerce(A, coords)
    B = Multivector.coerce(B, coords)
    _check_same(A, B)
    a, b = A.degree, B.degree
    if a == 0 and b == 0:
        return Multivector(0, A.coords, {})
    degree = a + b - 1
    if degree > A.dim:
        return Multivector(degree, A.coords, {})
    out: dict[Key, sp.Expr] = {}
    dA_xi, dB_xi = _right_derivatives(A), _right_derivatives(B)
    dA_x, dB_x = _coordinate_derivatives(A), _coordinate_derivatives(B)
    sign = -1 if ((a - 1) * (b - 1)) % 2 else 1
    for m, left in dA_xi.items():
        if m in dB_x:
            _accumulate(out, left, dB_x[m], 1)
    for m, left in dB_xi.items():
        if m in dA_x:
            _accumulate(out, left, dA_x[m], -sign)
    return Multivector(degree, A.coords, {k: sp.expand(v) for k, v in out.items()})


def lie_derivative(X, A, coords: Sequence[sp.Symbol] | None = None) -> Multivector:
    """Lie derivative ``L_X A = [X, A]`` of a multivector along a vector field."""
    return schouten_bracket(X, A, coords)


def jacobiator(P: Bivector | Multivector) -> Multivector:
    """``Jac^{ijk} = {x_i, {x_j, x_k}} + cyclic`` for ``i < j < k`` (so ``[P, P] = 2 Jac``).

    Computed sparsely: only triples that some non-constant entry can reach are formed, so a
    direct sum's Jacobiator is block-local automatically. Components are expanded but not
    otherwise simplified; use :func:`poissonkit.structure.jacobi.check_jacobi` for a zero test
    that understands square roots and constraints.
    """
    from poissonkit.structure.jacobi import jacobiator_terms

    if isinstance(P, Multivector):
        P = P.to_bivector()
    comps = {key: sp.expand(expr) for key, expr in jacobiator_terms(P).items()}
    return Multivector(3, P.coords, comps)


def lichnerowicz(P: Bivector, A, coords: Sequence[sp.Symbol] | None = None) -> Multivector:
    """Lichnerowicz–Poisson coboundary ``d_P A = [P, A]``.

    ``A`` may be a function (expression), a vector field (component list or Multivector) or a
    multivector / bivector. For a function ``d_P f = P df = X_f``; ``d_P^2 = 0`` when ``P`` is
    Poisson.
    """
    return schouten_bracket(P, A, coords or P.coords)


def is_poisson_vector_field(P: Bivector, X) -> bool:
    """True if ``L_X P = 0``, i.e. ``[P, X] = 0`` (exact; square roots handled as in
    :func:`~poissonkit.structure.jacobi.is_zero_expression`)."""
    from poissonkit.structure.jacobi import is_zero_expression

    X = Multivector.coerce(X, P.coords)
    if X.degree != 1:
        raise InputError(f"expected a vector field, got a {X.degree}-vector")
    return all(is_zero_expression(v) for v in schouten_bracket(P, X).components.values())


def are_compatible(P: Bivector, Q: Bivector) -> bool:
    """True if ``[P, Q] = 0``, i.e. every ``P + t Q`` is Poisson when ``P``, ``Q`` are.

    Uses the same radical-aware zero test as :func:`~poissonkit.structure.jacobi.check_jacobi`.
    """
    from poissonkit.structure.jacobi import is_zero_expression

    if P.coords != Q.coords:
        raise DimensionError("are_compatible: bivectors on different coordinates")
    S = schouten_bracket(P, Q)
    return all(is_zero_expression(v) for v in S.components.values())


def wedge(A: Multivector, B: Multivector) -> Multivector:
    """Exterior product ``A ^ B`` of two multivectors."""
    _check_same(A, B)
    degree = A.degree + B.degree
    if degree > A.dim:
        return Multivector(degree, A.coords, {})
    out: dict[Key, sp.Expr] = {}
    _accumulate(out, A.components, B.components, 1)
    return Multivector(degree, A.coords, {k: sp.expand(v) for k, v in out.items()})


def multivector_from_dict(components: Mapping[Iterable[int], object],
                          coords: Sequence[sp.Symbol | str], one_based: bool = True) -> Multivector:
    """Build from a PoissonGeometry-style dict ``{(i, j, ...): "expr"}`` (1-based by default).

    Strings are parsed with the allow-list parser; keys must all have the same length.
    """
    from poissonkit.structure.parsing import parse_expression

    syms = _as_symbols(coords)
    off = 1 if one_based else 0
    lengths = set()
    comps: dict[Key, sp.Expr] = {}
    for key, value in components.items():
        if isinstance(key, int):
            key = (key,)
        try:
            idx = tuple(int(k) - off for k in key)
        except (TypeError, ValueError):
            raise InputError(f"multivector key {key!r} is not a tuple of indices") from None
        if one_based and any(k < 0 for k in idx):
            raise InputError(f"index 0 or negative in {key!r}; indices are 1-based")
        lengths.add(len(idx))
        expr = parse_expression(value, syms) if isinstance(value, str) else _expr(value)
        comps[idx] = expr
    if len(lengths) > 1:
        raise InputError(f"keys of different lengths: {sorted(lengths)}")
    degree = lengths.pop() if lengths else 0
    return Multivector(degree, syms, comps)


__all__ = [
    "Multivector", "are_compatible", "is_poisson_vector_field", "jacobiator", "lichnerowicz",
    "lie_derivative", "multivector_from_dict", "schouten_bracket", "wedge",
]
