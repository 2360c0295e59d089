"""Verification of the survey's claims for a :class:`~poissonkit.structure.HamiltonianSystem`.

:func:`verify_system` checks every claim a system carries, through the symbolic core
(:mod:`poissonkit.structure`):

* the Jacobi identity ``[P, P] = 0`` (components ``Jac^{ijk}``, docs/conventions.md):
  :func:`poissonkit.structure.verification.jacobi_verdict`;
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

The Jacobi identity is decided by the verify engine that also serves ``poissonkit verify`` and
:func:`poissonkit.verify` (:func:`poissonkit.structure.verification.jacobi_verdict`, on the
constraint set when the system has constraints); this module adds the survey's own report.

Modes. ``"exact"`` is a symbolic proof of every claim. ``"random"`` runs the core's randomized
Jacobi check (exact arithmetic at random integer points, Schwartz–Zippel bound) and the core's
randomized field checks (``method="random"`` of :mod:`poissonkit.structure.checks`: integrals,
involution, equations, measure in exact arithmetic with exact square roots at seeded random
rational points, :mod:`poissonkit.structure.randompoints`; a failure is a genuine
counterexample point, a pass carries the false-positive bound shown in the report); Casimirs
are always proved exactly (cheap). ``"auto"`` (default) lets the core choose the Jacobi method
and proves the field claims exactly through the core, except for systems whose field is large
(the rolling-ball systems with ``g = sqrt(...)``, and above all the BMF bivector): there the
core's exact proof takes 0.5–50 s per claim against 0.01–0.3 s at random points, so those run
at random points (see :data:`AUTO_EXACT_OPS`). ``"random"`` cannot evaluate undefined
functions. An identity that fails on ``R^n`` is re-tested on the constraint set
(``(gamma, gamma) = 1``, random points on the sphere) and reported as such.

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
from poissonkit.structure.checks import (CheckResult, in_involution, is_conformally_hamiltonian,
                                         is_first_integral, is_invariant_measure)
from poissonkit.structure.jacobi import jacobiator_terms
from poissonkit.structure.randompoints import RandomPoints
from poissonkit.structure.system import HamiltonianSystem
from poissonkit.structure.verification import has_undefined_functions, jacobi_verdict

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


def _random_check(claim: str, run: Callable[[RandomPoints], CheckResult],
                  free: RandomPoints, shell: Callable[[], RandomPoints | None]) -> dict[str, Any]:
    """Run a core check at random points of ``R^n``, then (if it fails) on the constraint set."""
    t0 = time.perf_counter()
    res = run(free)
    on_shell = False
    on = shell() if not res.holds else None
    if on is not None:
        res2 = run(on)
        if res2.holds:
            res, on_shell = res2, True
    if on_shell:
        detail = _shell_note(on.constraints)
    elif res.holds:
        detail = ""
    else:
        at = ", ".join(f"{k} = {v}" for k, v in (res.point or {}).items())
        detail = ("nonzero: " + "; ".join(f"{k} = {_short(v)}" for k, v in res.failures[:4])
                  + (f" at {_short(at)}" if at else ""))
    method = (f"exact arithmetic at {res.trials} random rational points (poissonkit.structure, "
              f"method='random'; false-positive bound {res.false_positive_bound:.1e})")
    return _result(claim, res.holds, method, time.perf_counter() - t0, detail, on_shell)


def _jacobi_check(system: HamiltonianSystem, mode: str, points: int, seed: int,
                  almost_poisson: bool = False) -> dict[str, Any]:
    """The Jacobi claim by the verify engine's :func:`~poissonkit.structure.verification.
    jacobi_verdict` (what ``poissonkit verify`` and :func:`poissonkit.verify` run): exact,
    randomized, or in ``"auto"`` mode a large bracket at random points on the constraint set
    (the Routh sphere's ~48000 operations take ~10 s there). With ``almost_poisson`` the claim
    is that the identity *fails* (a bracket kept for integration only)."""
    t0 = time.perf_counter()
    res = jacobi_verdict(system.structure, mode, constraints=system.constraints,
                         trials=points, seed=seed)
    fails = [f"{k} = {_short(v)}" for k, v in res.failures.items()]
    if res.at_points:
        where = "on the constraint set " if system.constraints else ""
        method = (f"exact arithmetic at random rational points {where}(false-positive bound "
                  f"{res.false_positive_bound:.1e})")
    elif res.method == "exact":
        method = _EXACT
    else:
        method = (f"poissonkit.structure.check_jacobi at {res.trials} random integer points, "
                  f"exact arithmetic (false-positive bound {res.false_positive_bound:.1e})")
    detail = "" if res.is_poisson else "; ".join(fails[:4]) + (
        f" (+{len(fails) - 4} more)" if len(fails) > 4 else "")
    if almost_poisson:
        return _result("Jacobi identity fails (almost-Poisson bracket, as the entry states)",
                       not res.is_poisson, method, time.perf_counter() - t0,
                       detail or "P is Poisson after all")
    return _result("Jacobi identity [P,P] = 0", res.is_poisson, method,
                   time.perf_counter() - t0, detail)


def verify_system(system: HamiltonianSystem, *, mode: str = "auto", points: int = 3,
                  jacobi: bool = True, extra: bool = True, seed: int = 20140301,
                  almost_poisson: bool = False) -> dict[str, Any]:
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
    almost_poisson
        The system's bracket is deliberately not Poisson (registry tag ``"almost-poisson"``):
        the Jacobi claim is then that the identity fails.

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
    P = system.structure
    H = sp.sympify(system.hamiltonian)
    use, has_f = _method(system, mode)
    constraints = tuple(system.constraints)

    checks: list[dict[str, Any]] = []
    if jacobi:
        checks.append(_jacobi_check(system, mode, points, seed, almost_poisson))
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
        checks.extend(_exact_field_checks(system, pairs, funcs, constraints))
    else:
        checks.extend(_random_field_checks(system, pairs, funcs, points, seed))
    if extra:
        checks.extend(_extra_checks(system))
    return _report(system, use, checks, t_start)


def _method(system: HamiltonianSystem, mode: str) -> tuple[str, bool]:
    """``(method used, whether undefined functions occur)`` for ``mode``: ``"auto"`` picks
    the random method for large systems free of undefined functions."""
    M = system.structure.matrix
    H, N = sp.sympify(system.hamiltonian), sp.sympify(system.multiplier)
    pieces = [H, N, *system.casimirs.values(), *system.integrals.values(), *M]
    if system.measure is not None:
        pieces.append(system.measure)
    if system.original is not None:
        pieces.extend(system.original.values())
    has_f = has_undefined_functions(pieces)
    if mode == "random" and has_f:
        raise InputError("random mode cannot evaluate undefined functions; use mode='exact'")
    if mode == "auto":
        size = sum(sp.count_ops(e) for e in M if e != 0) + sp.count_ops(H) + sp.count_ops(N)
        return ("random" if not has_f and size > AUTO_EXACT_OPS else "exact"), has_f
    return mode, has_f


def _exact_field_checks(system: HamiltonianSystem, pairs, funcs: Mapping[Any, sp.Expr],
                        constraints: tuple[sp.Expr, ...]) -> list[dict[str, Any]]:
    """Integrals, involution, equations and measure proved exactly (on the constraint set
    where the system has one, see :func:`_core_check`)."""
    coords = system.coords
    P = system.structure
    H, N = sp.sympify(system.hamiltonian), sp.sympify(system.multiplier)
    checks: list[dict[str, Any]] = []
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
    return checks


def _extra_checks(system: HamiltonianSystem) -> list[dict[str, Any]]:
    """The system-specific claims of :mod:`poissonkit_nonholonomic.claims`."""
    from poissonkit_nonholonomic.claims import CLAIMS

    checks: list[dict[str, Any]] = []
    for claim in CLAIMS.get(system.name, ()):
        t0 = time.perf_counter()
        ok, detail, method = claim(system)
        checks.append(_result(claim.__doc__.strip().splitlines()[0], ok, method,
                              time.perf_counter() - t0, detail))
    return checks


def _report(system: HamiltonianSystem, use: str, checks: list[dict[str, Any]],
            t_start: float) -> dict[str, Any]:
    """The JSON-able report of :func:`verify_system` (see its Returns)."""
    coords = system.coords
    n = len(coords)
    M = system.structure.matrix
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


def _random_field_checks(system: HamiltonianSystem, pairs, funcs, points: int,
                         seed: int) -> list[dict[str, Any]]:
    """Integrals, involution, equations and measure by the core's ``method="random"`` (large
    systems, where the exact proof is 50–300x slower; see the module docstring). One point set
    on ``R^n`` and one on the constraint set are shared by all claims (memoised values of
    ``P``, ``dH``, ...)."""
    coords = system.coords
    free = RandomPoints(coords, trials=points, seed=seed)
    cache: list[RandomPoints | None] = []

    def shell() -> RandomPoints | None:
        if not cache:
            cache.append(RandomPoints(coords, system.constraints, trials=points, seed=seed)
                         if system.constraints else None)
        return cache[0]

    P = system.structure
    out = []
    for name, F in system.integrals.items():
        out.append(_random_check(
            f"first integral {name}: X(F) = 0",
            lambda pts, F=F: is_first_integral(system, F, method="random", points=pts),
            free, shell))
    for a, b in pairs:
        out.append(_random_check(
            f"involution {{{_label(a)}, {_label(b)}}} = 0",
            lambda pts, a=a, b=b: in_involution(P, _pair(a, b, funcs), method="random",
                                                points=pts),
            free, shell))
    if system.original is not None:
        out.append(_random_check(
            "X = N P dH reproduces the original equations of motion",
            lambda pts: is_conformally_hamiltonian(system.original, P, system.hamiltonian,
                                                   system.multiplier, method="random",
                                                   points=pts),
            free, shell))
    if system.measure is not None:
        out.append(_random_check(
            f"invariant measure rho = {_short(system.measure)}: div(rho X) = 0",
            lambda pts: is_invariant_measure(system, system.measure, method="random",
                                             points=pts),
            free, shell))
    return out


def _pair(a: Any, b: Any, funcs: Mapping[Any, sp.Expr]) -> dict[str, sp.Expr] | list[sp.Expr]:
    """The two functions named by their labels (a list if the labels coincide)."""
    la, lb = _label(a), _label(b)
    return {la: funcs[a], lb: funcs[b]} if la != lb else [funcs[a], funcs[b]]


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
    for every ``i < j < k`` (docs/conventions.md; ``[P, P] = 2 Jac``), expanded, from the core's
    :func:`poissonkit.structure.jacobi.jacobiator_terms` (triples it skips are zero)."""
    terms = jacobiator_terms(Bivector.from_matrix(sp.Matrix(matrix), tuple(coords)))
    return {key: sp.expand(terms.get(key, sp.Integer(0)))
            for key in itertools.combinations(range(len(coords)), 3)}
