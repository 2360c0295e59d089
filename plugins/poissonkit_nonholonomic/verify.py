"""Verification of the survey's claims for a :class:`~poissonkit.structure.HamiltonianSystem`.

:func:`verify_system` checks every claim a system carries, through the symbolic core
(:mod:`poissonkit.structure`):

* the Jacobi identity ``[P, P] = 0`` (components ``Jac^{ijk}``, FORMULAS.md §0):
  :func:`poissonkit.structure.jacobi.check_jacobi`;
* each Casimir ``C``: ``P dC = 0`` (:func:`poissonkit.structure.casimirs.is_casimir`);
* each first integral ``F``: ``X(F) = 0`` with ``X = N P dH``
  (:func:`poissonkit.structure.checks.is_first_integral`);
* the integrals (and ``H``) pairwise in involution, ``{F, G} = 0``
  (:func:`poissonkit.structure.checks.in_involution`);
* ``X = N P dH`` reproduces the original equations of motion
  (:func:`poissonkit.structure.checks.is_conformally_hamiltonian`);
* the invariant measure ``rho``: ``div(rho X) = 0``
  (:func:`poissonkit.structure.checks.is_invariant_measure`);
* extra, system-specific claims (:mod:`poissonkit_nonholonomic.claims`), e.g. the BMF
  decomposition (55) or the Chaplygin–Veselova equivalence (Prop. 4).

Modes. ``"exact"`` is a symbolic proof of every claim. ``"random"`` runs the core's randomized
Jacobi check (exact arithmetic at random integer points, Schwartz–Zippel bound) and tests the
field claims (integrals, involution, equations, measure) in exact arithmetic at random rational
points (:mod:`poissonkit_nonholonomic.algebra`; a false positive has probability at most
``D / (2 * 10**6 + 1)`` per point, ``D`` the degree of the numerator); Casimirs are always
proved exactly (cheap). ``"auto"`` (default) lets the core choose the Jacobi method and proves
the field claims exactly through the core, except for systems whose field is large (the
rolling-ball systems with ``g = sqrt(...)``, and above all the BMF bivector): there the core's
exact proof takes 0.5–50 s per claim against 0.02–0.1 s at random points, so the random-point
path is kept for them (see :data:`AUTO_EXACT_OPS`). ``"random"`` cannot evaluate undefined
functions. An identity that fails on ``R^n`` is re-tested on the constraint set
(``(gamma, gamma) = 1``) and reported as such.

:func:`format_report` prints a report in the style of seed 000's Maple worksheet.
"""

from __future__ import annotations

import itertools
import random
import time
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import sympy as sp

from poissonkit.errors import InputError
from poissonkit.structure.bivector import Bivector
from poissonkit.structure.casimirs import is_casimir
from poissonkit.structure.checks import (
    CheckResult,
    in_involution,
    is_conformally_hamiltonian,
    is_first_integral,
    is_invariant_measure,
)
from poissonkit.structure.jacobi import check_jacobi, jacobiator_terms
from poissonkit.structure.system import HamiltonianSystem
from poissonkit_nonholonomic.algebra import (
    PointSampler,
    Radicals,
    extract_radicals,
    vanishes,
)

__all__ = ["AUTO_EXACT_OPS", "format_report", "jacobiator", "verify_system"]

_MAX_STR = 240
#: In ``mode="auto"``, field claims are proved exactly by the core when ``P``, ``H`` and ``N``
#: together have at most this many operations (``sympy.count_ops``; the field ``N P dH`` itself
#: is not formed first: for the Routh sphere that alone takes minutes). Measured (same process):
#: Suslov, P_gf, generalized Chaplygin (< 220 ops): core 0.01–0.5 s per claim, comparable to
#: random points; Chaplygin ball / Veselova (320–400 ops, square roots): core 0.5–3 s per claim
#: against ~0.02 s at random points; BMF bivector (~880 ops): core 5–50 s per claim against
#: ~0.1 s; Routh sphere: ~48000 ops. Above the threshold the random-point path is kept
#: (``mode="exact"`` forces the core).
AUTO_EXACT_OPS = 250
_EXACT = "exact (symbolic, poissonkit.structure)"


def _short(expr: Any) -> str:
    text = str(expr)
    return text if len(text) <= _MAX_STR else text[: _MAX_STR - 3] + "..."


