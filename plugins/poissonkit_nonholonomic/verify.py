"""Verification of the survey's claims for a :class:`~poissonkit.structure.HamiltonianSystem`.

:func:`verify_system` checks, with exact arithmetic, every claim a system carries:

* the Jacobi identity ``[P, P] = 0`` (components ``Jac^{ijk}``, FORMULAS.md §0);
* each Casimir ``C``: ``P dC = 0``;
* each first integral ``F``: ``X(F) = 0`` with ``X = N P dH``;
* the integrals (and ``H``) pairwise in involution, ``{F, G} = 0``;
* ``X = N P dH`` reproduces the original equations of motion;
* the invariant measure ``rho``: ``div(rho X) = 0``;
* extra, system-specific claims (:mod:`poissonkit_nonholonomic.claims`), e.g. the BMF
  decomposition (55) or the Chaplygin–Veselova equivalence (Prop. 4).

Square roots (``g``) are handled by :mod:`poissonkit_nonholonomic.algebra`. ``mode="exact"`` is a
symbolic proof; ``mode="random"`` tests exact identities at random rational points (a false
positive has probability at most ``D / (2 * 10**6 + 1)`` per point, ``D`` the degree of the
numerator); ``"auto"`` uses exact mode when the system contains undefined functions (random
points cannot evaluate them) and random mode otherwise. An identity that fails on ``R^n`` is
re-tested on the constraint set (``(gamma, gamma) = 1``) and reported as such.

:func:`format_report` prints a report in the style of seed 000's Maple worksheet.
"""

from __future__ import annotations

import itertools
import time
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import sympy as sp

from poissonkit.errors import InputError
from poissonkit.structure.system import HamiltonianSystem
from poissonkit_nonholonomic.algebra import (
    PointSampler,
    Radicals,
    extract_radicals,
    vanishes,
)

__all__ = ["Checker", "format_report", "verify_system"]

_MAX_STR = 240


def _short(expr: Any) -> str:
    text = str(expr)
    return text if len(text) <= _MAX_STR else text[: _MAX_STR - 3] + "..."


class Checker:
    """Exact zero tests of expressions built from one system's pieces.

    Parameters
    ----------
    coords
        Coordinates.
    exprs
        Named expressions (keys are arbitrary hashables) sharing radicals; they are stored in
        radical-symbol form (``self.e[key]``).
    mode
        ``"exact"`` or ``"random"``.
    points
        Number of random points in random mode.
    constraints
        Constraint expressions for on-shell re-tests.
    """

    def __init__(self, coords: Sequence[sp.Symbol], exprs: Mapping[Any, sp.Expr], mode: str,
                 points: int = 3, constraints: Sequence[sp.Expr] = (), seed: int = 20140301):
        self.coords = tuple(coords)
        keys = list(exprs)
        converted, self.rad = extract_radicals([exprs[k] for k in keys])
        self.e = dict(zip(keys, converted))
        self.mode = mode
        self.points = points
        self.constraints = tuple(constraints)
        self.seed = seed
        self.has_functions = any(x.atoms(sp.core.function.AppliedUndef) for x in converted)
        if mode == "random" and self.has_functions:
            raise InputError("random mode cannot evaluate undefined functions; use mode='exact'")
        syms = set().union(*(x.free_symbols for x in converted)) if converted else set()
        self.extra = sorted(syms - set(self.coords) - set(self.rad.roots), key=str)
        self._deriv: dict[tuple[Any, int], sp.Expr] = {}
        self._point_cache: dict[tuple[int, bool], list[dict]] = {}

    # -------------------------------------------------------------- derivatives
    def d(self, key: Any, m: int) -> sp.Expr:
        """Cached derivative of the stored expression ``key`` along coordinate ``m``."""
        if (key, m) not in self._deriv:
            self._deriv[(key, m)] = self.rad.derivative(self.e[key], self.coords[m])
        return self._deriv[(key, m)]

    def dexpr(self, f: sp.Expr, m: int) -> sp.Expr:
        """Derivative of an arbitrary radical-form expression."""
        return self.rad.derivative(f, self.coords[m])

    # -------------------------------------------------------------- evaluation
    def _points(self, on_shell: bool) -> list[dict]:
        key = (self.points, on_shell)
        if key not in self._point_cache:
            sampler = PointSampler(self.coords + tuple(self.extra),
                                   self.constraints if on_shell else (), seed=self.seed)
            pts = []
            for _ in range(self.points):
                p = sampler.draw()
                local = {s: sp.sympify(Q).subs(p) for s, Q in self.rad.roots.items()}
                pts.append({"point": p, "radicals": Radicals(local), "cache": {}})
            self._point_cache[key] = pts
        return self._point_cache[key]

    def zero(self, build: Callable[[Callable[[sp.Expr], sp.Expr]], sp.Expr],
             on_shell: bool = False) -> tuple[bool, sp.Expr | None]:
        """Whether ``build(ev)`` vanishes; ``ev`` maps a radical-form expression to its value.

        In exact mode ``ev`` is the identity (or the on-shell substitution); in random mode it
        substitutes the point. Returns ``(ok, witness)`` with a nonzero value when it fails.
        """
        if self.mode == "exact":
            if on_shell:
                sub = _shell_substitution(self.coords, self.constraints)
                value = build(lambda f: sp.sympify(f).subs(sub))
            else:
                value = build(lambda f: f)
            ok = vanishes(value, self.rad)
            return ok, None if ok else self.rad.restore(value)
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


