"""The classical Lie algebras by name, and the Lie–Poisson brackets on their duals.

``lie_algebra("so(5)")`` returns a :class:`LieAlgebra`: a stated basis ``E_a`` of matrices,
coordinates ``x_a = <mu, E_a>`` on the dual, the structure constants computed from matrix
commutators ``[E_a, E_b] = sum_c C[a][b][c] E_c``, the Lie–Poisson bivector
``{x_a, x_b} = sum_c C[a][b][c] x_c`` and the standard invariants (traces of powers, the
Pfaffian). Bases, coordinate names and the pairing are stated in :mod:`poissonkit.conventions`
(section "Classical Lie algebras") and in ``docs/guide/classical-algebras.md``.

The structure constants are never typed in: each commutator is computed in the defining matrix
representation and decomposed in the basis, and the decomposition is checked to reproduce the
commutator exactly, so closure of the basis is verified on every construction.
"""

from __future__ import annotations

import re
from collections import defaultdict
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from fractions import Fraction
from functools import lru_cache

import sympy as sp
from sympy.polys.matrices import DomainMatrix

from poissonkit.errors import InputError, PoissonkitError, UnknownNameError
from poissonkit.structure.bivector import Bivector, _as_symbols
from poissonkit.structure.invariants import euclid_invariants, pfaffian_invariant, traces_invariants

__all__ = ["LIE_ALGEBRA_NAMES", "LieAlgebra", "lie_algebra", "pfaffian"]

#: The accepted names, with the range of the size argument.
LIE_ALGEBRA_NAMES: tuple[str, ...] = (
    "gl(n) n>=1", "sl(n) n>=2", "so(n) n>=2", "so(p,q) p+q>=2", "sp(2n) n>=1", "u(n) n>=1",
    "su(n) n>=2", "e(n) n>=2", "se(n) n>=2", "heisenberg(n) n>=1",
)

# a typo such as gl(100) would otherwise build 10^4 x 10^4 brackets
_MAX_DIM = 400

_AXES = ("x", "y", "z")

# sparse real matrix: {(row, col): value}
_Sparse = dict[tuple[int, int], Fraction]


