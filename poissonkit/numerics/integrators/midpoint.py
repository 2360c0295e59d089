"""Implicit midpoint rule ``y_{n+1} = y_n + h f((y_n + y_{n+1})/2)``, compiled.

Symmetric, order 2, and it preserves every quadratic invariant of the flow exactly (up to the
solver tolerance): ``|ν|²``, ``(ν, m)``, angular momentum, the Casimirs of Lie–Poisson
brackets. It needs only ``f`` (and, for Newton's method, the Jacobian), so it runs any system of
:func:`~poissonkit.numerics.compile_system`, including deformed brackets with multipliers, and
the N-body systems (fixed-point iteration there).
"""

from __future__ import annotations

import math
from typing import Any

import numba
import numpy as np

from poissonkit.errors import InputError, IntegrationError, NonFiniteStateError
from poissonkit.numerics.events import event_thresholds, raise_or_record
from poissonkit.numerics.integrators.base import (
    COLLISION,
    DONE,
    ESCAPE,
    NO_CONVERGENCE,
    NONFINITE,
    RawResult,
    SaveBuffer,
    check_step,
    locate_division,
    progress_bar,
)
from poissonkit.numerics.kernels import all_finite, copy_into, copy_row, gauss_solve


@numba.njit(error_model="numpy")
def _nojac(y, data, work, out):
    return


_runners: dict[int, Any] = {}


def _runner(kernels) -> Any:
    key = id(kernels.rhs)
    hit = _runners.get(key)
    if hit is not None:
        return hit[0]
    rhs = kernels.rhs
    jac = kernels.jac if kernels.jac is not None else _nojac
    min_distance, max_radius = kernels.min_distance, kernels.max_radius

    @numba.njit(error_model="numpy")
    def run(y, t0, h, n_total, tol, maxiter, newton, data, work, save_every, step0, max_steps,
            out_t, out_y, contact, escape):
        n = y.shape[0]
        f = np.empty(n)
        Y = np.empty(n)
        mid = np.empty(n)
        G = np.empty(n)
        J = np.empty((n, n))
        A = np.empty((n, n))
        delta = np.empty(n)
        nsave = 0
        nfev = 0
        for k in range(max_steps):
            gstep = step0 + k + 1
            rhs(y, data, work, f)
            nfev += 1
            for i in range(n):
                Y[i] = y[i] + h * f[i]
            ok = False
            prev = np.inf
            for it in range(maxiter):
                for i in range(n):
                    mid[i] = 0.5 * (y[i] + Y[i])
                rhs(mid, data, work, f)
                nfev += 1
                for i in range(n):
                    G[i] = Y[i] - y[i] - h * f[i]
                if newton:
                    jac(mid, data, work, J)
                    for i in range(n):
                        for j in range(n):
                            A[i, j] = -0.5 * h * J[i, j]
                        A[i, i] += 1.0
                    if not gauss_solve(A, G, delta):
                        return 6, t0 + gstep * h, k + 1, nsave, nfev, 0.0
                else:
                    copy_into(G, delta)
                dn = 0.0
                yn = 0.0
                for i in range(n):
                    Y[i] -= delta[i]
                    dn = max(dn, abs(delta[i]))
                    yn = max(yn, abs(Y[i]))
                if not math.isfinite(dn):
                    break
                if dn <= tol * (1.0 + yn):
                    ok = True
                    break
                # round-off floor: the correction stopped shrinking while already tiny
                if dn >= prev and dn <= 1e3 * tol * (1.0 + yn):
                    ok = True
                    break
                prev = dn
            t = t0 + gstep * h
            copy_into(Y, y)
            if not all_finite(y):
                return 1, t, k + 1, nsave, nfev, 0.0
            if not ok:
                return 6, t, k + 1, nsave, nfev, 0.0
            last = gstep >= n_total
            if contact > 0.0:
                d = min_distance(y, data, work)
                if d < contact:
                    out_t[nsave] = t
                    copy_row(y, out_y, nsave)
                    return 2, t, k + 1, nsave + 1, nfev, d
            if escape > 0.0:
                d = max_radius(y, data)
                if d > escape:
                    out_t[nsave] = t
                    copy_row(y, out_y, nsave)
                    return 3, t, k + 1, nsave + 1, nfev, d
            if last or gstep % save_every == 0:
                out_t[nsave] = t
                copy_row(y, out_y, nsave)
                nsave += 1
            if last:
                return 5, t, k + 1, nsave, nfev, 0.0
            if nsave == out_t.shape[0] - 1:
                return 4, t, k + 1, nsave, nfev, 0.0
        return 0, t0 + (step0 + max_steps) * h, max_steps, nsave, nfev, 0.0

    _runners[key] = (run, kernels)
    return run