class _RandomPoints:
    """Zero tests at random rational points, in exact arithmetic with square roots.

    Only used for the field claims of large systems (see the module docstring); everything else
    goes through the core. ``zero(build)`` evaluates ``build(ev)`` at each point, ``ev`` mapping
    a radical-form expression to its exact value there.
    """

    def __init__(self, coords: Sequence[sp.Symbol], exprs: Mapping[Any, sp.Expr], points: int,
                 constraints: Sequence[sp.Expr] = (), seed: int = 20140301):
        self.coords = tuple(coords)
        keys = list(exprs)
        converted, self.rad = extract_radicals([exprs[k] for k in keys])
        self.e = dict(zip(keys, converted))
        self.points = points
        self.constraints = tuple(constraints)
        self.seed = seed
        syms = set().union(*(x.free_symbols for x in converted)) if converted else set()
        self.extra = sorted(syms - set(self.coords) - set(self.rad.roots), key=str)
        self._deriv: dict[tuple[Any, int], sp.Expr] = {}
        self._point_cache: dict[bool, list[dict]] = {}

    def d(self, key: Any, m: int) -> sp.Expr:
        """Cached derivative of the stored expression ``key`` along coordinate ``m``."""
        if (key, m) not in self._deriv:
            self._deriv[(key, m)] = self.rad.derivative(self.e[key], self.coords[m])
        return self._deriv[(key, m)]

    def dexpr(self, f: sp.Expr, m: int) -> sp.Expr:
        """Derivative of an arbitrary radical-form expression."""
        return self.rad.derivative(f, self.coords[m])

    def _points(self, on_shell: bool) -> list[dict]:
        if on_shell not in self._point_cache:
            sampler = PointSampler(self.coords + tuple(self.extra),
                                   self.constraints if on_shell else (), seed=self.seed)
            pts = []
            for _ in range(self.points):
                p = sampler.draw()
                local = {s: sp.sympify(Q).subs(p) for s, Q in self.rad.roots.items()}
                pts.append({"point": p, "radicals": Radicals(local), "cache": {}})
            self._point_cache[on_shell] = pts
        return self._point_cache[on_shell]

    def zero(self, build: Callable[[Callable[[sp.Expr], sp.Expr]], sp.Expr],
             on_shell: bool = False) -> tuple[bool, sp.Expr | None]:
        """``(ok, witness)``: whether ``build(ev)`` vanishes at every point, else its value."""
        for pt in self._points(on_shell):
            point, cache = pt["point"], pt["cache"]

            def ev(f, point=point, cache=cache):
                # values are memoised per point: the same derivative enters many identities
                try:
                    return cache[f]
                except KeyError:
                    val = sp.sympify(f).xreplace(point)
                    cache[f] = val
                    return val

            value = build(ev)
            if not vanishes(value, pt["radicals"]):
                restored = sp.nsimplify(pt["radicals"].restore(value)) if value.free_symbols \
                    else value
                return False, sp.radsimp(sp.together(restored))
        return True, None


# ---------------------------------------------------------------------- the checks
def _result(claim: str, ok: bool, method: str, seconds: float, detail: str = "",
            on_shell: bool = False) -> dict[str, Any]:
    return {"claim": claim, "ok": bool(ok), "method": method, "seconds": round(seconds, 3),
            "detail": detail, "on_constraint_set": on_shell}


def _shell_note(constraints: Sequence[sp.Expr]) -> str:
    return "holds only on the constraint set " + ", ".join(f"{c} = 0" for c in constraints)


def _core_check(claim: str, run: Callable[[Sequence[sp.Expr]], CheckResult],
                constraints: Sequence[sp.Expr]) -> dict[str, Any]:
    """Run a core check identically, then (if it fails) modulo the system's constraints."""
    t0 = time.perf_counter()
    res = run(())
    on_shell = False
    if not res.holds and constraints:
        res2 = run(tuple(constraints))
        if res2.holds:
            res, on_shell = res2, True
    if on_shell:
        detail = _shell_note(constraints)
    elif res.holds:
        detail = ""
    else:
        detail = "nonzero: " + "; ".join(f"{k} = {_short(v)}" for k, v in res.failures[:4])
    return _result(claim, res.holds, _EXACT, time.perf_counter() - t0, detail, on_shell)


def _random_check(ck: _RandomPoints, claim: str, build) -> dict[str, Any]:
    t0 = time.perf_counter()
    method = f"exact arithmetic at {ck.points} random rational points"
    ok, witness = ck.zero(build)
    on_shell = False
    if not ok and ck.constraints:
        ok2, _ = ck.zero(build, on_shell=True)
        if ok2:
            ok, on_shell = True, True
    detail = _shell_note(ck.constraints) if on_shell else ("" if ok else f"nonzero: {_short(witness)}")
    return _result(claim, ok, method, time.perf_counter() - t0, detail, on_shell)


