"""Hamiltonisation search: find a bivector ``P`` and a multiplier ``N`` with ``X = N P dH``.

Given a vector field ``X`` (equations of motion), a Hamiltonian ``H`` (or none), functions that
must be Casimirs and optionally an invariant-measure density ``rho``, :func:`hamiltonize` looks
for ``P`` inside an :class:`Ansatz` such that

* ``X = N P dH``  (sign convention ``xdot = N {x, H}``, :mod:`poissonkit.conventions`),
* ``P dC = 0`` for every requested Casimir ``C``,
* ``[P, P] = 0``.

Method (survey of Borisov, Mamaev and Tsiganov, eq. (12)/(13), and its Theorem 2)
---------------------------------------------------------------------------------
1. **Ansatz.** ``P = s(x) Q(x)`` where ``s`` is a fixed prefactor and every entry ``Q^{ij}`` is a
   polynomial with unknown coefficients: monomials in the *positions* up to ``degree``, times
   ``1`` or a *momentum* (affine in the momenta, survey (13)). With the multiplier taken from
   the invariant measure, ``N = rho`` and ``s = rho`` by default: for the survey's systems
   ``rho = g^{-1}`` with ``g^2`` a polynomial, and ``g P`` is then polynomial (Theorem 2:
   ``P = P_0'/rho``).
2. **Linear conditions.** For fixed ``N`` the conditions ``X = N P dH`` and ``P dC = 0`` are
   linear in the unknown coefficients. Denominators are cleared exactly and the identities
   are split over the monomials in the coordinates; the resulting sparse system over ``QQ``
   (or ``QQ(parameters)``) is solved exactly (sparse reduced echelon form). With a polynomial
   multiplier ansatz, ``N = 1/mu`` with ``mu`` polynomial, the condition ``mu X = s Q dH`` is
   linear homogeneous in ``(mu, Q)``.
3. **Jacobi.** On the remaining affine family ``Q = Q_0 + sum_t t_t Q_t`` the identity
   ``[P, P] = 0`` is a system of quadratic equations in the free parameters ``t``: it is
   computed in a sparse polynomial ring (``Jac(s Q)/s^2 = Jac(Q) + sum (d log s) Q Q``), split
   over coordinate monomials and solved exactly with a Groebner basis.

Inputs as text (a field, a Hamiltonian, integrals, Casimirs, with declared parameters) are
read by :mod:`poissonkit.structure.hamiltonize_input`; a Hamiltonian searched among the
combinations of given integrals is linearised in step 2 (one copy of ``Q`` per integral) and
finished by :mod:`poissonkit.structure.hamiltonize_span`; a Casimir given by its differential
``dC`` enters step 2 exactly like a function's gradient.

A negative answer is a **proof within the ansatz**: either a vector ``y`` with ``y^T A = 0``,
``y^T b = 1`` (a combination of the linear conditions that reads ``0 = 1``; re-checked
independently before it is reported), or, for a polynomial multiplier, the elimination forces
``mu = 0``, or the Jacobi equations generate the unit ideal (reduced Groebner basis ``[1]``).
"""

from __future__ import annotations

import itertools
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import sympy as sp

from poissonkit.errors import InputError
from poissonkit.structure._exact_linear import (check_certificate, inconsistency_certificate,
                                                nullspace_sparse, solve_sparse)
from poissonkit.structure._expr import as_expr
from poissonkit.structure.bivector import Bivector
from poissonkit.structure.hamiltonize_ansatz import ansatz_columns, checked_ansatz
from poissonkit.structure.hamiltonize_input import build_problem, read_text
from poissonkit.structure.hamiltonize_problem import Ansatz, HamiltonizationProblem, problem_from
from poissonkit.structure.hamiltonize_result import Certificate, HamiltonizeResult, result_record
from poissonkit.structure.hamiltonize_span import casimir_combinations, impose_span

#: Name stem of the free parameters of a solution family (``t1, t2, ...``).
PARAMETER_STEM = "t"