class ImplicitMidpoint:
    """Implicit midpoint with Newton (if a Jacobian is available) or fixed-point iteration.

    Parameters
    ----------
    tol
        Iteration stops when ``max|ΔY| <= tol (1 + max|Y|)``; default ``1e-14``.
    max_iterations
        More iterations than this raise :class:`~poissonkit.errors.IntegrationError`.
    newton
        Use Newton's method when the system has a Jacobian.
    """

    family = "implicit"
    order = 2
    name = "midpoint"

    def __init__(self, tol: float = 1e-14, max_iterations: int = 50, newton: bool = True) -> None:
        if not tol > 0:
            raise InputError(f"midpoint tol must be > 0, got {tol!r}")
        if max_iterations < 1:
            raise InputError(f"max_iterations must be >= 1, got {max_iterations!r}")
        self.tol = float(tol)
        self.max_iterations = int(max_iterations)
        self.newton = bool(newton)

    def integrate(self, system: Any, y0: np.ndarray, t_end: float, *, step: float | None,
                  tol: float | None, events=(), progress: bool = False, save_every: int = 1,
                  t0: float = 0.0) -> RawResult:
        """Integrate with fixed step ``step``; ``tol`` overrides the iteration tolerance."""
        kernels = getattr(system, "kernels", None)
        if kernels is None:
            raise InputError(f"midpoint needs a compiled system, got {type(system).__name__}")
        h = check_step(step, t_end - t0, self.name)
        span = t_end - t0
        n_total = max(1, math.ceil(span / h - 1e-12))
        h = span / n_total
        itol = float(tol) if tol is not None else self.tol
        newton = self.newton and kernels.jac is not None
        contact, escape, cerr, eerr = event_thresholds(events)
        run = _runner(kernels)
        y = np.array(y0, dtype=float)
        data, work = system.data, system.work()
        buf = SaveBuffer(y.size, min(n_total // save_every + 2, 4096))
        buf.add(t0, y)
        bar = progress_bar(progress, span, self.name)
        chunk = max(1, n_total // 200) if progress else (1 << 62)
        steps, nfev, t, records = 0, 0, t0, []
        scratch = SaveBuffer(y.size, 4)

        def one_step(ys: np.ndarray, ts: float, done: int) -> tuple[int, float]:
            out = run(ys, t0, h, n_total, itol, self.max_iterations, newton, data, work,
                      save_every, done, 1, scratch.cur_t, scratch.cur_y, contact, escape)
            return out[0], out[1]

        try:
            while True:
                start = y.copy()
                try:
                    status, t_new, k, nsave, nf, value = run(
                        y, t0, h, n_total, itol, self.max_iterations, newton, data, work,
                        save_every, steps, chunk, buf.cur_t, buf.cur_y, contact, escape)
                except ZeroDivisionError:
                    raise locate_division(self.name, one_step, start, t, steps) from None
                buf.commit(nsave)
                if bar is not None:
                    bar.update(t_new - t)
                steps += k
                nfev += nf
                t = t_new
                if status == NONFINITE:
                    raise NonFiniteStateError(steps, t, "midpoint produced NaN/inf")
                if status == NO_CONVERGENCE:
                    raise IntegrationError(
                        f"midpoint: iteration did not converge to {itol:g} in "
                        f"{self.max_iterations} iterations at step {steps} (t = {t:.6g}); "
                        "reduce the step")
                if status in (COLLISION, ESCAPE):
                    kind = "collision" if status == COLLISION else "escape"
                    raise_or_record(kind, steps, t, value, cerr if status == COLLISION else eerr,
                                    records)
                    break
                if status == DONE:
                    break
        finally:
            if bar is not None:
                bar.close()
        ts, ys = buf.arrays()
        return RawResult(ts, ys, steps, nfev=nfev, events=records,
                         message="event" if records else "done",
                         extra={"step": h, "newton": newton})