@dataclass(frozen=True)
class LieAlgebra:
    """A classical Lie algebra ``g`` with a stated basis and the Lie–Poisson bracket on ``g*``.

    Build one with :func:`lie_algebra`. Conventions: :mod:`poissonkit.conventions`.

    Attributes
    ----------
    name
        Canonical name, e.g. ``"so(5)"``, ``"so(3,1)"``, ``"sp(4)"``.
    basis
        The basis ``E_a`` of ``g`` as matrices of the defining representation (complex for
        ``u(n)``, ``su(n)``).
    coords
        Coordinates on ``g*``: ``x_a = <mu, E_a>``, one per basis element.
    bivector
        The Lie–Poisson bivector ``{x_a, x_b} = sum_c C[a][b][c] x_c``.
    matrix
        The matrix ``X`` representing ``mu`` through the pairing
        ``<mu, Y> = kappa * Re tr(X^H Y)`` (``X`` in ``g``; entries are the coordinates, see the
        conventions), or ``None`` where ``g`` has no invariant trace form (``e(n)``, ``se(n)``,
        ``heisenberg(n)``).
    pairing
        The pairing in words.
    """

    name: str
    basis: tuple[sp.ImmutableMatrix, ...]
    coords: tuple[sp.Symbol, ...]
    bivector: Bivector
    matrix: sp.ImmutableMatrix | None
    pairing: str
    _brackets: tuple[tuple[int, int, tuple[tuple[int, Fraction], ...]], ...]
    _invariants: Callable[[LieAlgebra], dict[str, sp.Expr]]

    @property
    def dim(self) -> int:
        """Dimension of ``g``."""
        return len(self.basis)

    @property
    def structure_constants(self) -> tuple[tuple[tuple[sp.Rational, ...], ...], ...]:
        """Dense ``C[a][b][c]`` with ``[E_a, E_b] = sum_c C[a][b][c] E_c``.

        ``lie_poisson(alg.structure_constants, alg.coords)`` equals ``alg.bivector``.
        """
        n = self.dim
        C = [[[sp.Integer(0)] * n for _ in range(n)] for _ in range(n)]
        for a, b, terms in self._brackets:
            for c, v in terms:
                C[a][b][c] = sp.Rational(v.numerator, v.denominator)
                C[b][a][c] = -C[a][b][c]
        return tuple(tuple(tuple(r) for r in m) for m in C)

    def invariants(self) -> dict[str, sp.Expr]:
        """The standard polynomial Casimirs of ``g*``, expanded, by name.

        * ``gl(n)``: ``tr(X^k)``, ``k = 1..n``; ``sl(n)``: ``k = 2..n``.
        * ``so(n)``, ``so(p,q)`` (``n = p + q``): ``tr(X^(2k))``, ``2k < n``, and for even ``n``
          the Pfaffian ``Pf(X eta)`` (degree ``n/2``; ``eta = diag(1_p, -1_q)``, ``= Pf(X)``
          for ``so(n)``).
        * ``sp(2n)``: ``tr(X^(2k))``, ``k = 1..n``.
        * ``u(n)``: ``tr(H^k)``, ``k = 1..n``, with the Hermitian ``H = -i X``; ``su(n)``:
          ``k = 2..n``.
        * ``e(n)``, ``se(n)``: ``|nu|^2`` (``|P|^2``); for ``n = 3`` also ``(nu, m)``
          (``(L, P)``); for ``n >= 4`` also ``D_k``, ``k = 2..floor(n/2)`` (degree ``2k``) and
          for odd ``n`` ``Pf(Y)`` (degree ``(n+1)/2``), the contractions of the ``so(n+1)``
          invariants with ``Y = [[M, nu], [-nu^T, 0]]``
          (:mod:`poissonkit.structure.invariants`): ``floor((n+1)/2)`` in all, the index of
          ``e(n)``.
        * ``heisenberg(n)``: the central coordinate ``z``.

        Together they generate the polynomial Casimirs of the semisimple and reductive cases
        (Chevalley); for ``so(2m)`` ``tr(X^(2m))`` is left out because it is a polynomial in the
        lower traces and the Pfaffian. They are computed in a sparse polynomial ring
        (:mod:`poissonkit.structure.invariants`): ``so(7)``, ``sp(6)``, ``sl(5)`` in well under a
        second.
        """
        return self._invariants(self)

    def __repr__(self) -> str:
        return f"LieAlgebra({self.name!r}, dim={self.dim})"


# ------------------------------------------------------------------ sparse matrix helpers
def _unit(i: int, j: int, v=1) -> _Sparse:
    return {(i, j): Fraction(v)}


def _add(*terms: tuple[object, _Sparse]) -> _Sparse:
    out: dict[tuple[int, int], Fraction] = defaultdict(Fraction)
    for c, m in terms:
        for k, v in m.items():
            out[k] += Fraction(c) * v
    return {k: v for k, v in out.items() if v}


def _mul(A: _Sparse, B: _Sparse) -> _Sparse:
    rows: dict[int, list[tuple[int, Fraction]]] = defaultdict(list)
    for (k, j), v in B.items():
        rows[k].append((j, v))
    out: dict[tuple[int, int], Fraction] = defaultdict(Fraction)
    for (i, k), a in A.items():
        for j, b in rows.get(k, ()):
            out[(i, j)] += a * b
    return {k: v for k, v in out.items() if v}


def _realify(re_part: _Sparse, im_part: _Sparse, n: int) -> _Sparse:
    """``A + iS`` as the real ``2n x 2n`` matrix ``[[A, -S], [S, A]]`` (a Lie homomorphism)."""
    out: _Sparse = {}
    for (i, j), v in re_part.items():
        out[(i, j)] = out[(n + i, n + j)] = v
    for (i, j), v in im_part.items():
        out[(i, n + j)] = -v
        out[(n + i, j)] = v
    return out


# ------------------------------------------------------------------ the construction
@dataclass(frozen=True)
class _Spec:
    """A basis in the defining representation, before the brackets are computed."""

    name: str
    size: int                         # matrices are size x size (complex: before realifying)
    names: tuple[str, ...]
    real: tuple[_Sparse, ...]         # real parts
    imag: tuple[_Sparse, ...] | None  # imaginary parts (u, su) or None
    kappa: Fraction | None            # pairing factor; None: no trace form
    invariants: Callable[[LieAlgebra], dict[str, sp.Expr]]