# ------------------------------------------------------------------------------ helpers
def _has_radical(e: sp.Expr) -> bool:
    return any(isinstance(a, sp.Pow) and not a.exp.is_Integer for a in sp.preorder_traversal(e))


class _Field:
    """Exact rational functions of the coordinates and parameters.

    Everything is computed over ``QQ`` with the parameters as extra generators (multivariate
    gcds over ``QQ`` are fast; over ``QQ(parameters)`` they took minutes). :meth:`split` then
    reads a polynomial as ``{coordinate monomial: coefficient in K = QQ(parameters)}``.
    """

    def __init__(self, coords: Sequence[sp.Symbol], exprs: Sequence[sp.Expr]) -> None:
        params: set = set()
        for e in exprs:
            params |= e.free_symbols
        params -= set(coords)
        self.params = tuple(sorted(params, key=str))
        self.nc = len(coords)
        self.K = sp.QQ.frac_field(*self.params) if self.params else sp.QQ
        self.F, *_ = sp.polys.fields.field(list(coords) + list(self.params), sp.QQ)
        self.R = self.F.ring

    def convert(self, e: sp.Expr, what: str):
        if _has_radical(e):
            e = sp.powsimp(sp.together(e))
        if _has_radical(e):
            raise InputError(f"{what} is not rational in the coordinates after the prefactor "
                             f"and multiplier are applied ({e}); state a prefactor that "
                             "absorbs the square root (Ansatz.prefactor)")
        try:
            return self.F.from_expr(e)
        except (ValueError, sp.PolynomialError, sp.CoercionFailed, TypeError) as exc:
            raise InputError(
                f"{what} is not a rational function of the coordinates and parameters "
                "(undefined functions such as g(gamma) must be replaced by concrete "
                f"expressions): {str(exc)[-160:]}") from None

    def cleared(self, items):
        """``(D, [f * D])`` with ``D`` the lcm of the denominators (polynomials in R)."""
        den = self.R.one
        for f in items:
            if f:
                den = den.lcm(f.denom)
        return den, [(f.numer * den.exquo(f.denom)) if f else self.R.zero for f in items]

    def shift(self, mono: tuple[int, ...]) -> tuple[int, ...]:
        """A coordinate monomial as a monomial of ``R`` (parameter exponents 0)."""
        return tuple(mono) + (0,) * len(self.params)

    def to_K(self, part: Mapping[tuple[int, ...], object]):
        """``{parameter monomial: rational}`` as an element of ``K``."""
        if not self.params:
            return sum(part.values(), sp.QQ.zero)
        ring = self.K.field.ring
        return self.K.field.field_new(ring({m: sp.QQ(c) for m, c in part.items() if c}))

    def split(self, poly) -> dict[tuple[int, ...], object]:
        """``{coordinate monomial: coefficient in K}`` of a polynomial of ``R``."""
        acc: dict[tuple, dict] = {}
        for monom, coeff in poly.terms():
            acc.setdefault(monom[:self.nc], {})[monom[self.nc:]] = coeff
        return {cm: self.to_K(part) for cm, part in acc.items()}


