"""Energy-preserving discrete-gradient method for ``ẋ = N(x) P(x) ∇H(x)``, compiled.

One step solves ``x' = x + h S(x̄) ∇̄H(x, x')`` for ``x'``, with ``x̄ = (x + x')/2``, the skew
matrix ``S = N P`` at the midpoint and a *discrete gradient* ``∇̄H``: a function with
``∇̄H(x, x')·(x' − x) = H(x') − H(x)`` and ``∇̄H(x, x) = ∇H(x)`` (McLachlan, Quispel & Robidoux,
Phil. Trans. R. Soc. A 357 (1999) 1021). Because ``S`` is skew, ``H(x') − H(x) =
h ∇̄Hᵀ S ∇̄H = 0``: the energy is conserved up to round-off and the Newton residual, for any
bracket (constant, linear, quadratic, rational) and any multiplier ``N``. Both choices of
``∇̄H`` below are symmetric, so the method is symmetric and of order 2.

* ``"avf"`` — the average vector field ``∇̄H = ∫₀¹ ∇H(x + s(x' − x)) ds`` (Quispel & McLaren,
  J. Phys. A 41 (2008) 045206; for Poisson systems with ``S`` at the midpoint, Cohen & Hairer,
  BIT 51 (2011) 91). For a polynomial ``H`` of degree ``p`` the integrand is a polynomial of
  degree ``p − 1`` in ``s``, integrated exactly by Gauss–Legendre with ``⌈p/2⌉`` nodes (the
  degree is read from the symbolic ``H``).
* ``"gonzalez"`` — the midpoint discrete gradient ``∇̄H = ∇H(x̄) + (H(x') − H(x) − ∇H(x̄)·Δ)
  Δ/|Δ|²``, ``Δ = x' − x`` (Gonzalez, J. Nonlinear Sci. 6 (1996) 449), exact for any ``H``
  (roots, quotients, logarithms). ``H(x)`` in it is taken as the run's initial energy, equal
  to it in exact arithmetic: the computed ``H`` moves in steps of an ulp between neighbouring
  doubles, and with the computed ``H(x)`` those steps would add up as a random walk
  (``ε|H|√n`` after ``n`` steps); against the fixed level they do not add up.

``"auto"`` takes ``"avf"`` for polynomial ``H`` and ``"gonzalez"`` otherwise.

Casimirs: a Casimir ``C`` changes by ``C(x') − C(x)``; for ``C`` linear or quadratic this is
``∇C(x̄)·(x' − x) = h ∇C(x̄)ᵀ S(x̄) ∇̄H = 0``, so linear and quadratic Casimirs (``|m|²`` of
so(3), the quadratic Casimirs of any Lie–Poisson bracket, ``(γ, γ)`` and ``(γ, M)`` of the
Chaplygin ball) are conserved to round-off, as by the implicit midpoint rule. Casimirs of higher
degree or not polynomial (``x₁x₂x₃`` of Plank's bracket ``{xᵢ, xⱼ} = aᵢⱼ xᵢ xⱼ`` when ``a`` has
the kernel ``(1, 1, 1)``, ``Σ kᵢ ln xᵢ`` in general) are *not* conserved exactly: they drift at
the method's order, ``O(h²)``. Nothing projects them back.

The implicit equation is solved for the increment ``D = x' − x`` by simplified Newton: the
matrix ``I − (h/2) J(x̄)`` with the compiled field's Jacobian ``J`` at the predicted midpoint
(the midpoint rule's matrix; it differs from the exact Jacobian by ``O(h²)``, so the iteration
converges linearly at a rate ``O(h²)``) is factorised once per step, and the iteration runs to
a tolerance relative to ``D``. The state is accumulated with Kahan's compensated summation, so
its rounding does not add up over long runs. A step whose iteration does not converge raises
:class:`~poissonkit.errors.IntegrationError`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from poissonkit.contracts import (
    CompiledFunction,
    Event,
    HasCompiledKernels,
    HasSymbolicForm,
    System,
)
from poissonkit.errors import CapabilityError, InputError, IntegrationError
from poissonkit.numerics.events import event_thresholds
from poissonkit.numerics.integrators.base import (
    NO_CONVERGENCE,
    RUNNING,
    RawResult,
    SaveBuffer,
    step_end_kernels,
    step_tail,
)
from poissonkit.numerics.integrators.capabilities import DISCRETE_GRADIENT
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
    near_increment,
    newton_solver,
    no_jacobian,
)
from poissonkit.numerics.jit import jit
from poissonkit.traits import offers

#: The discrete gradients this method offers (``"auto"`` chooses from the Hamiltonian).
GRADIENTS = ("auto", "avf", "gonzalez")


class DiscreteGradientKernels(NamedTuple):
    """Compiled pieces of one system: ``skew(y, out)`` (entries of ``N P`` above the diagonal),
    ``grad(y, out)`` (``∇H``), ``energy(y, out)`` (``out[0] = H``) and the polynomial degree of
    ``H`` (``-1``: none)."""

    skew: CompiledFunction
    grad: CompiledFunction
    energy: CompiledFunction
    degree: int


_kernel_cache: dict[str, DiscreteGradientKernels] = {}


def discrete_gradient_kernels(system: HasSymbolicForm) -> DiscreteGradientKernels:
    """The compiled ``N P``, ``∇H`` and ``H`` of ``system`` (generated once, disk-cached)."""
    from poissonkit.numerics.codegen import compile_source, discrete_gradient_sources
    from poissonkit.numerics.jit import load_sources, source_key, store_sources

    form = system.symbolic_form()
    key = source_key(form.key, "discrete-gradient")
    hit = _kernel_cache.get(key)
    if hit is not None:
        return hit
    sources = load_sources(key)
    if sources is None:
        sources = discrete_gradient_sources(form.coords, form.hamiltonian, form.multiplier,
                                            form.structure)
        store_sources(key, sources)
    hit = DiscreteGradientKernels(compile_source(sources["dg_skew"], "dg_skew"),
                                  compile_source(sources["dg_grad"], "dg_grad"),
                                  compile_source(sources["dg_energy"], "dg_energy"),
                                  int(sources["degree"]))
    _kernel_cache[key] = hit
    return hit


def avf_nodes(degree: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss–Legendre nodes and weights on ``[0, 1]`` integrating ``∇H(x + sΔ)`` exactly for
    a polynomial ``H`` of total degree ``degree`` (``⌈degree/2⌉`` nodes, at least one)."""
    k = max(1, math.ceil(degree / 2))
    x, w = np.polynomial.legendre.leggauss(k)
    return 0.5 * (x + 1.0), 0.5 * w