def _build(spec: _Spec, coords: Sequence[sp.Symbol | str] | None) -> LieAlgebra:
    n = spec.size
    work = list(spec.real) if spec.imag is None else [
        _realify(r, i, n) for r, i in zip(spec.real, spec.imag)]
    dim = len(work)
    if coords is None:
        syms = _as_symbols(spec.names)
    else:
        syms = _as_symbols(coords)
        if len(syms) != dim:
            raise InputError(f"{spec.name} has dimension {dim}; {len(syms)} coordinate names given")
    # Frobenius Gram matrix of the basis (realified, so it is 2 Re tr(E_a^H E_b) for u, su)
    by_entry: dict[tuple[int, int], list[tuple[int, Fraction]]] = defaultdict(list)
    for a, m in enumerate(work):
        for k, v in m.items():
            by_entry[k].append((a, v))
    gram: dict[int, dict[int, Fraction]] = defaultdict(lambda: defaultdict(Fraction))
    for lst in by_entry.values():
        for a, va in lst:
            for b, vb in lst:
                gram[a][b] += va * vb
    G = DomainMatrix({a: {b: sp.QQ(v.numerator, v.denominator) for b, v in r.items() if v}
                      for a, r in gram.items()}, (dim, dim), sp.QQ)
    Ginv = {a: {b: Fraction(int(v.numerator), int(v.denominator)) for b, v in r.items()}
            for a, r in G.inv().to_sdm().items()}

    def decompose(Y: _Sparse) -> dict[int, Fraction]:
        g: dict[int, Fraction] = defaultdict(Fraction)
        for k, v in Y.items():
            for a, va in by_entry.get(k, ()):
                g[a] += va * v
        c: dict[int, Fraction] = defaultdict(Fraction)
        for a, ga in g.items():
            for b, w in Ginv[a].items():
                c[b] += w * ga
        c = {b: v for b, v in c.items() if v}
        if _add(*((v, work[b]) for b, v in c.items())) != Y:  # closure, checked exactly
            raise PoissonkitError(f"{spec.name}: a commutator left the span of the basis "
                                  "(the basis is not closed; please report)")
        return c

    brackets = []
    mat = sp.zeros(dim, dim)
    for a in range(dim):
        for b in range(a + 1, dim):
            Y = _add((1, _mul(work[a], work[b])), (-1, _mul(work[b], work[a])))
            if not Y:
                continue
            c = decompose(Y)
            brackets.append((a, b, tuple(sorted(c.items()))))
            e = sp.Add(*[sp.Rational(v.numerator, v.denominator) * syms[k] for k, v in c.items()])
            mat[a, b], mat[b, a] = e, -e
    basis = tuple(_dense(r, i, n) for r, i in zip(
        spec.real, spec.imag if spec.imag is not None else [None] * dim))
    X = None
    pairing = "x_a = <mu, E_a>; no invariant trace form, no matrix X"
    if spec.kappa is not None:
        # <mu, Y> = kappa Re tr(X^H Y) with X = sum_b c_b E_b: x = kappa * Gram_C c, where the
        # complex Gram is half the realified one
        scale = spec.kappa if spec.imag is None else spec.kappa / 2
        X = sp.zeros(n, n)
        for a in range(dim):
            for b, w in Ginv[a].items():
                X += sp.Rational(w.numerator, w.denominator) / sp.Rational(
                    scale.numerator, scale.denominator) * syms[a] * basis[b]
        X = sp.ImmutableMatrix(X.applyfunc(sp.expand))
        herm = "^H" if spec.imag is not None else "^T"
        k = "" if spec.kappa == 1 else f"{spec.kappa} "
        pairing = f"x_a = <mu, E_a>, <mu, Y> = {k}Re tr(X{herm} Y) with X in g"
    return LieAlgebra(spec.name, basis, syms, Bivector.from_matrix(mat, syms), X, pairing,
                      tuple(brackets), spec.invariants)


def _dense(re_part: _Sparse, im_part: _Sparse | None, n: int) -> sp.ImmutableMatrix:
    M = sp.zeros(n, n)
    for (i, j), v in re_part.items():
        M[i, j] += sp.Rational(v.numerator, v.denominator)
    for (i, j), v in (im_part or {}).items():
        M[i, j] += sp.I * sp.Rational(v.numerator, v.denominator)
    return sp.ImmutableMatrix(M)