def _shell_substitution(coords, constraints) -> dict:
    """Exact on-shell substitution: ``gamma`` on the unit sphere via inverse stereographic
    projection in new symbols ``u, v``; linear constraints solved for one coordinate."""
    sub: dict = {}
    u, v = sp.symbols("_u _v", real=True)
    for c in constraints:
        c = sp.expand(c)
        vars_ = [x for x in coords if c.has(x)]
        if len(vars_) == 3 and sp.expand(c - sum(x**2 for x in vars_) + 1) == 0:
            n = 1 + u**2 + v**2
            sub.update(dict(zip(vars_, (2 * u / n, 2 * v / n, (1 - u**2 - v**2) / n))))
        else:
            for x in vars_:
                if sp.degree(c, x) == 1:
                    sub[x] = sp.solve(c, x)[0]
                    break
    return sub


# ---------------------------------------------------------------------- the checks
def _result(claim: str, ok: bool, method: str, seconds: float, detail: str = "",
            on_shell: bool = False) -> dict[str, Any]:
    return {"claim": claim, "ok": bool(ok), "method": method, "seconds": round(seconds, 3),
            "detail": detail, "on_constraint_set": on_shell}


def _check(ck: Checker, claim: str, build, constraints_ok: bool = True) -> dict[str, Any]:
    t0 = time.perf_counter()
    method = "exact (symbolic)" if ck.mode == "exact" else \
        f"exact arithmetic at {ck.points} random rational points"
    ok, witness = ck.zero(build)
    on_shell = False
    if not ok and constraints_ok and ck.constraints:
        ok2, witness2 = ck.zero(build, on_shell=True)
        if ok2:
            ok, on_shell = True, True
    detail = "" if ok else f"nonzero: {_short(witness)}"
    if on_shell:
        detail = "holds only on the constraint set " + ", ".join(f"{c} = 0" for c in ck.constraints)
    return _result(claim, ok, method, time.perf_counter() - t0, detail, on_shell)