def _prefactor_and_multiplier(problem, multiplier, prefactor):
    """``(N or None, s, how)``: ``N is None`` means a polynomial multiplier ansatz."""
    rho = problem.measure
    if isinstance(multiplier, str):
        if multiplier not in ("auto", "measure", "one"):
            raise InputError(f"multiplier must be 'auto', 'measure', 'one', an expression or "
                             f"('polynomial', degree), got {multiplier!r}")
        if multiplier == "measure" and rho is None:
            raise InputError("multiplier='measure' needs an invariant measure (none given)")
        if multiplier == "one" or rho is None:
            N, how = sp.Integer(1), "N = 1"
        else:
            N, how = rho, "N = rho (density of the invariant measure)"
        has_h = problem.hamiltonian is not None or bool(problem.hamiltonian_span)
        s = N if prefactor is None and has_h else \
            (sp.Integer(1) if prefactor is None else as_expr(prefactor, "prefactor"))
        return N, s, how
    if isinstance(multiplier, tuple):
        if len(multiplier) not in (2, 3) or multiplier[0] != "polynomial" or \
                isinstance(multiplier[1], bool) or not isinstance(multiplier[1], int) or \
                multiplier[1] < 0:
            raise InputError("a multiplier ansatz is ('polynomial', degree >= 0) or "
                             f"('polynomial', degree, base), got {multiplier!r}")
        base = multiplier[2] if len(multiplier) == 3 else 1
        if isinstance(base, str):
            if base != "measure" or rho is None:
                raise InputError("the base of a multiplier ansatz is an expression or "
                                 "'measure' (with a measure given)")
            base = rho
        base = as_expr(base, "multiplier base")
        s = (base if problem.hamiltonian is not None else sp.Integer(1)) \
            if prefactor is None else as_expr(prefactor, "prefactor")
        return base, s, (f"N = ({base})/mu, mu polynomial of degree <= {multiplier[1]} in all "
                         "coordinates")
    N = as_expr(multiplier, "multiplier")
    if N == 0:
        raise InputError("multiplier must not be zero")
    s = sp.Integer(1) if prefactor is None else as_expr(prefactor, "prefactor")
    return N, s, "N given"