def _ij(i: int, j: int, n: int) -> str:
    """Index pair, 1-based, joined (``12``) or for ``n > 9`` separated (``1_12``)."""
    return f"{i + 1}{j + 1}" if n <= 9 else f"{i + 1}_{j + 1}"


# ------------------------------------------------------------------ invariants
def _traces(powers: Sequence[int], label: str = "X",
            of: Callable[[sp.Matrix], sp.Matrix] = lambda X: X):
    return traces_invariants(list(powers), label, of)


def pfaffian(A: sp.Matrix) -> sp.Expr:
    """Pfaffian of an antisymmetric matrix of even size (expansion along the first row).

    ``Pf(A)^2 = det(A)``; ``Pf([[0, a], [-a, 0]]) = a``.
    """
    n = A.rows
    if n % 2:
        return sp.Integer(0)
    if n == 0:
        return sp.Integer(1)
    out = sp.Integer(0)
    for j in range(1, n):
        if A[0, j] == 0:
            continue
        rest = [k for k in range(1, n) if k != j]
        out += (-1) ** (j + 1) * A[0, j] * pfaffian(A.extract(rest, rest))
    return sp.expand(out)


def _so_invariants(n: int, eta: Sequence[int]):
    traces = _traces(range(2, n if n % 2 == 0 else n + 1, 2)) if n > 2 else (lambda alg: {})

    def inv(alg: LieAlgebra) -> dict[str, sp.Expr]:
        out = traces(alg)
        if n % 2 == 0:
            label = "Pf(X)" if all(e == 1 for e in eta) else "Pf(X eta)"
            out[label] = pfaffian_invariant(alg, eta)
        return out
    return inv


def _euclid_invariants(trans: Sequence[int], rot: Sequence[int], n: int, names: tuple[str, str]):
    # rotation coordinate k of so(n) (n >= 4) is m_ij for the k-th pair i < j: M_ij = m_ij
    pairs = [(i, j) for i in range(n) for j in range(i + 1, n)]
    higher = euclid_invariants(list(trans), [(c, i, j, 1) for c, (i, j) in zip(rot, pairs)], n) \
        if n >= 4 else (lambda alg: {})

    def inv(alg: LieAlgebra) -> dict[str, sp.Expr]:
        t = [alg.coords[i] for i in trans]
        a, b = names
        out = {f"|{a}|^2": sp.Add(*[v ** 2 for v in t])}
        if n == 3:
            r = [alg.coords[i] for i in rot]
            out[f"({a}, {b})" if trans[0] == 0 else f"({b}, {a})"] = sp.Add(
                *[u * v for u, v in zip(t, r)])
        out.update(higher(alg))
        return out
    return inv


# ------------------------------------------------------------------ the families
def _gl(n: int) -> _Spec:
    real = tuple(_unit(i, j) for i in range(n) for j in range(n))
    names = tuple(f"x_{_ij(i, j, n)}" for i in range(n) for j in range(n))
    return _Spec(f"gl({n})", n, names, real, None, Fraction(1), _traces(range(1, n + 1)))


def _sl(n: int) -> _Spec:
    real, names = [], []
    for i in range(n):
        for j in range(n):
            if i != j:
                real.append(_unit(i, j))
            elif i < n - 1:
                # E_ii - I/n: the dual of the diagonal entry X_ii on traceless X
                real.append(_add((1, _unit(i, i)), *((Fraction(-1, n), _unit(k, k))
                                                     for k in range(n))))
            else:
                continue
            names.append(f"x_{_ij(i, j, n)}")
    return _Spec(f"sl({n})", n, tuple(names), tuple(real), None, Fraction(1),
                 _traces(range(2, n + 1)))


def _so(p: int, q: int) -> _Spec:
    n = p + q
    eta = [1] * p + [-1] * q
    name = f"so({n})" if q == 0 or p == 0 else f"so({p},{q})"
    if p == 0:
        eta = [1] * n  # so(0, q) = so(q)
    pairs = [(i, j) for i in range(n) for j in range(i + 1, n)]

    def B(i: int, j: int) -> _Sparse:
        # E_ij - eta_i eta_j E_ji: antisymmetric in a definite block, symmetric (a boost) across
        return _add((1, _unit(i, j)), (-eta[i] * eta[j], _unit(j, i)))

    if n == 3 and (q == 0 or p == 0):
        # hat map: J_x = -B_23, J_y = B_13, J_z = -B_12, X = hat(m); equals so3()
        real = (_add((-1, B(1, 2))), B(0, 2), _add((-1, B(0, 1))))
        names = tuple(f"m_{a}" for a in _AXES)
    else:
        real = tuple(B(i, j) for i, j in pairs)
        names = tuple(f"m_{_ij(i, j, n)}" for i, j in pairs)
    return _Spec(name, n, names, real, None, Fraction(1, 2), _so_invariants(n, eta))