def _jacobi_check(system: HamiltonianSystem, mode: str, points: int, seed: int) -> dict[str, Any]:
    """The core's :func:`check_jacobi` (exact, randomized or its own automatic choice)."""
    t0 = time.perf_counter()
    res = check_jacobi(system.structure, method=mode, trials=points, seed=seed)
    if res.method == "exact":
        method = _EXACT
    else:
        method = (f"poissonkit.structure.check_jacobi at {res.trials} random integer points, "
                  f"exact arithmetic (false-positive bound {res.false_positive_bound:.1e})")
    fails = [f"{k} = {_short(v)}" for k, v in res.named_failures().items()]
    detail = "" if res.is_poisson else "; ".join(fails[:4]) + (
        f" (+{len(fails) - 4} more)" if len(fails) > 4 else "")
    return _result("Jacobi identity [P,P] = 0", res.is_poisson, method,
                   time.perf_counter() - t0, detail)


def _has_functions(exprs) -> bool:
    return any(sp.sympify(e).atoms(sp.core.function.AppliedUndef) for e in exprs)


def verify_system(system: HamiltonianSystem, *, mode: str = "auto", points: int = 3,
                  jacobi: bool = True, extra: bool = True, seed: int = 20140301) -> dict[str, Any]:
    """Check every claim of a (conformally) Hamiltonian system; return a JSON-able report.

    Parameters
    ----------
    system
        The system; its ``structure``, ``hamiltonian``, ``multiplier``, ``casimirs``,
        ``integrals``, ``measure`` and ``original`` are checked.
    mode
        ``"auto"``, ``"exact"`` or ``"random"`` (see the module docstring).
    points
        Random points per identity in random mode.
    jacobi
        Whether to check the Jacobi identity.
    extra
        Whether to run the system-specific claims of :mod:`poissonkit_nonholonomic.claims`.
    seed
        Seed of the random points (reports are reproducible).

    Returns
    -------
    dict
        ``name``, ``doc``, ``coordinates``, ``parameters``, ``mode``, ``checks`` (list of
        ``{claim, ok, method, seconds, detail, on_constraint_set}``), ``brackets`` (the nonzero
        ``{x_i, x_j}``), ``equations`` (``xdot_i``), ``integrals``, ``ok`` (all checks passed)
        and ``seconds``.

    Raises
    ------
    InputError
        Not a system, unknown mode, or ``mode="random"`` with undefined functions.
    """
    if not isinstance(system, HamiltonianSystem):
        raise InputError(f"verify_system needs a HamiltonianSystem, got {type(system).__name__}")
    if mode not in ("auto", "exact", "random"):
        raise InputError(f"mode must be 'auto', 'exact' or 'random', got {mode!r}")
    t_start = time.perf_counter()
    coords = system.coords
    n = len(coords)
    P = system.structure
    M = P.matrix
    H, N = sp.sympify(system.hamiltonian), sp.sympify(system.multiplier)
    pieces = [H, N, *system.casimirs.values(), *system.integrals.values(), *M]
    if system.measure is not None:
        pieces.append(system.measure)
    if system.original is not None:
        pieces.extend(system.original.values())
    has_f = _has_functions(pieces)
    if mode == "random" and has_f:
        raise InputError("random mode cannot evaluate undefined functions; use mode='exact'")
    if mode == "auto":
        size = sum(sp.count_ops(e) for e in M if e != 0) + sp.count_ops(H) + sp.count_ops(N)
        use = "random" if not has_f and size > AUTO_EXACT_OPS else "exact"
    else:
        use = mode
    constraints = tuple(system.constraints)

    checks: list[dict[str, Any]] = []
    if jacobi:
        checks.append(_jacobi_check(system, mode, points, seed))
    for name, C in system.casimirs.items():
        checks.append(_core_check(f"Casimir {name}: P dC = 0",
                                  lambda cons, C=C: is_casimir(P, C, constraints=cons),
                                  constraints))
    # keys: ("F", name) for an integral, "H" for the Hamiltonian (an integral may be named "H")
    funcs: dict[Any, sp.Expr] = {("F", k): sp.sympify(F) for k, F in system.integrals.items()}
    funcs["H"] = H
    inv = [k for k, F in funcs.items() if k != "H" and not _proportional(F, H, coords, has_f)]
    pairs = list(itertools.combinations([*inv, "H"], 2))
    if use == "exact":
        X = dict(zip(coords, system.vector_field()))
        for name, F in system.integrals.items():
            checks.append(_core_check(
                f"first integral {name}: X(F) = 0",
                lambda cons, F=F: is_first_integral(X, F, constraints=cons, coords=coords),
                constraints))
        for a, b in pairs:
            na, nb = _label(a), _label(b)
            checks.append(_core_check(
                f"involution {{{na}, {nb}}} = 0",
                lambda cons, a=a, b=b: in_involution(P, [funcs[a], funcs[b]], constraints=cons),
                constraints))
        if system.original is not None:
            checks.append(_core_check(
                "X = N P dH reproduces the original equations of motion",
                lambda cons: is_conformally_hamiltonian(system.original, P, H, N,
                                                        constraints=cons),
                constraints))
        if system.measure is not None:
            checks.append(_core_check(
                f"invariant measure rho = {_short(system.measure)}: div(rho X) = 0",
                lambda cons: is_invariant_measure(X, system.measure, constraints=cons,
                                                  coords=coords),
                constraints))
    else:
        checks.extend(_random_field_checks(system, pairs, points, seed))
    if extra:
        from poissonkit_nonholonomic.claims import CLAIMS

        for claim in CLAIMS.get(system.name, ()):
            t0 = time.perf_counter()
            ok, detail, method = claim(system)
            checks.append(_result(claim.__doc__.strip().splitlines()[0], ok, method,
                                  time.perf_counter() - t0, detail))
    brackets = {f"{{{coords[i]},{coords[j]}}}": _short(M[i, j])
                for i in range(n) for j in range(i + 1, n) if M[i, j] != 0}
    equations = {}
    if system.original is not None:
        equations = {f"d{x}/dt": _short(v) for x, v in system.original.items()}
    return {
        "name": system.name,
        "doc": system.doc,
        "coordinates": [str(c) for c in coords],
        "parameters": {k: (str(v) if not isinstance(v, (int, float)) else v)
                       for k, v in system.params.items()},
        "mode": use,
        "multiplier": _short(system.multiplier),
        "hamiltonian": _short(system.hamiltonian),
        "casimirs": {k: _short(v) for k, v in system.casimirs.items()},
        "integrals": {k: _short(v) for k, v in system.integrals.items()},
        "measure": None if system.measure is None else _short(system.measure),
        "brackets": brackets,
        "equations": equations,
        "checks": checks,
        "ok": all(c["ok"] for c in checks),
        "seconds": round(time.perf_counter() - t_start, 3),
    }