# ------------------------------------------------------------------------------ main
def hamiltonize(system=None, *, field=None, coords=None, params=None, hamiltonian=...,
                integrals=None, casimirs=None, measure=None, ansatz: Ansatz | None = None,
                degree: int | None = None, multiplier="auto", prefactor=None,
                positions: Sequence | None = None, momenta: Sequence | None = None,
                momentum_terms: str = "affine", zero: Sequence = (),
                max_jacobi_parameters: int = 12, name: str = "") -> HamiltonizeResult:
    """Search a Poisson bivector ``P`` and multiplier ``N`` with ``X = N P dH``.

    Parameters
    ----------
    system
        A :class:`~poissonkit.structure.system.HamiltonianSystem` (its equations of motion,
        Hamiltonian, Casimir claims and measure are read; see :func:`problem_from`), a
        :class:`HamiltonizationProblem`, a registered system name, or the field. Or:
    field
        The vector field ``X`` (``xdot = X``): a sequence of components in the order of
        ``coords``, or a mapping coordinate -> component; each a sympy expression or text
        (read by the allow-list parser; names: ``coords``, ``params`` and its fixed functions).
        Any polynomial or rational field (after the multiplier and prefactor are applied).
    coords
        The coordinates of ``field`` (names, which become real symbols, or sympy symbols).
    params
        Parameters the texts may name, as in
        :func:`~poissonkit.structure.parsing.declare_parameters` (``["a", "b"]``,
        ``{"k": {"positive": True}}``). The search then runs over ``QQ(parameters)``.
    integrals
        First integrals ``I_k`` (a sequence, named ``I1, I2, ...``, or a mapping; with a system
        also names of its integrals). Without ``hamiltonian``: ``H = sum c_k I_k`` is searched with
        unknown constants ``c`` (see :mod:`~poissonkit.structure.hamiltonize_span`; a negative
        answer covers every combination). With it: ``H`` is fixed and each found bracket reports
        which combinations of the integrals are its Casimirs (``res.integral_casimirs``).
    measure
        Invariant-measure density ``rho`` of ``field`` (multiplier ``"auto"`` then uses it).
    name
        Label for reports (with ``field``).
    ansatz
        The searched space (:class:`Ansatz`). If omitted it is built from ``positions``,
        ``momenta``, ``degree``, ``momentum_terms``, ``prefactor`` and ``zero``.
    degree
        Degree of the coefficients in the positions (default 1).
    multiplier
        ``"auto"`` (``N = rho`` if a measure is known, else 1), ``"measure"``, ``"one"``, an
        expression, or ``("polynomial", k)`` / ``("polynomial", k, base)``: ``N = base/mu``
        with ``mu`` an unknown polynomial of degree ``<= k`` in all coordinates (``base`` an
        expression or ``"measure"``; default 1).
    prefactor
        ``s`` in ``P = s Q`` (an expression or text). Default: ``N`` (or the base of a
        multiplier ansatz) if from the measure with a Hamiltonian (``P = rho Q``), else 1.
    hamiltonian
        Override of ``H``; ``None`` drops the condition ``X = N P dH``.
    casimirs
        Casimirs to impose: a mapping ``{name: C}``, where a value that is a sequence of ``n``
        components is the *differential* ``dC`` of a Casimir known only through it (its
        closedness is checked exactly; the condition ``P dC = 0`` is linear as for any
        Casimir), or a sequence of expressions / names of the given integrals (with a system:
        names among its Casimirs and integrals; default: its Casimir claims).
    positions, momenta
        Default: coordinates named ``gamma_*`` (or ``q_*``, ``nu_*``) are positions, the others
        momenta; without such names every coordinate is a position (coefficients polynomial
        of degree ``<= degree`` in all coordinates: no ``positions=`` needed for a field that
        is not mechanical).
    momentum_terms, zero
        See :class:`Ansatz`; ``zero`` may also be ``"positions"`` / ``"momenta"`` to force the
        whole ``{pos, pos}`` / ``{mom, mom}`` block to vanish (or a list of index pairs).
    max_jacobi_parameters
        Above this number of free parameters the Jacobi system is not attempted (status
        ``"jacobi_unsolved"``).

    Returns
    -------
    HamiltonizeResult
        The family, its Poisson members, or a certificate of non-existence.

    Raises
    ------
    InputError
        Malformed input, or a field/prefactor that is not rational in the coordinates.
    ParseError
        Text with a name that is neither a coordinate nor a declared parameter (the message
        lists the allowed names), or an unsafe construct.

    Examples
    --------
    >>> import poissonkit as pk
    >>> res = pk.hamiltonize(field=["x2*x3", "-x1*x3", "0"], coords=["x1", "x2", "x3"],
    ...                      integrals=["x1**2 + x2**2", "x3**2"], degree=1)
    >>> res.found
    True
    >>> pk.hamiltonize("nh.chaplygin_ball", degree=2).status  # doctest: +SKIP
    'no_linear_solution'
    >>> res = pk.hamiltonize("nh.chaplygin_ball", degree=3)   # doctest: +SKIP
    >>> res.found, res.parameters                             # doctest: +SKIP
    (True, ())
    """
    t0 = time.perf_counter()
    problem, ints = build_problem(system, field=field, coords=coords, params=params,
                                  hamiltonian=hamiltonian, integrals=integrals,
                                  casimirs=casimirs, measure=measure, name=name)
    return _search(problem, ints, t0, ansatz, multiplier, prefactor, degree, positions, momenta,
                   momentum_terms, zero, max_jacobi_parameters)