_runners: dict[tuple[int, int, int, int, bool], tuple[CompiledFunction, object]] = {}


def _runner(system: HasCompiledKernels, dg: DiscreteGradientKernels,
            gonzalez: bool) -> CompiledFunction:
    """The compiled time loop for one system's kernels and discrete gradient (cached)."""
    ks = system.kernels
    key = (id(ks.rhs), id(dg.skew), id(dg.grad), id(dg.energy), bool(gonzalez))
    hit = _runners.get(key)
    if hit is not None:
        return hit[0]
    rhs = ks.rhs
    jac = ks.jac if ks.jac is not None else no_jacobian
    skew, grad, energy = dg.skew, dg.grad, dg.energy
    gz = bool(gonzalez)  # a compile-time constant of the loop
    remember = step_end_kernels(ks)[0]
    tail = step_tail(ks, compensated=True)

    @jit(inline="always")
    def residual(D, y, h, mid, G, data, work, args):
        # G(D) = D − h S((x + x')/2) ∇̄H(x, x'), x' = x + D
        c, nodes, weights, href, up, S, g, e1, gb, xs = args
        n = D.shape[0]
        for i in range(n):
            mid[i] = y[i] + 0.5 * D[i]
        skew(mid, up)
        q = 0
        for i in range(n):
            for j in range(i + 1, n):
                S[i, j] = up[q]
                S[j, i] = -up[q]
                q += 1
        if gz:
            # x' exactly as the compensated update below will store it: the level
            # H(x') = href is met by the stored state itself
            for i in range(n):
                xs[i] = y[i] + (D[i] - c[i])
            energy(xs, e1)
            grad(mid, g)
            dot = 0.0
            dd = 0.0
            for i in range(n):
                gb[i] = g[i]
                dot += g[i] * D[i]
                dd += D[i] * D[i]
            if dd > 0.0:
                corr = (e1[0] - href - dot) / dd
                for i in range(n):
                    gb[i] += corr * D[i]
        else:
            for i in range(n):
                gb[i] = 0.0
            for r in range(nodes.shape[0]):
                for i in range(n):
                    xs[i] = y[i] + nodes[r] * D[i]
                grad(xs, g)
                for i in range(n):
                    gb[i] += weights[r] * g[i]
        for i in range(n):
            acc = 0.0
            for j in range(n):
                acc += S[i, j] * gb[j]
            G[i] = D[i] - h * acc

    solve = newton_solver(residual, jac, near_increment, simplified=True)

    @jit
    def run(y, c, t0, h, n_total, tol, maxiter, newton, nodes, weights, href, data, work,
            save_every, step0, max_steps, out_t, out_y, contact, escape, watch, back1, back2,
            hist):
        n = y.shape[0]
        f = np.empty(n)
        D = np.empty(n)
        mid = np.empty(n)
        xs = np.empty(n)
        up = np.empty(max(n * (n - 1) // 2, 1))
        S = np.zeros((n, n))
        g = np.empty(n)
        e1 = np.empty(1)
        gb = np.empty(n)
        G = np.empty(n)
        J = np.empty((n, n))
        A = np.empty((n, n))
        delta = np.empty(n)
        piv = np.empty(n, dtype=np.int64)
        args = (c, nodes, weights, href, up, S, g, e1, gb, xs)
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
                D[i] = h * f[i]
            yn = 0.0
            for i in range(n):
                yn = max(yn, abs(y[i]))
            outcome, nf = solve(D, y, h, tol, maxiter, newton, yn, data, work, args, mid, G, J,
                                A, piv, delta)
            nfev += nf
            if outcome == SINGULAR:
                return NO_CONVERGENCE, t0 + gstep * h, k + 1, nsave, nfev, 0.0
            ok = outcome == CONVERGED
            t = t0 + gstep * h
            for i in range(n):  # Kahan: the state is y - c
                v = D[i] - c[i]
                s = y[i] + v
                c[i] = (s - y[i]) - v
                y[i] = s
            last = gstep >= n_total
            status, nsave, value = tail(y, c, t, RUNNING if ok else NO_CONVERGENCE, last,
                                        last or gstep % save_every == 0, track, data, work,
                                        contact, escape, watch, hist, out_t, out_y, nsave)
            if status != RUNNING:
                return status, t, k + 1, nsave, nfev, value
        return RUNNING, t0 + (step0 + max_steps) * h, max_steps, nsave, nfev, 0.0

    _runners[key] = (run, (ks, dg))  # keep the kernels (and their ids) alive
    return run


class DiscreteGradient:
    """Energy-preserving discrete-gradient method for symbolic Poisson systems (see the module
    docstring: average vector field or Gonzalez's midpoint discrete gradient, ``S = N P`` at the
    midpoint; Cohen & Hairer 2011, McLachlan–Quispel–Robidoux 1999).

    Parameters
    ----------
    gradient
        ``"auto"`` (default: ``"avf"`` for a polynomial ``H``, else ``"gonzalez"``), ``"avf"``
        (average vector field, exact Gauss–Legendre quadrature; polynomial ``H`` only) or
        ``"gonzalez"`` (midpoint discrete gradient, any ``H``).
    tol
        Newton stops when ``max|ΔD| <= tol max|D|`` (``D`` the step's increment), or when the
        correction stagnates at round-off; default ``1e-14``.
    max_iterations
        More iterations than this raise :class:`~poissonkit.errors.IntegrationError`.
    newton
        Use Newton's method with the field's Jacobian at the midpoint (else fixed-point
        iteration).
    """

    family = DISCRETE_GRADIENT.family
    capabilities = DISCRETE_GRADIENT.capabilities
    order = DISCRETE_GRADIENT.order
    name = "discrete_gradient"

    def __init__(self, gradient: str = "auto", tol: float = 1e-14, max_iterations: int = 50,
                 newton: bool = True) -> None:
        if gradient not in GRADIENTS:
            raise InputError(f"discrete_gradient: gradient must be one of {', '.join(GRADIENTS)},"
                             f" got {gradient!r}")
        if not tol > 0:
            raise InputError(f"discrete_gradient tol must be > 0, got {tol!r}")
        if max_iterations < 1:
            raise InputError(f"max_iterations must be >= 1, got {max_iterations!r}")
        self.gradient = gradient
        self.tol = float(tol)
        self.max_iterations = int(max_iterations)
        self.newton = bool(newton)

    def _choose(self, degree: int) -> str:
        """The discrete gradient to use for a Hamiltonian of polynomial degree ``degree``."""
        if self.gradient == "auto":
            return "avf" if degree >= 0 else "gonzalez"
        if self.gradient == "avf" and degree < 0:
            raise InputError("discrete_gradient: gradient='avf' needs a polynomial Hamiltonian "
                             "(its quadrature is exact only then); use 'gonzalez' or 'auto'")
        return self.gradient

    def integrate(self, system: System, y0: np.ndarray, t_end: float, *, step: float | None,
                  tol: float | None, events: Sequence[Event] = (), progress: bool = False,
                  save_every: int = 1, t0: float = 0.0,
                  control: Control | None = None) -> RawResult:
        """Integrate with fixed step ``step``; ``tol`` overrides the Newton tolerance
        (``control``: checkpoints, streaming, stop requests, see
        :func:`~poissonkit.numerics.integrators.driver.drive`)."""
        if not offers(system, HasSymbolicForm) or not offers(system, HasCompiledKernels):
            raise CapabilityError(self.name, "needs_kernels", f"{type(system).__name__} has no "
                                  "symbolic form (N, P, H); compile a HamiltonianSystem with "
                                  "compile_system")
        h, n_total = fixed_grid(self.name, step, t0, t_end)
        itol = float(tol) if tol is not None else self.tol
        dg = discrete_gradient_kernels(system)
        mode = self._choose(dg.degree)
        gonzalez = mode == "gonzalez"
        nodes, weights = avf_nodes(max(dg.degree, 0)) if not gonzalez else (np.zeros(1),
                                                                           np.zeros(1))
        kernels = system.kernels
        newton = self.newton and kernels.jac is not None
        contact, escape, watch = event_thresholds(events)
        run = _runner(system, dg, gonzalez)
        y = np.array(y0, dtype=float)
        data, work = system.data, system.work()
        scratch = Scratch(y.size)
        # Gonzalez: H(x) of every step is the run's initial energy (equal in exact arithmetic),
        # so the rounding of the computed energies does not add up from step to step
        e0 = np.empty(1)
        dg.energy(y, e0)
        href = float(e0[0])
        args = (itol, self.max_iterations, newton, nodes, weights, href, data, work)

        def chunk(st: LoopState, max_steps: int, buf: SaveBuffer) -> ChunkResult:
            return run(st.y, st.comp, t0, h, n_total, *args, save_every, st.steps, max_steps,
                       buf.cur_t, buf.cur_y, contact, escape, watch, st.prev, st.prev2, st.hist)

        def one_step(ys: np.ndarray, ts: float, done: int) -> tuple[int, float]:
            cs = np.zeros_like(ys)
            out = run(ys, cs, t0, h, n_total, *args, save_every, done, 1, scratch.t, scratch.y,
                      0.0, 0.0, 0.0, ys, ys, scratch.hist)
            ys -= cs
            return out[0], out[1]

        def advance(ys: np.ndarray, s: float) -> np.ndarray:
            yc = np.array(ys, dtype=float)
            cc = np.zeros_like(yc)
            status = run(yc, cc, 0.0, s, 1, *args, 1, 0, 1, scratch.t, scratch.y, 0.0, 0.0, 0.0,
                         yc, yc, scratch.hist)[0]
            if status == NO_CONVERGENCE:
                raise IntegrationError(f"{self.name}: Newton did not converge while locating "
                                       "an event")
            return yc - cc

        def failure(status: int, st: LoopState) -> Exception | None:
            if status == NO_CONVERGENCE:
                return IntegrationError(
                    f"{self.name}: Newton did not converge to {itol:g} in "
                    f"{self.max_iterations} iterations at step {st.steps} (t = {st.t:.6g}); "
                    "reduce the step")
            return None

        raw = drive(LoopProblem(
            self.name, system, y, t0, t_end,
            guard_division(self.name, chunk, lambda st: (one_step, st.y - st.comp)), advance,
            lambda st: st.steps >= n_total,
            describe(self.name, h, t0, t_end, n_total, save_every, y, tol=float(itol).hex(),
                     newton=bool(newton), gradient=mode, nodes=int(nodes.size)),
            min(n_total // save_every + 2, 4096), events, progress, save_every, control,
            failure, compensated=True))
        raw.extra.update(step=h, newton=newton, gradient=mode,
                         nodes=0 if gonzalez else int(nodes.size))
        return raw
