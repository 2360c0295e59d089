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

from poissonkit.contracts import (CompiledFunction, CompiledKernels, Event, HasCompiledKernels,
                                  System)
from poissonkit.errors import InputError
from poissonkit.numerics.integrators.base import RawResult
from poissonkit.numerics.integrators.capabilities import MIDPOINT
from poissonkit.numerics.integrators.driver import Control
from poissonkit.numerics.integrators.glue import describe, fixed_grid
from poissonkit.numerics.integrators.implicit import (ImplicitMethod, ImplicitRun, drive_implicit,
                                                      implicit_loop)
from poissonkit.numerics.integrators.newton import near_state
from poissonkit.numerics.jit import jit
from poissonkit.numerics.kernels import copy_into
from poissonkit.traits import offers

_runners: dict[int, tuple[CompiledFunction, CompiledKernels]] = {}


@jit(inline="always")
def _scratch(n, f, c, extra):
    return (f,)


@jit(inline="always")
def _guess(Z, y, f, h):
    # explicit Euler as the start, and no state scale in the stopping test
    for i in range(y.shape[0]):
        Z[i] = y[i] + h * f[i]
    return 0.0


@jit(inline="always")
def _accept(Z, y, c):
    copy_into(Z, y)


def _runner(kernels: CompiledKernels) -> CompiledFunction:
    key = id(kernels.rhs)
    hit = _runners.get(key)
    if hit is not None:
        return hit[0]
    rhs = kernels.rhs

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

    run = implicit_loop(kernels, ImplicitMethod(residual, near_state, False, _scratch, _guess,
                                                _accept, compensated=False))
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
        y = np.array(y0, dtype=float)
        spec = ImplicitRun(self.name, "iteration", itol, self.max_iterations, newton, (),
                           describe(self.name, h, t0, t_end, n_total, save_every, y,
                                    tol=float(itol).hex(), newton=bool(newton)))
        return drive_implicit(_runner(kernels), spec, False, system, y, t0, t_end, h, n_total,
                              events, progress, save_every, control)