def _search(problem: HamiltonizationProblem, ints, t0: float, ansatz: Ansatz | None,
            multiplier, prefactor, degree: int | None, positions: Sequence | None,
            momenta: Sequence | None, momentum_terms: str, zero: Sequence,
            max_jacobi_parameters: int) -> HamiltonizeResult:
    """:func:`hamiltonize` on a built problem (``t0``: the start time of the call): the
    multiplier and the ansatz, then steps 2 and 3 (linear conditions, then Jacobi)."""
    if isinstance(prefactor, str):  # text, read like every other argument
        prefactor = read_text(problem, prefactor, "prefactor")
    N, s, how = _prefactor_and_multiplier(problem, multiplier, prefactor)
    ansatz = checked_ansatz(problem, ansatz, multiplier, prefactor, degree, positions, momenta,
                            momentum_terms, s, zero)
    coords = problem.coords
    span = problem.hamiltonian_span
    poly_mult = isinstance(multiplier, tuple)
    columns = ansatz_columns(ansatz, coords, multiplier[1] if poly_mult else None,
                             max(1, len(span)))
    t1 = time.perf_counter()
    system_ = _assemble(problem, ansatz.prefactor, N, columns, poly_mult)
    t2 = time.perf_counter()
    stats: dict[str, object] = {"unknowns": len(columns), "equations": len(system_.labels),
                                "multiplier_rule": how, "seconds_assemble": t2 - t1}

    def finish(status, **kw):
        stats["seconds_total"] = time.perf_counter() - t0
        sols = kw.get("solutions", ())
        if sols and "hamiltonians" not in kw:
            kw["hamiltonians"] = tuple(problem.hamiltonian for _ in sols)
        if sols and ints:
            kw["integral_casimirs"] = tuple(casimir_combinations(P, ints) for P in sols)
        return HamiltonizeResult(status=status, ansatz=ansatz, problem=problem, stats=stats, **kw)

    K = system_.fld.K
    if poly_mult:
        sol = nullspace_sparse(system_.rows, len(columns), K)
    else:
        sol = solve_sparse(system_.rows, system_.rhs, len(columns), K)
    t3 = time.perf_counter()
    stats.update(rank=sol.rank, seconds_linear=t3 - t2)
    if not sol.consistent:
        cert = _linear_certificate(system_, len(columns), coords)
        stats["seconds_certificate"] = time.perf_counter() - t3
        return finish("no_linear_solution", multiplier=N, certificate=cert)
    mu_cols = [c for c, col in enumerate(columns) if col[0] == "mu"]
    if poly_mult and not any(any(d.get(c) for c in mu_cols) for d in sol.directions):
        return finish("no_multiplier", certificate=Certificate(
            "multiplier", text=f"Every solution of the {len(system_.labels)} linear equations "
            f"has mu = 1/N = 0: no multiplier of degree <= {multiplier[1]} exists (exact "
            "elimination)."))

    tau, Qs, mu = _family(sol, columns, coords, K, max(1, len(span)))
    stats["parameters"] = len(tau)
    if span:
        if len(tau) > max_jacobi_parameters:
            return finish("jacobi_unsolved", multiplier=N, parameters=tau)
        t4 = time.perf_counter()
        status, out = impose_span(
            Qs, ansatz.prefactor, coords, tau, span, N,
            lambda Q: _jacobi_equations(Q, ansatz.prefactor, coords, tau, system_.fld))
        stats["jacobi_equations"] = out.pop("count")
        stats["seconds_jacobi"] = time.perf_counter() - t4
        return finish(status, multiplier=N, **out)
    Qm = Qs[0]
    Nfam = (N / mu) if poly_mult else N
    if problem.hamiltonian is None:
        Nfam = None  # no field condition: the multiplier plays no part
    family = Bivector(coords, sp.ImmutableMatrix(Qm * ansatz.prefactor))
    if len(tau) > max_jacobi_parameters:
        return finish("jacobi_unsolved", multiplier=Nfam, family=family, parameters=tau)
    t4 = time.perf_counter()
    status, out = _impose_jacobi(Qm, ansatz.prefactor, coords, tau, system_.fld, family, Nfam,
                                 mu if poly_mult else None)
    stats["jacobi_equations"] = out.pop("count")
    stats["seconds_jacobi"] = time.perf_counter() - t4
    return finish(status, multiplier=Nfam, family=family, **out)


@dataclass
class _LinearSystem:
    """The coefficient equations: ``rows[r] . u = rhs[r]``, labelled ``labels[r]``."""

    labels: list[tuple]
    rows: list[dict[int, object]]
    rhs: list[object]
    fld: _Field


