"""Implicit midpoint rule ``y_{n+1} = y_n + h f((y_n + y_{n+1})/2)``, compiled.

Symmetric, order 2, and it preserves every quadratic invariant of the flow exactly (up to the
solver tolerance): ``|ν|²``, ``(ν, m)``, angular momentum, the Casimirs of Lie–Poisson
brackets. It needs only ``f`` (and, for Newton's method, the Jacobian), so it runs any system of
:func:`~poissonkit.numerics.compile_system`, including deformed brackets with multipliers, and
the N-body systems (fixed-point iteration there).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from poissonkit.contracts import (
    CompiledFunction,
    CompiledKernels,
    Event,
    HasCompiledKernels,
    System,
)
from poissonkit.errors import InputError, IntegrationError
from poissonkit.numerics.events import event_thresholds
from poissonkit.numerics.integrators.base import (
    NO_CONVERGENCE,
    RUNNING,
    RawResult,
    SaveBuffer,
    step_end_kernels,
    step_tail,
)
from poissonkit.numerics.integrators.capabilities import MIDPOINT
from poissonkit.numerics.integrators.driver import (
    Control,
    LoopProblem,
    LoopState,
    drive,
)
from poissonkit.numerics.integrators.glue import (
    ChunkResult,
    Scratch,
    describe,
    fixed_grid,
    guard_division,
)
from poissonkit.numerics.integrators.newton import (
    CONVERGED,
    SINGULAR,
    near_state,
    newton_solver,
    no_jacobian,
)
from poissonkit.numerics.jit import jit
from poissonkit.numerics.kernels import copy_into
from poissonkit.traits import offers

_runners: dict[int, tuple[CompiledFunction, CompiledKernels]] = {}


def _runner(kernels: CompiledKernels) -> CompiledFunction:
    key = id(kernels.rhs)
    hit = _runners.get(key)
    if hit is not None:
        return hit[0]
    rhs = kernels.rhs
    jac = kernels.jac if kernels.jac is not None else no_jacobian
    remember = step_end_kernels(kernels)[0]
    tail = step_tail(kernels)

    @jit(inline="always")
    def residual(Z, y, h, mid, G, data, work, args):
        # G(Y) = Y − y − h f((y + Y)/2)
        f = args[0]
        n = Z.shape[0]
        for i in range(n):
            mid[i] = 0.5 * (y[i] + Z[i])
        rhs(mid, data, work, f)
        for i in range(n):
            G[i] = Z[i] - y[i] - h * f[i]

    solve = newton_solver(residual, jac, near_state, simplified=False)

    @jit
    def run(y, t0, h, n_total, tol, maxiter, newton, data, work, save_every, step0, max_steps,
            out_t, out_y, contact, escape, watch, back1, back2, hist):
        n = y.shape[0]
        f = np.empty(n)
        Y = np.empty(n)
        mid = np.empty(n)
        G = np.empty(n)
        J = np.empty((n, n))
        A = np.empty((n, n))
        delta = np.empty(n)
        piv = np.empty(n, dtype=np.int64)
        args = (f,)
        nsave = 0
        nfev = 0
        track = contact > 0.0 or escape > 0.0 or watch > 0.0
        for k in range(max_steps):
            gstep = step0 + k + 1
            if track:  # event-search memory, see poissonkit.numerics.locate
                remember(y, back1, back2, hist, t0 + (gstep - 1) * h)
            rhs(y, data, work, f)
            nfev += 1
            for i in range(n):
                Y[i] = y[i] + h * f[i]
            outcome, nf = solve(Y, y, h, tol, maxiter, newton, 0.0, data, work, args, mid, G, J,
                                A, piv, delta)
            nfev += nf
            if outcome == SINGULAR:
                return NO_CONVERGENCE, t0 + gstep * h, k + 1, nsave, nfev, 0.0
            ok = outcome == CONVERGED
            t = t0 + gstep * h
            copy_into(Y, y)
            last = gstep >= n_total
            status, nsave, value = tail(y, y, t, RUNNING if ok else NO_CONVERGENCE, last,
                                        last or gstep % save_every == 0, track, data, work,
                                        contact, escape, watch, hist, out_t, out_y, nsave)
            if status != RUNNING:
                return status, t, k + 1, nsave, nfev, value
        return RUNNING, t0 + (step0 + max_steps) * h, max_steps, nsave, nfev, 0.0

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

    family = MIDPOINT.family
    capabilities = MIDPOINT.capabilities
    order = MIDPOINT.order
    name = "midpoint"

    def __init__(self, tol: float = 1e-14, max_iterations: int = 50, newton: bool = True) -> None:
        if not tol > 0:
            raise InputError(f"midpoint tol must be > 0, got {tol!r}")
        if max_iterations < 1:
            raise InputError(f"max_iterations must be >= 1, got {max_iterations!r}")
        self.tol = float(tol)
        self.max_iterations = int(max_iterations)
        self.newton = bool(newton)

    def integrate(self, system: System, y0: np.ndarray, t_end: float, *, step: float | None,
                  tol: float | None, events: Sequence[Event] = (), progress: bool = False,
                  save_every: int = 1, t0: float = 0.0,
                  control: Control | None = None) -> RawResult:
        """Integrate with fixed step ``step``; ``tol`` overrides the iteration tolerance
        (``control``: checkpoints, streaming, stop requests, see
        :func:`~poissonkit.numerics.integrators.driver.drive`)."""
        if not offers(system, HasCompiledKernels):
            raise InputError(f"midpoint needs a compiled system, got {type(system).__name__}")
        kernels = system.kernels
        h, n_total = fixed_grid(self.name, step, t0, t_end)
        itol = float(tol) if tol is not None else self.tol
        newton = self.newton and kernels.jac is not None
        contact, escape, watch = event_thresholds(events)
        run = _runner(kernels)
        y = np.array(y0, dtype=float)
        data, work = system.data, system.work()
        scratch = Scratch(y.size)
        iters = self.max_iterations

        def chunk(st: LoopState, max_steps: int, buf: SaveBuffer) -> ChunkResult:
            return run(st.y, t0, h, n_total, itol, iters, newton, data, work, save_every,
                       st.steps, max_steps, buf.cur_t, buf.cur_y, contact, escape, watch,
                       st.prev, st.prev2, st.hist)

        def one_step(ys: np.ndarray, ts: float, done: int) -> tuple[int, float]:
            out = run(ys, t0, h, n_total, itol, iters, newton, data, work, save_every, done, 1,
                      scratch.t, scratch.y, 0.0, 0.0, 0.0, ys, ys, scratch.hist)
            return out[0], out[1]

        def advance(ys: np.ndarray, s: float) -> np.ndarray:
            yc = np.array(ys, dtype=float)
            status = run(yc, 0.0, s, 1, itol, iters, newton, data, work, 1, 0, 1, scratch.t,
                         scratch.y, 0.0, 0.0, 0.0, yc, yc, scratch.hist)[0]
            if status == NO_CONVERGENCE:
                raise IntegrationError("midpoint: iteration did not converge while locating an "
                                       "event")
            return yc

        def failure(status: int, st: LoopState) -> Exception | None:
            if status == NO_CONVERGENCE:
                return IntegrationError(
                    f"midpoint: iteration did not converge to {itol:g} in {iters} iterations "
                    f"at step {st.steps} (t = {st.t:.6g}); reduce the step")
            return None

        raw = drive(LoopProblem(
            self.name, system, y, t0, t_end,
            guard_division(self.name, chunk, lambda st: (one_step, st.y.copy())), advance,
            lambda st: st.steps >= n_total,
            describe(self.name, h, t0, t_end, n_total, save_every, y,
                     tol=float(itol).hex(), newton=bool(newton)),
            min(n_total // save_every + 2, 4096), events, progress, save_every, control,
            failure))
        raw.extra.update(step=h, newton=newton)
        return raw
