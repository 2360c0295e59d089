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

from poissonkit.contracts import (CompiledFunction, Event, HasCompiledKernels, HasSymbolicForm,
                                  System)
from poissonkit.errors import CapabilityError, InputError
from poissonkit.numerics.integrators.base import RawResult
from poissonkit.numerics.integrators.capabilities import DISCRETE_GRADIENT
from poissonkit.numerics.integrators.driver import Control
from poissonkit.numerics.integrators.glue import describe, fixed_grid
from poissonkit.numerics.integrators.implicit import (ImplicitMethod, ImplicitRun, drive_implicit,
                                                      implicit_loop)
from poissonkit.numerics.integrators.newton import near_increment
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


@jit(inline="always")
def _scratch(n, f, c, extra):
    # the residual's args: (c, nodes, weights, href, up, S, g, e1, gb, xs)
    nodes, weights, href = extra
    return (c, nodes, weights, href, np.empty(max(n * (n - 1) // 2, 1)), np.zeros((n, n)),
            np.empty(n), np.empty(1), np.empty(n), np.empty(n))


@jit(inline="always")
def _guess(D, y, f, h):
    # the explicit Euler increment as the start; the stopping test scales with max|y|
    n = y.shape[0]
    for i in range(n):
        D[i] = h * f[i]
    yn = 0.0
    for i in range(n):
        yn = max(yn, abs(y[i]))
    return yn


@jit(inline="always")
def _accept(D, y, c):
    for i in range(y.shape[0]):  # Kahan: the state is y - c
        v = D[i] - c[i]
        s = y[i] + v
        c[i] = (s - y[i]) - v
        y[i] = s


_runners: dict[tuple[int, int, int, int, bool], tuple[CompiledFunction, object]] = {}


def _runner(system: HasCompiledKernels, dg: DiscreteGradientKernels,
            gonzalez: bool) -> CompiledFunction:
    """The compiled time loop for one system's kernels and discrete gradient (cached)."""
    ks = system.kernels
    key = (id(ks.rhs), id(dg.skew), id(dg.grad), id(dg.energy), bool(gonzalez))
    hit = _runners.get(key)
    if hit is not None:
        return hit[0]
    skew, grad, energy = dg.skew, dg.grad, dg.energy
    gz = bool(gonzalez)  # a compile-time constant of the loop

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

    run = implicit_loop(ks, ImplicitMethod(residual, near_increment, True, _scratch, _guess,
                                           _accept, compensated=True))
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
        newton = self.newton and system.kernels.jac is not None
        run = _runner(system, dg, gonzalez)
        y = np.array(y0, dtype=float)
        # Gonzalez: H(x) of every step is the run's initial energy (equal in exact arithmetic),
        # so the rounding of the computed energies does not add up from step to step
        e0 = np.empty(1)
        dg.energy(y, e0)
        href = float(e0[0])
        spec = ImplicitRun(self.name, "Newton", itol, self.max_iterations, newton,
                           (nodes, weights, href),
                           describe(self.name, h, t0, t_end, n_total, save_every, y,
                                    tol=float(itol).hex(), newton=bool(newton), gradient=mode,
                                    nodes=int(nodes.size)))
        raw = drive_implicit(run, spec, True, system, y, t0, t_end, h, n_total, events,
                             progress, save_every, control)
        raw.extra.update(gradient=mode,
                         nodes=0 if gonzalez else int(nodes.size))
        return raw
