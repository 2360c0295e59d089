"""Constraint surfaces as rational parametrisations, for random points on them.

The unit sphere ``x**2 + y**2 + z**2 = 1`` in three coordinates is recognised (inverse
stereographic projection, which covers every rational point but the pole), and so are
constraints linear in one coordinate (solved for it); any other surface needs an explicit
``parametrization={coord: expression in new symbols}``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import sympy as sp

from poissonkit.errors import InputError

__all__ = ["sphere_parametrization"]


def sphere_parametrization(x: sp.Symbol, y: sp.Symbol, z: sp.Symbol,
                           u: sp.Symbol | None = None, v: sp.Symbol | None = None
                           ) -> dict[sp.Symbol, sp.Expr]:
    """Rational parametrisation of the unit sphere ``x**2 + y**2 + z**2 = 1``.

    Inverse stereographic projection from the south pole:
    ``(x, y, z) = (2u, 2v, 1 - u**2 - v**2) / (1 + u**2 + v**2)`` (every rational point of the
    sphere except the pole ``(0, 0, -1)``).

    Parameters
    ----------
    x, y, z
        The three coordinates on the sphere.
    u, v
        The parameters; default symbols named after the coordinates (``_u_x_y_z``, ...), so
        that seeded points are reproducible.

    Returns
    -------
    dict
        ``{x: ..., y: ..., z: ...}``, usable as ``parametrization=`` of the random checks and
        of :func:`~poissonkit.structure.jacobi.check_jacobi`.
    """
    tag = "_".join(str(s) for s in (x, y, z))
    u = u if u is not None else sp.Symbol(f"_u_{tag}", real=True)
    v = v if v is not None else sp.Symbol(f"_v_{tag}", real=True)
    n = 1 + u**2 + v**2
    return {x: 2 * u / n, y: 2 * v / n, z: (1 - u**2 - v**2) / n}


def _recognise(constraints: Sequence[sp.Expr], coords: Sequence[sp.Symbol] | None
               ) -> dict[sp.Symbol, sp.Expr]:
    """A parametrisation for unit spheres and constraints linear in one variable."""
    out: dict[sp.Symbol, sp.Expr] = {}
    for c in constraints:
        c = sp.expand(sp.numer(sp.together(c.xreplace(out))))
        vs = sorted(c.free_symbols, key=str)
        cand = [x for x in (coords if coords is not None else vs) if x in c.free_symbols]
        if len(cand) == 3 and not set(cand) & set(out) \
                and sp.expand(c - sum(x**2 for x in cand) + 1) == 0:
            out.update(sphere_parametrization(*cand))
            continue
        for x in cand:
            if x in out:
                continue
            try:
                poly = sp.Poly(c, x)
            except sp.PolynomialError:
                continue
            if poly.degree() == 1:
                a1, a0 = poly.all_coeffs()
                if a1.is_number and a1 != 0:   # solvable everywhere, no division by zero
                    out[x] = sp.together(-a0 / a1)
                    break
        else:
            raise InputError(f"random points on the constraint {c} = 0 need a "
                             "parametrization of the surface (parametrization={coord: expr})")
    return out


def _check_acyclic(param: Mapping[sp.Symbol, sp.Expr]) -> None:
    """A parametrisation must not define a coordinate through itself (even indirectly)."""
    state: dict[sp.Symbol, int] = {}

    def visit(s: sp.Symbol) -> None:
        if state.get(s) == 2:
            return
        if state.get(s) == 1:
            raise InputError(f"parametrization defines {s} through itself")
        state[s] = 1
        for t in param[s].free_symbols & set(param):
            visit(t)
        state[s] = 2

    for s in param:
        visit(s)


def _param_degree(param: Mapping[sp.Symbol, sp.Expr]) -> int:
    deg = 1
    for e in param.values():
        num, den = sp.fraction(sp.together(e))
        gens = sorted(e.free_symbols, key=str)
        if not gens:
            continue
        try:
            deg = max(deg, sp.Poly(num, *gens).total_degree(), sp.Poly(den, *gens).total_degree())
        except sp.PolynomialError:
            raise InputError(f"parametrization component {e} is not a rational function") from None
    return deg