def _random_field_checks(system: HamiltonianSystem, pairs, points: int,
                         seed: int) -> list[dict[str, Any]]:
    """Integrals, involution, equations and measure at random rational points (large systems,
    where the core's exact proof is 50–300x slower; see the module docstring)."""
    coords = system.coords
    n = len(coords)
    M = system.structure.matrix
    nonzero = {(i, j) for i in range(n) for j in range(n) if M[i, j] != 0}
    exprs: dict[Any, sp.Expr] = {("P", i, j): M[i, j] for (i, j) in nonzero}
    exprs["H"] = sp.sympify(system.hamiltonian)
    exprs["N"] = sp.sympify(system.multiplier)
    for name, F in system.integrals.items():
        exprs[("F", name)] = sp.sympify(F)
    if system.measure is not None:
        exprs["rho"] = sp.sympify(system.measure)
    if system.original is not None:
        for x, v in system.original.items():
            exprs[("X0", str(x))] = sp.sympify(v)
    ck = _RandomPoints(coords, exprs, points, system.constraints, seed)

    def P(i, j):
        return ck.e[("P", i, j)]

    def grad(key):
        return [ck.d(key, m) for m in range(n)]

    dH = grad("H")

    def Y(ev, i):  # (P dH)_i
        return sum((ev(P(i, j)) * ev(dH[j]) for j in range(n) if (i, j) in nonzero), sp.Integer(0))

    out = []
    for name in system.integrals:
        dF = grad(("F", name))

        def build(ev, dF=dF):
            return ev(ck.e["N"]) * sum((Y(ev, i) * ev(dF[i]) for i in range(n)), sp.Integer(0))

        out.append(_random_check(ck, f"first integral {name}: X(F) = 0", build))
    for a, b in pairs:
        da, db = grad(a), grad(b)

        def build(ev, da=da, db=db):
            return sum((ev(da[i]) * ev(P(i, j)) * ev(db[j]) for (i, j) in nonzero), sp.Integer(0))

        out.append(_random_check(ck, f"involution {{{_label(a)}, {_label(b)}}} = 0", build))
    if system.original is not None:
        def build(ev):
            return sp.Matrix([ev(ck.e["N"]) * Y(ev, i) - ev(ck.e[("X0", str(x))])
                              for i, x in enumerate(coords)])

        out.append(_random_check(ck, "X = N P dH reproduces the original equations of motion",
                                 _vector(build)))
    if system.measure is not None:
        rhoN = ck.e["rho"] * ck.e["N"]
        d_rhoN = [ck.dexpr(rhoN, m) for m in range(n)]

        def build(ev):
            # div(rho N P dH) = sum_i d_i(rho N) (P dH)_i + rho N sum_ij d_i P_ij d_j H
            total = sum((ev(d_rhoN[i]) * Y(ev, i) for i in range(n)), sp.Integer(0))
            inner = sum((ev(ck.d(("P", i, j), i)) * ev(dH[j]) for (i, j) in nonzero),
                        sp.Integer(0))
            return total + ev(rhoN) * inner

        out.append(_random_check(ck, f"invariant measure rho = {_short(system.measure)}: "
                                     "div(rho X) = 0", build))
    return out