def _assemble(problem: HamiltonizationProblem, s, N, columns, poly_mult: bool) -> _LinearSystem:
    """Clear denominators and split ``X = N s Q dH`` and ``s Q dC = 0`` over monomials.

    Fixed ``N``: ``Q dH = X/(N s)``. Multiplier ansatz ``N = base/mu``: ``Q dH - mu X/(base s)
    = 0`` (homogeneous; ``N`` is the base here). Hamiltonian span ``H = sum c_k I_k``: the
    bilinear ``sum c_k Q dI_k`` is linearised as ``sum_k W_k dI_k`` with one copy ``W_k = c_k Q``
    per integral (:mod:`poissonkit.structure.hamiltonize_span` restores ``W_k = c_k Q``).
    """
    coords = problem.coords
    n = len(coords)
    forms = problem.casimir_forms()
    gens = list(problem.hamiltonian_span.values()) or (
        [problem.hamiltonian] if problem.hamiltonian is not None else [])
    exprs = list(problem.field) + [a for f in forms.values() for a in f] + [s, N] + gens
    fld = _Field(coords, [sp.sympify(e) for e in exprs])
    rows: dict[tuple, dict[int, dict]] = {}
    rhs: dict[tuple, dict] = {}

    # accumulate {parameter monomial: rational} per entry; converted to K once at the end
    def add(label_stem, poly, col=None, sign=1):
        for monom, coeff in poly.terms():
            key = label_stem + (monom[:fld.nc],)
            row = rows.setdefault(key, {})
            slot = rhs.setdefault(key, {}) if col is None else row.setdefault(col, {})
            pm = monom[fld.nc:]
            slot[pm] = slot.get(pm, 0) + (coeff if sign > 0 else -coeff)

    if gens:
        m = len(gens)
        dH = [fld.convert(sp.diff(G, x), "dH") for G in gens for x in coords]
        r = [fld.convert(sp.sympify(problem.field[i]) / (N * s), f"X_{i}/(N s)")
             for i in range(n)]
        # row i, cleared by its own denominator: [D_i dG_1 (n entries), ..., D_i dG_m, D_i r_i]
        cleared = [fld.cleared(dH + [r[i]])[1] for i in range(n)]
        for c, (kind, i, j, mono, k) in enumerate(columns):
            if kind == "P":
                add(("X", i), cleared[i][k * n + j].mul_monom(fld.shift(mono)), c)
                add(("X", j), cleared[j][k * n + i].mul_monom(fld.shift(mono)), c, -1)
            else:
                for q in range(n):
                    add(("X", q), cleared[q][m * n].mul_monom(fld.shift(mono)), c, -1)
        if not poly_mult:
            for i in range(n):
                add(("X", i), cleared[i][m * n])
    for cname, form in forms.items():
        dC = [fld.convert(a, f"d({cname})") for a in form]
        _, cc = fld.cleared(dC)
        # every copy W_k = c_k Q is annihilated when Q is (some c_k is not zero)
        for c, (kind, i, j, mono, k) in enumerate(columns):
            if kind == "P":
                add(("C", cname, i, k), cc[j].mul_monom(fld.shift(mono)), c)
                add(("C", cname, j, k), cc[i].mul_monom(fld.shift(mono)), c, -1)
    labels = list(rows)
    return _LinearSystem(labels, [{c: fld.to_K(v) for c, v in rows[k].items()} for k in labels],
                         [fld.to_K(rhs.get(k, {})) for k in labels], fld)


def _linear_certificate(ls: _LinearSystem, ncols: int, coords) -> Certificate:
    """A short, re-checked combination of the equations that reads ``0 = 1``."""
    K = ls.fld.K
    keep = _inconsistent_core(ls.labels, ls.rows, ls.rhs, ncols, K)
    sub_rows = [ls.rows[r] for r in keep]
    sub_rhs = [ls.rhs[r] for r in keep]
    y = inconsistency_certificate(sub_rows, sub_rhs, ncols, K)
    if y is None or not check_certificate(sub_rows, sub_rhs, ncols, y, K):
        raise RuntimeError("internal error: inconsistent system without a certificate")
    combo = {_label(ls.labels[keep[r]], coords): K.to_sympy(v) for r, v in y.items()}
    return Certificate("linear", combo, (), (
        f"The linear conditions are inconsistent: a combination of {len(combo)} of the "
        f"{len(ls.labels)} coefficient equations has left-hand side 0 and right-hand side 1 "
        "(exact, re-checked)."))