def _sp(n2: int) -> _Spec:
    n = n2 // 2
    real, names = [], []
    for i in range(n):
        for j in range(n):
            real.append(_add((1, _unit(i, j)), (-1, _unit(n + j, n + i))))
            names.append(f"a_{_ij(i, j, n)}")
    for blk, (ro, co) in (("b", (0, n)), ("c", (n, 0))):
        for i in range(n):
            for j in range(i, n):
                real.append(_add((1, _unit(ro + i, co + j)), (1, _unit(ro + j, co + i))))
                names.append(f"{blk}_{_ij(i, j, n)}")
    return _Spec(f"sp({n2})", n2, tuple(names), tuple(real), None, Fraction(1, 2),
                 _traces(range(2, n2 + 1, 2)))


def _u(n: int, special: bool) -> _Spec:
    re_parts, im_parts, names = [], [], []
    for i in range(n):
        for j in range(i, n):
            if i == j:
                if special and i == n - 1:
                    continue
                d = _unit(i, i, 2)
                if special:  # 2i (E_ii - I/n): the dual of H_ii on traceless H
                    d = _add((1, d), *((Fraction(-2, n), _unit(k, k)) for k in range(n)))
                re_parts.append({})
                im_parts.append(d)
            else:
                re_parts.append({})
                im_parts.append(_add((1, _unit(i, j)), (1, _unit(j, i))))
            names.append(f"s_{_ij(i, j, n)}")
    for i in range(n):
        for j in range(i + 1, n):
            re_parts.append(_add((1, _unit(j, i)), (-1, _unit(i, j))))
            im_parts.append({})
            names.append(f"a_{_ij(i, j, n)}")
    first = 2 if special else 1
    name = f"su({n})" if special else f"u({n})"
    return _Spec(name, n, tuple(names), tuple(re_parts), tuple(im_parts), Fraction(1, 2),
                 _traces(range(first, n + 1), "H", lambda X: (-sp.I * X)))


def _euclid(n: int, rotations_first: bool) -> _Spec:
    so = _so(n, 0)
    rot = [dict(m) for m in so.real]  # n x n blocks inside (n+1) x (n+1)
    trans = [_unit(i, n) for i in range(n)]
    a, b = ("P", "L") if rotations_first else ("nu", "m")
    tnames = [f"{a}_{_AXES[i]}" if n == 3 else f"{a}_{i + 1}" for i in range(n)]
    rnames = [f"{b}_{s.split('_', 1)[1]}" for s in so.names]
    if rotations_first:
        real, names = rot + trans, rnames + tnames
        ti, ri = range(len(rot), len(rot) + n), range(len(rot))
    else:
        real, names = trans + rot, tnames + rnames
        ti, ri = range(n), range(n, n + len(rot))
    name = f"se({n})" if rotations_first else f"e({n})"
    return _Spec(name, n + 1, tuple(names), tuple(real), None, None,
                 _euclid_invariants(list(ti), list(ri), n, (a, b)))


def _heisenberg(n: int) -> _Spec:
    Q = [_unit(0, 1 + i) for i in range(n)]
    P = [_unit(1 + i, n + 1) for i in range(n)]
    Z = _unit(0, n + 1)
    names = tuple(f"q_{i + 1}" for i in range(n)) + tuple(f"p_{i + 1}" for i in range(n)) + ("z",)

    def inv(alg: LieAlgebra) -> dict[str, sp.Expr]:
        return {"z": alg.coords[-1]}
    return _Spec(f"heisenberg({n})", n + 2, names, tuple(Q + P + [Z]), None, None, inv)


class UnknownAlgebraError(UnknownNameError, InputError):
    """A Lie algebra name that is not one of the accepted ones: an unknown name, and bad
    input (``except InputError`` catches it, as it does every other malformed argument)."""