def _label(key: Any) -> str:
    return "H" if key == "H" else key[1]


def _proportional(F: sp.Expr, H: sp.Expr, coords: Sequence[sp.Symbol], has_f: bool) -> bool:
    """Whether ``F = c H`` for a constant ``c`` (then ``{F, H} = 0`` is trivial): tested at two
    random points in floating point; only used to skip redundant checks."""
    F, H = sp.sympify(F), sp.sympify(H)
    if F == 0 or H == 0:
        return False
    if has_f:
        return sp.simplify(F / H).is_number
    rng = random.Random(1)
    syms = sorted(F.free_symbols | H.free_symbols | set(coords), key=str)
    ratios = []
    for _ in range(2):
        pt = {x: sp.Float(rng.uniform(-0.5, 0.5)) for x in syms}
        h = complex(H.xreplace(pt).evalf())
        if abs(h) < 1e-12:
            return False
        ratios.append(complex(F.xreplace(pt).evalf()) / h)
    return abs(ratios[0] - ratios[1]) < 1e-9 * max(1.0, abs(ratios[0]))


def _vector(build):
    """Wrap a builder returning a column so that it fails if any component is nonzero: the zero
    test is applied to ``sum_i t**i * component_i`` in a fresh symbol ``t`` (a polynomial in
    ``t`` vanishes iff every coefficient does)."""
    t = sp.Symbol("_t")

    def combined(ev):
        col = build(ev)
        return sum((t**i * c for i, c in enumerate(col)), sp.Integer(0))

    return combined


def format_report(report: Mapping[str, Any]) -> str:
    """Human-readable report in the style of seed 000's Maple worksheet."""
    lines = [f"=== {report['name']} ===", report.get("doc", ""),
             "coordinates: " + ", ".join(report["coordinates"])]
    if report.get("parameters"):
        lines.append("parameters: " + ", ".join(f"{k} = {v}" for k, v in report["parameters"].items()))
    lines.append(f"Hamiltonian H = {report['hamiltonian']}")
    lines.append(f"multiplier N = {report['multiplier']}   (xdot = N P dH)")
    lines.append("brackets of the variables:")
    for k, v in report["brackets"].items():
        lines.append(f"  {k} = {v}")
    if report.get("equations"):
        lines.append("equations of motion:")
        for k, v in report["equations"].items():
            lines.append(f"  {k} = {v}")
    lines.append("conservation laws: Casimirs " + ", ".join(report["casimirs"])
                 + "; integrals " + ", ".join(report["integrals"]))
    for c in report["checks"]:
        status = "OK" if c["ok"] else "FAILED"
        extra = f" [{c['detail']}]" if c["detail"] else ""
        lines.append(f"{c['claim']}: {status}  ({c['method']}, {c['seconds']} s){extra}")
    lines.append(f"all claims: {'OK' if report['ok'] else 'NOT ALL OK'} ({report['seconds']} s)")
    return "\n".join(lines)


def jacobiator(matrix: sp.Matrix, coords: Sequence[sp.Symbol]) -> dict[tuple[int, int, int], sp.Expr]:
    """``Jac^{ijk} = sum_m (P^{im} d_m P^{jk} + P^{jm} d_m P^{ki} + P^{km} d_m P^{ij})``
    for every ``i < j < k`` (FORMULAS.md §0; ``[P, P] = 2 Jac``), expanded, from the core's
    :func:`poissonkit.structure.jacobi.jacobiator_terms` (triples it skips are zero)."""
    terms = jacobiator_terms(Bivector.from_matrix(sp.Matrix(matrix), tuple(coords)))
    return {key: sp.expand(terms.get(key, sp.Integer(0)))
            for key in itertools.combinations(range(len(coords)), 3)}
