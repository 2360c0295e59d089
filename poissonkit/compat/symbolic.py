"""``PoissonGeometry``: a drop-in for the class of the PyPI package ``poissongeometry`` (1.1.1).

Same constructor, method names, signatures and formats (dicts of 1-based index tuples to
expression strings), computed on poissonkit's core (:mod:`poissonkit.structure`). Differences,
all deliberate (docs/compat.md):

* **Sign.** As in PoissonGeometry, ``hamiltonian_vf`` and ``sharp_morphism`` use
  ``P#(alpha) = -P alpha``, so ``X_h = {h, .} = -P dh``. This is the *opposite* of poissonkit's
  ``X_H = P dH = {., H}`` (:mod:`poissonkit.conventions`) and lives only in :mod:`poissonkit.compat`.
  Brackets agree: ``{f, g} = df . P . dg`` in both.
* **Curl / modular vector field.** PoissonGeometry differentiates the density by the wrong
  coordinate; here the curl is ``D(A) = D_Omega(A) + i_{d log f} A`` (see :func:`curl_operator`).
* **Safety.** Strings are parsed with an allow-list parser, never ``sympify``; bad input raises
  typed errors (subclasses of :class:`poissonkit.errors.InputError`).
* **Consistent return types.** ``poisson_bracket`` always returns a string (PoissonGeometry
  sometimes returns a sympy ``0``), ``one_forms_bracket`` always string values,
  ``bivector_to_matrix(..., latex=True)`` the ``n x n`` matrix (not a padded ``(n+1) x (n+1)``),
  and zero entries of a ``linear_normal_form_R3`` input are ignored instead of raising.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import sympy as sp

from poissonkit.compat import _calculus as calc
from poissonkit.compat._inputs import Reader, is_zero, one_based, render, tidy, validate_dimension
from poissonkit.compat.errors import (CasimirError, FunctionError, MultivectorError, Nonhomogeneous,
                                      Nonlinear)
from poissonkit.errors import DimensionError

Dict = Mapping[tuple[int, ...], object]


def _latex_flag(latex: bool, latex_format: bool | None) -> bool:
    """``latex`` is the 1.1.1 name; ``latex_format`` the name in older PoissonGeometry docs."""
    return bool(latex if latex_format is None else latex_format)


class PoissonGeometry:
    """Symbolic Poisson calculus on ``R^dim`` in PoissonGeometry's formats.

    Parameters
    ----------
    dimension
        ``n >= 2``.
    variable
        Coordinate prefix: coordinates are ``{variable}1 .. {variable}n`` (default ``x``).

    Attributes
    ----------
    dim, variable, coords, coordinates
        As in PoissonGeometry (``coords`` are plain sympy symbols ``x1 .. xn``).

    Notes
    -----
    Inputs: bivectors / multivectors ``{(i, j, ...): "expr"}``, 1-forms ``{(i,): "expr"}``,
    functions ``"expr"``; 1-based indices. Names allowed in expressions: the coordinates, the
    parser's functions (``sin``, ``exp``, ``sqrt``, ...) and free parameter names (``a1``,
    ``L12``); anything else (attributes, dunders, ``__import__(...)``) raises
    :class:`~poissonkit.errors.ParseError`.

    Hamiltonian vector fields follow PoissonGeometry's sign, ``X_h = {h, .} = -P dh`` — the
    opposite of poissonkit's ``P dH`` — see :mod:`poissonkit.conventions`.

    Examples
    --------
    >>> from poissonkit.compat import PoissonGeometry
    >>> pg = PoissonGeometry(3)
    >>> P = {(1, 2): "x3", (1, 3): "-x2", (2, 3): "x1"}
    >>> pg.hamiltonian_vf(P, "x1 + x2 + x3")
    {(1,): 'x2 - x3', (2,): '-x1 + x3', (3,): 'x1 - x2'}
    >>> pg.is_casimir(P, "x1**2 + x2**2 + x3**2")
    True
    """

    def __init__(self, dimension: int, variable: str = "x") -> None:
        self.dim = validate_dimension(dimension)
        self.variable = variable
        self._reader = Reader(self.dim, variable)
        self.coords: tuple[sp.Symbol, ...] = self._reader.coords
        c = self.coords
        self.coordinates = f"({c[0]},...,{c[-1]})" if len(c) >= 4 else f"({c})"

    def __repr__(self) -> str:
        return f"PoissonGeometry({self.dim}, variable={self.variable!r})"

    # ------------------------------------------------------------------ helpers
    def _P(self, bivector: Dict):
        return self._reader.bivector(bivector)

    def _f(self, function: object, what: str = "function") -> sp.Expr:
        return self._reader.expr(function, what)

    def _vector_out(self, column: sp.MatrixBase, latex: bool):
        """All ``n`` components ``{(i,): "expr"}``, zeros included (PoissonGeometry's format)."""
        return render({(i + 1,): column[i] for i in range(self.dim)}, latex)

    # ------------------------------------------------------------------ basic operations
    def bivector_to_matrix(self, bivector: Dict, latex: bool = False, *,
                           latex_format: bool | None = None):
        """Antisymmetric matrix ``[P^{ij}]`` of a bivector.

        Returns
        -------
        sympy.Matrix or str
            ``n x n`` matrix, or its LaTeX when ``latex`` is true.
        """
        M = sp.Matrix(self._P(bivector).matrix)
        return sp.latex(M) if _latex_flag(latex, latex_format) else M

    def sharp_morphism(self, bivector: Dict, one_form: Dict, latex: bool = False, *,
                       latex_format: bool | None = None):
        """``P#(alpha) = i_alpha P``, with PoissonGeometry's sign ``P#(alpha) = -P alpha``.

        Returns
        -------
        dict or str
            ``{(i,): "expr"}`` for every ``i``, or LaTeX.
        """
        alpha = self._reader.one_form(one_form)
        return self._vector_out(calc.sharp(self._P(bivector).matrix, alpha),
                                _latex_flag(latex, latex_format))

    def is_in_kernel(self, bivector: Dict, one_form: Dict) -> bool:
        """True if ``P#(alpha) = 0``."""
        alpha = self._reader.one_form(one_form)
        return all(is_zero(v) for v in self._P(bivector).matrix * alpha)

    def hamiltonian_vf(self, bivector: Dict, ham_function: object, latex: bool = False, *,
                       latex_format: bool | None = None):
        """Hamiltonian vector field in PoissonGeometry's sign: ``X_h = P#(dh) = -P dh = {h, .}``.

        This is minus poissonkit's :meth:`poissonkit.structure.Bivector.hamiltonian_vector_field`.

        Returns
        -------
        dict or str
            ``{(i,): "expr"}`` for every ``i``, or LaTeX.
        """
        P = self._P(bivector)
        X = -P.hamiltonian_vector_field(self._f(ham_function, "ham_function"))
        return self._vector_out(X, _latex_flag(latex, latex_format))

    def is_casimir(self, bivector: Dict, function: object) -> bool:
        """True if ``P dK = 0``."""
        P, K = self._P(bivector), self._f(function)
        try:
            from poissonkit.structure.casimirs import is_casimir as core_is_casimir
        except ImportError:  # the core module is optional at import time; same test inline
            return all(is_zero(v) for v in P.matrix * self._reader.gradient(K))
        return bool(core_is_casimir(P, K))

    def poisson_bracket(self, bivector: Dict, function_1: object, function_2: object,
                        latex: bool = False, *, latex_format: bool | None = None) -> str:
        """``{f, g} = df . P . dg`` (same sign in PoissonGeometry and poissonkit).

        Returns
        -------
        str
            The bracket (LaTeX when ``latex``); always a string, also when it is ``0``.
        """
        P = self._P(bivector)
        value = tidy(P.bracket(self._f(function_1, "function_1"), self._f(function_2, "function_2")))
        return sp.latex(value) if _latex_flag(latex, latex_format) else str(value)

    # ------------------------------------------------------------------ divergence
    def curl_operator(self, multivector: Dict, function: object, latex: bool = False, *,
                      latex_format: bool | None = None):
        """Divergence of a multivector relative to the volume form ``f dx1^..^dxn``.

        ``D_{f Omega}(A) = D_Omega(A) + i_{d log f} A``: for ``A = sum A^J d_J``, the component of
        ``d_{J without i}`` receives ``(-1)^p (d_i A^J + A^J d_i f / f)`` with ``p`` the position of
        ``i`` in ``J``. PoissonGeometry 1.1.1 uses ``d_{x_{p+1}} f`` here instead of ``d_i f``,
        which is wrong whenever ``f`` is not symmetric under those coordinates (docs/compat.md).

        Parameters
        ----------
        multivector
            ``{(i1, .., ik): "expr"}``, non-empty.
        function
            Nowhere-vanishing density (string or number).

        Returns
        -------
        dict or str
            ``{J: "expr"}`` for a ``k``-vector with ``k >= 2``; a string for a vector field.
        """
        f = self._f(function)
        if is_zero(f):
            raise FunctionError(f"function {function} == 0")
        if isinstance(multivector, str):
            raise MultivectorError(f"multivector {multivector!r} is not a dict")
        A = self._reader.multivector(multivector)
        out = calc.curl(dict(A.components), self.coords, f)
        flag = _latex_flag(latex, latex_format)
        if A.degree == 1:
            value = tidy(out.get((), 0))
            return sp.latex(value) if flag else str(value)
        return render({one_based(k): v for k, v in out.items()}, flag)

    def modular_vf(self, bivector: Dict, function: object, latex: bool = False, *,
                   latex_format: bool | None = None):
        """Modular vector field of ``P`` relative to ``f dx1^..^dxn``: ``Z(g) = div_{f Omega}(X_g)``.

        With PoissonGeometry's ``X_g = -P dg``: ``Z^k = sum_i d_i P^{ki} + P^{ki} d_i log f``,
        i.e. the curl of ``-P``; ``Z_{h Omega} = Z_Omega - X_h / h``.
        """
        P = self._P(bivector)
        n = self.dim
        minus_P = {(i + 1, j + 1): -P.matrix[i, j] for i in range(n) for j in range(i + 1, n)
                   if P.matrix[i, j] != 0}
        if not minus_P:
            f = self._f(function)
            if is_zero(f):
                raise FunctionError(f"function {function} == 0")
            return render({}, _latex_flag(latex, latex_format))
        return self.curl_operator(minus_P, function, latex, latex_format=latex_format)

    def is_unimodular_homogeneous(self, bivector: Dict) -> bool:
        """True if a homogeneous polynomial bivector has zero modular vector field (``f = 1``).

        Raises
        ------
        Nonhomogeneous
            If an entry is not a homogeneous polynomial in the coordinates.
        """
        P = self._P(bivector)
        for i in range(self.dim):
            for j in range(i + 1, self.dim):
                e = P.matrix[i, j]
                if e == 0:
                    continue
                order = sp.homogeneous_order(e, *self.coords)
                if order is None or order < 0 or not e.is_polynomial(*self.coords):
                    raise Nonhomogeneous(f"({i + 1}, {j + 1}): {e} is not a homogeneous "
                                         f"polynomial in {self.coordinates}")
        Z = self.modular_vf(bivector, 1)
        return all(is_zero(self._f(v)) for v in Z.values())

    # ------------------------------------------------------------------ forms
    def one_forms_bracket(self, bivector: Dict, one_form_1: Dict, one_form_2: Dict,
                          latex: bool = False, *, latex_format: bool | None = None):
        """Lie bracket of 1-forms ``{a, b}_P = i_{P#a} db - i_{P#b} da + d P(a, b)``.

        ``{df, dg}_P = d{f, g}``. Returns the non-zero components ``{(i,): "expr"}`` (``{}`` if
        all vanish), or LaTeX.
        """
        P = self._P(bivector)
        a = self._reader.one_form(one_form_1, "one_form_1")
        b = self._reader.one_form(one_form_2, "one_form_2")
        v = calc.one_forms_bracket(P.matrix, a, b, self.coords)
        entries = {(i + 1,): v[i] for i in range(self.dim) if not is_zero(v[i])}
        return render(entries, _latex_flag(latex, latex_format))

    def gauge_transformation(self, bivector: Dict, two_form: Dict, gauge_biv: bool = True,
                             det: bool = False, latex: bool = False, *,
                             latex_format: bool | None = None):
        """Gauge transformation ``P_B = P (I - B P)^{-1}`` of ``P`` by a closed 2-form ``B``.

        Returns
        -------
        dict, str, tuple or bool
            As PoissonGeometry: ``{}`` if neither output is asked; ``"det"`` if only ``det``;
            ``False`` if ``det(I - B P) = 0``; the non-zero upper entries ``{(i, j): "expr"}``;
            ``(entries, "det")`` if both (LaTeX strings when ``latex``).
        """
        if not gauge_biv and not det:
            return {}
        flag = _latex_flag(latex, latex_format)
        P = self._P(bivector)
        B = self._reader.bivector(two_form, "two_form")
        G, d = calc.gauge(P.matrix, B.matrix)
        det_out = sp.latex(d) if flag else str(d)  # calc.gauge returns it factored
        if det and not gauge_biv:
            return det_out
        if G is None:
            return False
        n = self.dim
        entries = {(i + 1, j + 1): G[i, j] for i in range(n) for j in range(i + 1, n)
                   if not is_zero(G[i, j])}
        out = render(entries, flag)
        return (out, det_out) if det else out

    # ------------------------------------------------------------------ constructions
    def flaschka_ratiu_bivector(self, casimirs: Sequence[object], symplectic_form: bool = False,
                                latex: bool = False, *, latex_format: bool | None = None):
        """Flaschka–Ratiu bivector with Casimirs ``K_1 .. K_{n-2}``.

        ``P^{ij} = (-1)^{i+j} det(dK_1..dK_{n-2} without columns i, j)`` (PoissonGeometry's sign);
        with ``symplectic_form`` also the 2-form ``-P^{ij} / sum (P^{kl})^2`` on every pair.

        Raises
        ------
        DimensionError
            If ``n < 3``.
        CasimirError
            If the number of Casimirs is not ``n - 2``.
        """
        if self.dim < 3:
            raise DimensionError(f"the dimension {self.dim} is less than 3")
        if isinstance(casimirs, (str, bytes)) or not isinstance(casimirs, Sequence):
            raise CasimirError("casimirs must be a list of expressions")
        if len(casimirs) != self.dim - 2:
            raise CasimirError(f"{len(casimirs)} Casimir functions given, need {self.dim - 2}")
        K = [self._f(c, "casimir") for c in casimirs]
        FR = calc.flaschka_ratiu(K, self.coords)
        flag = _latex_flag(latex, latex_format)
        biv = render({one_based(k): v for k, v in FR.items() if not is_zero(v)}, flag)
        if not symplectic_form:
            return biv
        norm = sum(v ** 2 for v in FR.values())
        form = render({one_based(k): -v / norm for k, v in FR.items()}, flag)
        return biv, form

    def _linear_matrix(self, bivector: Dict) -> sp.Matrix:
        if self.dim != 3:
            raise DimensionError(f"linear normal forms are for R^3; this space has dimension {self.dim}")
        P = self._P(bivector)
        for i in range(3):
            for j in range(i + 1, 3):
                e = sp.expand(P.matrix[i, j])
                if e == 0:
                    continue  # PoissonGeometry raises Nonlinear on explicit "0" entries
                if (not e.is_polynomial(*self.coords)
                        or sp.homogeneous_order(e, *self.coords) != 1
                        or e.free_symbols - set(self.coords)):
                    raise Nonlinear(f"({i + 1}, {j + 1}): {P.matrix[i, j]} is not a linear "
                                    f"polynomial with numeric coefficients in {self.coordinates}")
        return sp.Matrix(P.matrix)

    def linear_normal_form_R3(self, bivector: Dict, latex: bool = False, *,
                              latex_format: bool | None = None):
        """Normal form of a Lie–Poisson bivector on ``R^3`` modulo linear isomorphisms.

        Same classification and normal forms as PoissonGeometry (by unimodularity and the rank
        and signature of the quadratic form ``E_P = (-x1 P^{23} + x2 P^{13} - x3 P^{12}) / 2``);
        the non-unimodular families keep PoissonGeometry's free parameter ``a``. Signatures are
        computed exactly (Descartes' rule on the characteristic polynomial).
        """
        M = self._linear_matrix(bivector)
        flag = _latex_flag(latex, latex_format)
        if M == sp.zeros(3, 3):
            return sp.latex({}) if flag else {}
        x1, x2, x3 = self.coords
        E = sp.Rational(1, 2) * (-x1 * M[1, 2] + x2 * M[0, 2] - x3 * M[0, 1])
        H = sp.Rational(1, 2) * sp.hessian(E, self.coords)
        rank = H.rank()
        pos, neg = calc.inertia(H)
        sig = abs(pos - neg)
        unimodular = self.is_unimodular_homogeneous(bivector)
        a = sp.Symbol("a")
        form: dict[tuple[int, int], sp.Expr] = {}
        if unimodular:
            if rank == 3:
                form = {(1, 2): x3 if sig == 3 else -x3, (1, 3): -x2, (2, 3): x1}
            elif rank == 2:
                form = {(1, 3): -x2 if sig == 2 else x2, (2, 3): x1}
            elif rank == 1:
                form = {(2, 3): x1}
        elif rank == 0:
            form = {(1, 3): x1, (2, 3): x2}
        elif rank == 2:
            form = {(1, 3): x1 - 4 * a * x2 if sig == 2 else x1 + 4 * a * x2,
                    (2, 3): 4 * a * x1 + x2}
        elif rank == 1:
            form = {(1, 3): x1, (2, 3): 4 * x1 + x2}
        if flag:
            return sp.latex(form)
        return {k: str(v) for k, v in form.items()}

    def isomorphic_lie_poisson_R3(self, bivector_1: Dict, bivector_2: Dict) -> bool:
        """True if two Lie–Poisson bivectors on ``R^3`` have the same linear normal form.

        As in PoissonGeometry, the non-unimodular families are compared with their parameter
        ``a`` left free.
        """
        n1 = self.linear_normal_form_R3(bivector_1)
        n2 = self.linear_normal_form_R3(bivector_2)
        if not n1 and not n2:
            return True
        if set(n1) != set(n2):
            return False
        return all(is_zero(self._f(n1[k]) - self._f(n2[k])) for k in n1)

    # ------------------------------------------------------------------ Schouten calculus
    def coboundary_operator(self, bivector: Dict, multivector: Dict | str, latex: bool = False, *,
                            latex_format: bool | None = None):
        """Lichnerowicz–Poisson coboundary ``[P, A]`` (Schouten–Nijenhuis bracket).

        Conventions (shared with PoissonGeometry and :mod:`poissonkit.conventions`):
        ``[P, P] = 2 Jac``, ``[P, X] = -L_X P``, ``[P, f] = P df`` (for a function given as a
        string; that is ``-X_f`` in PoissonGeometry's sign).

        Returns
        -------
        dict or str
            Non-zero components ``{(i1, .., i_{k+1}): "expr"}`` (``{}`` when ``[P, A] = 0``); for a
            function, all ``n`` components ``{(i,): "expr"}``.
        """
        from poissonkit.structure.schouten import lichnerowicz

        flag = _latex_flag(latex, latex_format)
        if not multivector:
            return sp.latex({}) if flag else {}
        P = self._P(bivector)
        if isinstance(multivector, str):
            return self._vector_out(P.matrix * self._reader.gradient(self._f(multivector)), flag)
        A = self._reader.multivector(multivector)
        if A.degree + 1 > self.dim:
            return sp.latex({}) if flag else {}
        R = lichnerowicz(P, A)
        entries = {one_based(k): v for k, v in R.components.items() if not is_zero(v)}
        return render(entries, flag)

    def jacobiator(self, bivector: Dict, latex: bool = False, *, latex_format: bool | None = None):
        """``[P, P]`` (``= 2 Jac``, as in PoissonGeometry): non-zero components, ``{}`` if Poisson."""
        return self.coboundary_operator(bivector, bivector, latex, latex_format=latex_format)

    def is_poisson_bivector(self, bivector: Dict) -> bool:
        """True if ``[P, P] = 0`` (exact check by :func:`poissonkit.structure.jacobi.check_jacobi`)."""
        from poissonkit.structure.jacobi import check_jacobi

        return bool(check_jacobi(self._P(bivector), method="exact").is_poisson)

    def is_poisson_tensor(self, bivector: Dict) -> bool:
        """Alias of :meth:`is_poisson_bivector` (the name in PoissonGeometry's README)."""
        return self.is_poisson_bivector(bivector)

    def is_poisson_vf(self, bivector: Dict, vector_field: Dict) -> bool:
        """True if ``[P, X] = -L_X P = 0``."""
        from poissonkit.structure.schouten import schouten_bracket

        S = schouten_bracket(self._P(bivector), self._reader.vector_field(vector_field))
        return all(is_zero(v) for v in S.components.values())

    def is_poisson_pair(self, bivector_1: Dict, bivector_2: Dict) -> bool:
        """True if ``[P1, P2] = 0`` (then ``P1 + t P2`` is Poisson for Poisson ``P1``, ``P2``)."""
        from poissonkit.structure.schouten import are_compatible

        return bool(are_compatible(self._P(bivector_1), self._reader.bivector(bivector_2, "bivector_2")))

    def lichnerowicz_poisson_operator(self, bivector: Dict, multivector: Dict | str,
                                      latex: bool = False):
        """Alias of :meth:`coboundary_operator` (the name in PoissonGeometry's README)."""
        return self.coboundary_operator(bivector, multivector, latex)