def _family(sol, columns, coords, K, copies: int = 1):
    """``(tau, [Q_0, ...], mu)``: the solution family (one ``Q`` per copy) with free
    parameters ``t1..tk`` as sympy objects."""
    n = len(coords)
    k = len(sol.free)
    tau = sp.symbols(f"{PARAMETER_STEM}1:{k + 1}", real=True) if k else ()
    coeff: dict[int, sp.Expr] = {c: K.to_sympy(v) for c, v in sol.particular.items()}
    for t, d in zip(tau, sol.directions):
        for c, v in d.items():
            coeff[c] = coeff.get(c, sp.Integer(0)) + K.to_sympy(v) * t
    Qs = [sp.zeros(n, n) for _ in range(copies)]
    mu = sp.Integer(0)
    for c, val in coeff.items():
        kind, i, j, mono, k = columns[c]
        term = val * sp.Mul(*[x**e for x, e in zip(coords, mono)])
        if kind == "P":
            Qs[k][i, j] += term
            Qs[k][j, i] -= term
        else:
            mu += term
    return tau, Qs, mu


def _impose_jacobi(Qm, s, coords, tau, fld, family, Nfam, mu) -> tuple[str, dict]:
    """Jacobi on the family: ``(status, fields of the result)``; ``mu`` for a multiplier ansatz."""
    eqs = _jacobi_equations(Qm, s, coords, tau, fld)
    if not eqs:      # every member is Poisson
        return "found", dict(count=0, parameters=tau, solutions=(family,), multipliers=(Nfam,))
    if not tau:
        return "no_jacobi_solution", dict(
            count=len(eqs), jacobi_equations=tuple(eqs), certificate=Certificate(
                "jacobi", equations=tuple(eqs[:5]), text=(
                    "The linear conditions fix P uniquely and [P,P] != 0: "
                    f"{len(eqs)} non-zero coefficients of the Jacobiator.")))
    basis = tuple(sp.groebner(eqs, *tau, order="grevlex").exprs)
    if basis == (1,):
        return "no_jacobi_solution", dict(
            count=len(eqs), parameters=tau, jacobi_equations=basis, certificate=Certificate(
                "jacobi", equations=basis, text=(
                    f"The {len(eqs)} Jacobi equations in the {len(tau)} free parameters "
                    "generate the unit ideal (reduced Groebner basis [1]): no member of the "
                    "family is Poisson.")))
    sols = sp.solve(list(basis), list(tau), dict=True)
    if not sols:
        # no real solution found by sympy's solver: not a proof (the ideal is not [1])
        return "jacobi_unsolved", dict(count=len(eqs), parameters=tau, jacobi_equations=basis)
    members, mults = [], []
    for sd in sols:
        if mu is not None and sp.expand(mu.subs(sd)) == 0:
            continue  # mu = 0 is not a multiplier
        members.append(family.subs(sd))
        mults.append(None if Nfam is None else sp.sympify(Nfam).subs(sd))
    if not members:
        return "no_jacobi_solution", dict(
            count=len(eqs), parameters=tau, jacobi_equations=basis, certificate=Certificate(
                "jacobi", equations=basis, text=(
                    "Every solution of the Jacobi equations has mu = 0: none is a "
                    "multiplier.")))
    return "found", dict(count=len(eqs), parameters=tau, jacobi_equations=basis,
                         solutions=tuple(members), multipliers=tuple(mults))