def _jacobi(ck: Checker, n: int, nonzero: set) -> tuple[bool, list[str], float, str]:
    """All components ``Jac^{ijk}``; returns (ok, failing components, seconds, method)."""
    t0 = time.perf_counter()
    failures: list[str] = []

    def P(i, j):
        return ck.e[("P", i, j)] if (i, j) in nonzero else sp.Integer(0)

    def dP(i, j, m):
        return ck.d(("P", i, j), m) if (i, j) in nonzero else sp.Integer(0)

    for i, j, k in itertools.combinations(range(n), 3):
        def build(ev, i=i, j=j, k=k):
            total = sp.Integer(0)
            for m in range(n):
                for (a, bc) in ((i, (j, k)), (j, (k, i)), (k, (i, j))):
                    if (a, m) in nonzero and bc in nonzero:
                        total += ev(P(a, m)) * ev(dP(bc[0], bc[1], m))
            return total

        ok, witness = ck.zero(build)
        if not ok:
            c = ck.coords
            failures.append(f"Jac({c[i]},{c[j]},{c[k]}) = {_short(witness)}")
    method = "exact (symbolic)" if ck.mode == "exact" else \
        f"exact arithmetic at {ck.points} random rational points"
    return not failures, failures, time.perf_counter() - t0, method


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
        Whether to check the Jacobi identity (the most expensive check).
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
    """
    if not isinstance(system, HamiltonianSystem):
        raise InputError(f"verify_system needs a HamiltonianSystem, got {type(system).__name__}")
    if mode not in ("auto", "exact", "random"):
        raise InputError(f"mode must be 'auto', 'exact' or 'random', got {mode!r}")
    t_start = time.perf_counter()
    coords = system.coords
    n = len(coords)
    M = system.structure.matrix
    nonzero = {(i, j) for i in range(n) for j in range(n) if M[i, j] != 0}
    exprs: dict[Any, sp.Expr] = {("P", i, j): M[i, j] for (i, j) in nonzero}
    exprs["H"] = sp.sympify(system.hamiltonian)
    exprs["N"] = sp.sympify(system.multiplier)
    for name, C in system.casimirs.items():
        exprs[("C", name)] = sp.sympify(C)
    for name, F in system.integrals.items():
        exprs[("F", name)] = sp.sympify(F)
    if system.measure is not None:
        exprs["rho"] = sp.sympify(system.measure)
    if system.original is not None:
        for x, v in system.original.items():
            exprs[("X0", str(x))] = sp.sympify(v)
    has_f = any(sp.sympify(e).atoms(sp.core.function.AppliedUndef) for e in exprs.values())
    use = ("exact" if has_f else "random") if mode == "auto" else mode
    ck = Checker(coords, exprs, use, points, system.constraints, seed)

    def P(i, j):
        return ck.e[("P", i, j)] if (i, j) in nonzero else sp.Integer(0)

    def grad(key):
        return [ck.d(key, m) for m in range(n)]

    dH = grad("H")

    def Y(ev, i):  # (P dH)_i
        return sum((ev(P(i, j)) * ev(dH[j]) for j in range(n) if (i, j) in nonzero), sp.Integer(0))

    checks: list[dict[str, Any]] = []
    if jacobi:
        ok, fails, secs, method = _jacobi(ck, n, nonzero)
        checks.append(_result("Jacobi identity [P,P] = 0", ok, method, secs,
                              "" if ok else "; ".join(fails[:4])
                              + (f" (+{len(fails) - 4} more)" if len(fails) > 4 else "")))
    for name in system.casimirs:
        dC = grad(("C", name))

        def build(ev, dC=dC):
            # sum of squares would hide sign cancellations; test each component separately
            return sp.Matrix([sum((ev(P(i, j)) * ev(dC[j]) for j in range(n)
                                   if (i, j) in nonzero), sp.Integer(0)) for i in range(n)])

        checks.append(_check(ck, f"Casimir {name}: P dC = 0", _vector(build)))
    integral_keys = [("F", name) for name in system.integrals]
    for key in integral_keys:
        dF = grad(key)

        def build(ev, dF=dF):
            return ev(ck.e["N"]) * sum((Y(ev, i) * ev(dF[i]) for i in range(n)), sp.Integer(0))

        checks.append(_check(ck, f"first integral {key[1]}: X(F) = 0", build))
    inv = [k for k in integral_keys if not _proportional(ck, ck.e[k], ck.e["H"])] + ["H"]
    for a, b in itertools.combinations(inv, 2):
        da, db = (dH if a == "H" else grad(a)), (dH if b == "H" else grad(b))

        def build(ev, da=da, db=db):
            return sum((ev(da[i]) * ev(P(i, j)) * ev(db[j]) for (i, j) in nonzero), sp.Integer(0))

        na = "H" if a == "H" else a[1]
        nb = "H" if b == "H" else b[1]
        checks.append(_check(ck, f"involution {{{na}, {nb}}} = 0", build))
    if system.original is not None:
        def build(ev):
            return sp.Matrix([ev(ck.e["N"]) * Y(ev, i) - ev(ck.e[("X0", str(x))])
                              for i, x in enumerate(coords)])

        checks.append(_check(ck, "X = N P dH reproduces the original equations of motion",
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

        checks.append(_check(ck, f"invariant measure rho = {_short(system.measure)}: "
                                 "div(rho X) = 0", build))
    if extra:
        from poissonkit_nonholonomic.claims import CLAIMS

        for claim in CLAIMS.get(system.name, ()):
            t0 = time.perf_counter()
            ok, detail, method = claim(system)
            checks.append(_result(claim.__doc__.strip().splitlines()[0], ok, method,
                                  time.perf_counter() - t0, detail))
    brackets = {f"{{{coords[i]},{coords[j]}}}": _short(M[i, j])
                for i in range(n) for j in range(i + 1, n) if (i, j) in nonzero}
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


def _proportional(ck: Checker, F: sp.Expr, H: sp.Expr) -> bool:
    """Whether ``F = c H`` for a constant ``c`` (then ``{F, H} = 0`` is trivial): tested at two
    random points in floating point; only used to skip redundant checks."""
    if ck.has_functions:
        return sp.simplify(F / H).is_number if F != 0 and H != 0 else False
    import random

    rng = random.Random(1)
    ratios = []
    syms = list(ck.coords) + list(ck.extra)
    for _ in range(2):
        pt = {x: sp.Float(rng.uniform(-0.5, 0.5)) for x in syms}
        pt.update({s: sp.sqrt(sp.sympify(Q).xreplace(pt)) for s, Q in ck.rad.roots.items()})
        h = complex(sp.sympify(H).xreplace(pt).evalf())
        if abs(h) < 1e-12:
            return False
        ratios.append(complex(sp.sympify(F).xreplace(pt).evalf()) / h)
    return abs(ratios[0] - ratios[1]) < 1e-9 * max(1.0, abs(ratios[0]))


def _vector(build):
    """Wrap a builder returning a column so that it fails if any component is nonzero.

    The components are combined with independent random-ish weights would be unsafe; instead
    the zero test is applied to the sum of ``t**i * component_i`` in a fresh symbol ``t`` (a
    polynomial in ``t`` vanishes iff every coefficient does).
    """
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
    """Symbolic ``Jac^{ijk} = sum_m (P^{im} d_m P^{jk} + P^{jm} d_m P^{ki} + P^{km} d_m P^{ij})``
    for ``i < j < k`` (FORMULAS.md §0; ``[P, P] = 2 Jac``), square roots restored."""
    n = len(coords)
    conv, rad = extract_radicals(list(matrix))
    P = sp.Matrix(n, n, conv)
    out = {}
    for i, j, k in itertools.combinations(range(n), 3):
        total = sp.Integer(0)
        for m in range(n):
            total += P[i, m] * rad.derivative(P[j, k], coords[m]) \
                + P[j, m] * rad.derivative(P[k, i], coords[m]) \
                + P[k, m] * rad.derivative(P[i, j], coords[m])
        out[(i, j, k)] = rad.restore(sp.expand(total))
    return out
