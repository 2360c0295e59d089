"""The Jacobi verdict of a verify report: which method, and the JSON-ready result.

One decision serves ``poissonkit verify``, :func:`poissonkit.verify` and the non-holonomic
survey's :func:`poissonkit_nonholonomic.verify.verify_system`: a large bracket (more than
:data:`AUTO_POINTS_OPS` operations) under ``method="auto"``, or any bracket under
``method="random"`` with constraints, is checked at random rational points (on the constraint
set, if any; :func:`check_jacobi_at_points`); otherwise the core's
:func:`~poissonkit.structure.jacobi.check_jacobi` decides (exact, or at random integer points),
modulo the constraints when there are any.
"""

from __future__ import annotations

import itertools
import time
from collections.abc import Sequence
from dataclasses import dataclass, field

import sympy as sp

from poissonkit.structure.bivector import Bivector

#: Above this many operations in ``P`` (``sympy.count_ops``), ``method="auto"`` checks Jacobi
#: at random rational points (on the constraint set, if any) instead of symbolically: the
#: Routh sphere's bracket (~48000 operations) took more than 39 min exactly modulo its
#: constraint, ~10 s at points.
AUTO_POINTS_OPS = 2500

__all__ = ["AUTO_POINTS_OPS", "JacobiVerdict", "check_jacobi_at_points", "has_undefined_functions",
           "jacobi_verdict"]

#: A JSON-ready Jacobi record (the ``"jacobi"`` entry of a verify report).
JacobiRecord = dict[str, object]


@dataclass(frozen=True)
class JacobiVerdict:
    """Outcome of :func:`jacobi_verdict`.

    Attributes
    ----------
    is_poisson
        Whether the identity holds (at the points, for a randomized check).
    method
        ``"exact"`` or ``"random"``.
    failures
        Non-zero components ``{"Jac(a, b, c)": value}`` (values as text).
    false_positive_bound
        Probability that a non-Poisson ``P`` passes (0 for exact).
    seconds
        Time taken.
    note
        How it was checked (points, seed, constraints).
    trials
        Random points used (0 for exact).
    at_points
        Checked by :func:`check_jacobi_at_points` (random rational points, on the constraint
        set if any) rather than by :func:`~poissonkit.structure.jacobi.check_jacobi`.
    """

    is_poisson: bool
    method: str
    failures: dict[str, str] = field(default_factory=dict)
    false_positive_bound: float | None = 0.0
    seconds: float = 0.0
    note: str = ""
    trials: int = 0
    at_points: bool = False

    def record(self) -> JacobiRecord:
        """The JSON-ready dict of a verify report: ``is_poisson``, ``method``, ``failures``,
        ``false_positive_bound``, ``seconds``, ``note``."""
        return {"is_poisson": self.is_poisson, "method": self.method,
                "failures": dict(self.failures),
                "false_positive_bound": self.false_positive_bound,
                "seconds": self.seconds, "note": self.note}


def has_undefined_functions(exprs: Sequence[sp.Expr] | sp.Matrix) -> bool:
    """Whether any expression contains an undefined function such as ``g(gamma)`` (random
    rational points cannot evaluate it)."""
    return any(sp.sympify(e).atoms(sp.core.function.AppliedUndef) for e in exprs)


def _at_points(P: Bivector, constraints: Sequence[sp.Expr], trials: int,
               seed: int | None) -> JacobiVerdict:
    from poissonkit.structure.checks import check_vanishing
    from poissonkit.structure.randompoints import RandomPoints

    t0 = time.perf_counter()
    X, M, n = P.coords, P.matrix, P.dim
    pts = RandomPoints(X, tuple(constraints), trials=trials, seed=seed)

    def term(a: int, b: int, c: int) -> sp.Expr:
        if M[b, c] == 0:
            return sp.Integer(0)
        return sp.Add(*[M[a, m] * pts.derivative(M[b, c], X[m]) for m in range(n)
                        if M[a, m] != 0])

    comps = {f"Jac({X[i]}, {X[j]}, {X[k]})": term(i, j, k) + term(j, k, i) + term(k, i, j)
             for i, j, k in itertools.combinations(range(n), 3)}
    comps = {k: v for k, v in comps.items() if v != 0}
    res = check_vanishing(comps or [sp.Integer(0)], method="random", points=pts)
    where = "on the constraint set " if constraints else ""
    at = ", ".join(f"{k} = {v}" for k, v in (res.point or {}).items())
    return JacobiVerdict(
        is_poisson=bool(res.holds), method="random",
        failures={k: str(v) for k, v in res.failures},
        false_positive_bound=res.false_positive_bound,
        seconds=round(time.perf_counter() - t0, 4),
        note=f"{res.trials} random rational point(s) {where}(seed {pts.seed}), exact "
             "arithmetic" + (f"; counterexample at {at}" if at else ""),
        trials=res.trials, at_points=True)


def check_jacobi_at_points(P: Bivector, constraints: Sequence[sp.Expr] = (), trials: int = 3,
                           seed: int | None = None) -> JacobiRecord:
    """Jacobi identity at random rational points (on the constraint set, if any), exactly.

    ``Jac^{ijk} = P^{im} d_m P^{jk} + cyclic`` (docs/conventions.md) with the derivatives taken at
    the points (:class:`~poissonkit.structure.randompoints.RandomPoints`, which also places the
    points on recognised constraint surfaces such as ``(gamma, gamma) = 1``). A non-zero value
    is an exact counterexample (a proof that ``P`` is not Poisson there); a pass carries the
    false-positive bound. Much faster than the symbolic Jacobiator of large brackets.

    Returns
    -------
    dict
        ``is_poisson``, ``method``, ``failures`` (``{"Jac(a, b, c)": value}``),
        ``false_positive_bound``, ``seconds``, ``note``.
    """
    return _at_points(P, constraints, trials, seed).record()


def jacobi_verdict(P: Bivector, method: str = "auto", *, constraints: Sequence[sp.Expr] = (),
                   trials: int = 3, seed: int | None = None) -> JacobiVerdict:
    """The Jacobi identity of ``P`` by the method a verify report uses.

    Parameters
    ----------
    P
        The bivector.
    method
        ``"auto"``, ``"exact"`` or ``"random"``. ``"auto"`` checks a bracket of more than
        :data:`AUTO_POINTS_OPS` operations at random rational points and lets
        :func:`~poissonkit.structure.jacobi.check_jacobi` choose otherwise; ``"random"`` with
        constraints uses random rational points on the constraint set. Brackets with undefined
        functions never go to random rational points.
    constraints
        Expressions vanishing on the phase space (the identity is checked there).
    trials
        Random points.
    seed
        Seed of the random points; ``None`` is seed 0 at random rational points (reports are
        reproducible) and a fresh seed in ``check_jacobi``.

    Returns
    -------
    JacobiVerdict
    """
    from poissonkit.structure.jacobi import check_jacobi

    constraints = tuple(constraints)
    big = sum(sp.count_ops(e) for e in P.matrix if e != 0) > AUTO_POINTS_OPS
    if not has_undefined_functions(P.matrix) and (
            method == "random" and constraints or method == "auto" and big):
        return _at_points(P, constraints, trials, 0 if seed is None else seed)
    res = check_jacobi(P, method=method, seed=seed, constraints=constraints, trials=trials)
    return JacobiVerdict(
        is_poisson=res.is_poisson, method=res.method,
        failures={k: str(v) for k, v in res.named_failures().items()},
        false_positive_bound=res.false_positive_bound, seconds=round(res.seconds, 4),
        note=res.note, trials=res.trials)