_NAME = re.compile(r"^\s*([a-z]+)\s*\(\s*(\d+)\s*(?:,\s*(\d+)\s*)?\)\s*$")
_MIN = {"gl": 1, "sl": 2, "so": 2, "sp": 2, "u": 1, "su": 2, "e": 2, "se": 2, "heisenberg": 1}


def _spec(name: str) -> _Spec:
    if not isinstance(name, str):
        raise InputError(f"a Lie algebra name must be a string such as 'so(5)', got "
                         f"{type(name).__name__}")
    m = _NAME.match(name.lower())
    if m is None or m.group(1) not in _MIN or (m.group(3) is not None and m.group(1) != "so"):
        raise UnknownAlgebraError("Lie algebra", name, LIE_ALGEBRA_NAMES)
    fam, k = m.group(1), int(m.group(2))
    size = k + int(m.group(3)) if m.group(3) is not None else k
    if size < _MIN[fam] or (fam == "sp" and k % 2):
        why = "sp(2n) takes the even matrix size 2n" if fam == "sp" and k % 2 else \
            "size out of range"
        raise InputError(f"{name!r}: {why}; accepted: " + ", ".join(LIE_ALGEBRA_NAMES))
    dims = {"gl": k * k, "sl": k * k - 1, "so": size * (size - 1) // 2, "sp": k * (k + 1) // 2,
            "u": k * k, "su": k * k - 1, "e": k * (k + 1) // 2, "se": k * (k + 1) // 2,
            "heisenberg": 2 * k + 1}
    if dims[fam] > _MAX_DIM:
        raise InputError(f"{name!r} has dimension {dims[fam]} > {_MAX_DIM}; build larger algebras "
                         "from structure constants with lie_poisson(C, coords)")
    if fam == "gl":
        return _gl(k)
    if fam == "sl":
        return _sl(k)
    if fam == "so":
        return _so(k, int(m.group(3)) if m.group(3) is not None else 0)
    if fam == "sp":
        return _sp(k)
    if fam in ("u", "su"):
        return _u(k, fam == "su")
    if fam in ("e", "se"):
        return _euclid(k, fam == "se")
    return _heisenberg(k)


@lru_cache(maxsize=32)
def _cached(name: str, coords: tuple[sp.Symbol | str, ...] | None) -> LieAlgebra:
    return _build(_spec(name), coords)


def lie_algebra(name: str, coords: Sequence[sp.Symbol | str] | None = None) -> LieAlgebra:
    """A classical Lie algebra by name, with its basis, coordinates and Lie–Poisson bracket.

    Parameters
    ----------
    name
        One of ``gl(n)``, ``sl(n)``, ``so(n)``, ``so(p,q)``, ``sp(2n)`` (``sp(4)`` is the
        algebra of ``4 x 4`` matrices), ``u(n)``, ``su(n)``, ``e(n)`` (translations first, as
        :func:`~poissonkit.structure.e3`), ``se(n)`` (rotations first, as
        :func:`~poissonkit.structure.se3`), ``heisenberg(n)`` (dimension ``2n + 1``).
    coords
        Coordinate names overriding the default ones (same length as the basis).

    Returns
    -------
    LieAlgebra
        Basis, coordinates, bivector, matrix ``X`` and :meth:`LieAlgebra.invariants`.

    Raises
    ------
    UnknownNameError
        If the name is not one of the accepted ones (they are listed in the message); also an
        :class:`~poissonkit.errors.InputError`.
    InputError
        If the size is out of range (``sl(1)``, ``sp(3)``, ...) or too large.

    Notes
    -----
    Bases, coordinate names and the pairing of each family are listed in
    :mod:`poissonkit.conventions`. ``so(3)``, ``e(3)`` and ``se(3)`` give exactly the bivectors
    of :func:`~poissonkit.structure.so3`, :func:`~poissonkit.structure.e3` and
    :func:`~poissonkit.structure.se3`.

    Examples
    --------
    >>> g = lie_algebra("so(4)")
    >>> g.coords
    (m_12, m_13, m_14, m_23, m_24, m_34)
    >>> g.bivector.bracket(g.coords[0], g.coords[3])
    m_13
    >>> sorted(g.invariants())
    ['Pf(X)', 'tr(X^2)']
    """
    key = None if coords is None else tuple(coords)
    try:
        return _cached(name, key)
    except TypeError:  # unhashable coordinate objects: build uncached
        return _build(_spec(name), coords)