def _inconsistent_core(labels, rows, rhs, ncols, K) -> list[int]:
    """Rows of a still-inconsistent subsystem, found by dropping whole condition groups.

    A group is one component of one condition (``(X - N P dH)_i`` or ``P dC`` row ``i``). The
    certificate is then computed on the smaller system: the transposed solve costs in
    proportion to the number of equations.
    """
    groups: dict[tuple, list[int]] = {}
    for r, key in enumerate(labels):
        groups.setdefault(key[:-1], []).append(r)
    live = list(groups)
    for g in list(live):
        trial = [r for h in live if h != g for r in groups[h]]
        if not trial:
            continue
        sol = solve_sparse([rows[r] for r in trial], [rhs[r] for r in trial], ncols, K)
        if not sol.consistent:
            live.remove(g)
    return [r for h in live for r in groups[h]]


def _label(key: tuple, coords) -> tuple:
    """Readable label of an equation: ``(condition, component, monomial as expression)``."""
    *stem, monom = key
    mono = sp.Mul(*[x**e for x, e in zip(coords, monom)])
    if stem[0] == "X":
        return (f"(X - N P dH)_{coords[stem[1]]}", mono)
    return (f"P d({stem[1]})_{coords[stem[2]]}", mono)


def _jacobi_equations(Qm: sp.Matrix, s: sp.Expr, coords, tau, fld: _Field) -> list[sp.Expr]:
    """Coefficients (over coordinate monomials) of ``delta * Jac(s Q) / s^2``, in ``tau``.

    ``Jac(s Q)/s^2 = Jac(Q) + sum_m (d_m log s) (Q^{im} Q^{jk} + cyclic)``; ``delta`` clears the
    denominators of ``d log s``. Computed in a sparse polynomial ring over the coordinates and
    the parameters ``tau``.
    """
    n = len(coords)
    dlog = [fld.convert(sp.diff(s, x) / s, "d log(prefactor)") for x in coords]
    delta, ell = fld.cleared(dlog)
    R2, *gens = sp.ring(list(coords) + list(tau), fld.K)
    nc = len(coords)

    def lift(p):
        return R2({m + (0,) * len(tau): c for m, c in fld.split(p).items()}) if p else R2.zero

    delta2 = lift(delta)
    ell2 = [lift(e) for e in ell]
    Q = [[R2.zero] * n for _ in range(n)]
    for i in range(n):
        for j in range(n):
            if Qm[i, j] != 0:
                Q[i][j] = R2.from_expr(sp.expand(Qm[i, j]))
    dQ = [[[Q[i][j].diff(gens[m]) if Q[i][j] else R2.zero for m in range(n)]
           for j in range(n)] for i in range(n)]
    eqs: dict = {}
    for i, j, k in itertools.combinations(range(n), 3):
        acc = R2.zero
        for (a, b, c) in ((i, j, k), (j, k, i), (k, i, j)):
            for m in range(n):
                if not Q[a][m]:
                    continue
                if dQ[b][c][m]:
                    acc += delta2 * Q[a][m] * dQ[b][c][m]
                if ell2[m] and Q[b][c]:
                    acc += ell2[m] * Q[a][m] * Q[b][c]
        if not acc:
            continue
        split: dict = {}
        for monom, coeff in acc.terms():
            key = monom[:nc]
            split.setdefault(key, {})
            split[key][monom[nc:]] = coeff
        for part in split.values():
            expr = sum((fld.K.to_sympy(cf) * sp.Mul(*[t**e for t, e in zip(tau, mt)])
                        for mt, cf in part.items()), sp.Integer(0))
            expr = sp.expand(expr)
            if expr != 0:
                # normalise so that equal equations are kept once
                lead = sp.Poly(expr, *tau).LC() if tau else expr
                eqs[sp.expand(expr / lead) if tau else expr] = True
    return list(eqs)



__all__ = ["Ansatz", "Certificate", "HamiltonizationProblem", "HamiltonizeResult",
           "hamiltonize", "problem_from", "result_record"]
