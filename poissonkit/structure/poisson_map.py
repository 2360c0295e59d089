"""Push-forward of bivectors and Poisson maps.

Conventions: :mod:`poissonkit.conventions`. A map ``phi: x -> y = phi(x)`` is given by the
expressions ``phi_k(x)``, one per new coordinate ``y_k``. With ``J = d phi / dx``,

    ``{y_a, y_b}(phi(x)) = (J P J^T)_ab (x)``,

and ``phi`` is a Poisson map from ``(x, P)`` to ``(y, Q)`` iff ``J P J^T = Q o phi``.

:func:`push_forward` must express ``J P J^T`` in the new coordinates. In order it tries

1. the ``inverse`` map ``x = psi(y)`` if the caller gives one;
2. components with ``phi_k = x_j`` (a coordinate kept) are renamed directly, also inside
   undefined functions such as ``g(q)``; the remaining old coordinates are solved for with
   ``sympy.solve`` (works when the map is invertible and the equations are tractable);
3. otherwise (non-invertible maps such as the moment map ``M = gamma x p``) an elimination
   Groebner basis (lex, old coordinates first) of the graph ideal ``y - phi(x)``: each entry's
   normal form must be free of old coordinates. The image need not be open: the elements of
   the basis that involve only ``y`` are returned as ``image_relations``, and the pushed
   bivector is only meaningful on that image.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import sympy as sp
from sympy.core.function import AppliedUndef

from poissonkit.errors import DimensionError, InputError, PoissonkitError
from poissonkit.structure.bivector import Bivector, _as_symbols
from poissonkit.structure.checks import CheckResult
from poissonkit.structure.zerotest import _as_exprs, _Atomizer, _expr, _vanishing

__all__ = ["PushForward", "PushForwardError", "is_poisson_map", "jacobian_bracket",
           "push_forward"]


class PushForwardError(PoissonkitError):
    """The push-forward could not be written in the new coordinates (pass ``inverse=``)."""


@dataclass(frozen=True)
class PushForward:
    """Result of :func:`push_forward`.

    Attributes
    ----------
    bivector
        ``Q`` on the new coordinates with ``Q o phi = J P J^T``.
    image_relations
        Equations in the new coordinates satisfied on the image of ``phi`` (empty if the image
        is open); ``Q`` is determined only on that set.
    method
        ``"inverse"``, ``"solve"`` or ``"groebner"``.
    """

    bivector: Bivector
    image_relations: tuple[sp.Expr, ...] = ()
    method: str = ""

    @property
    def coords(self) -> tuple[sp.Symbol, ...]:
        """The new coordinates."""
        return self.bivector.coords

    @property
    def matrix(self) -> sp.ImmutableMatrix:
        """The matrix of the pushed bivector."""
        return self.bivector.matrix


def _map_exprs(P: Bivector, phi) -> list[sp.Expr]:
    if isinstance(phi, Mapping):
        raise InputError("phi must be a sequence of expressions, one per new coordinate")
    if isinstance(phi, (str, sp.Basic)) and not isinstance(phi, sp.MatrixBase):
        phi = [phi]
    return [_expr(e, "map component") for e in phi]


def jacobian_bracket(P: Bivector, phi: Sequence) -> sp.Matrix:
    """``J P J^T`` in the *old* coordinates: the brackets ``{phi_a, phi_b}``."""
    phis = _map_exprs(P, phi)
    J = sp.Matrix([[sp.diff(f, x) for x in P.coords] for f in phis])
    return (J * P.matrix * J.T).applyfunc(sp.expand)


def _simplify_entry(e: sp.Expr) -> sp.Expr:
    e = sp.together(sp.expand(e))
    return sp.factor(e) if not e.has(AppliedUndef, sp.Derivative, sp.Subs) else sp.cancel(e)


def push_forward(P: Bivector, phi: Sequence, new_coords: Sequence, *,
                 inverse: Mapping | None = None) -> PushForward:
    """Push ``P`` through ``y = phi(x)``: the bivector ``Q`` with ``Q(phi(x)) = J P J^T``.

    Parameters
    ----------
    P
        Bivector on the old coordinates ``x``.
    phi
        Expressions ``phi_k(x)``, one per new coordinate.
    new_coords
        Names or symbols of the new coordinates ``y``. A name may equal an old one (e.g. ``q``
        kept); it then refers to the new coordinate.
    inverse
        Optional ``{old coordinate: expression in y}``; used instead of solving.

    Returns
    -------
    PushForward
        The bivector, the equations of the image (if any) and the method used.

    Raises
    ------
    PushForwardError
        If the entries cannot be written in ``y`` (the pushed bracket is not well defined or
        the elimination failed); pass ``inverse``.

    Examples
    --------
    Survey (42) is the push-forward of the canonical bracket under ``(q, p) -> (q, g(q) p)``
    (survey (41)–(44)); see ``tests/symbolic/test_symbolic_poisson_maps.py``.
    """
    if not isinstance(P, Bivector):
        raise InputError(f"push_forward needs a Bivector, got {type(P).__name__}")
    phis = _map_exprs(P, phi)
    ys = _as_symbols(new_coords)
    if len(ys) != len(phis):
        raise DimensionError(f"{len(phis)} map components for {len(ys)} new coordinates")
    old = set(P.coords)
    params = set().union(*(e.free_symbols for e in P.matrix)) - old
    clash = [str(y) for y in ys if y in params]
    if clash:
        raise InputError(f"new coordinates {clash} clash with parameters of P")
    # old symbols that share a name with a new coordinate are renamed in the work copy
    ren = {x: sp.Dummy(str(x)) for x in P.coords if x in set(ys)}
    Pw = Bivector(tuple(ren.get(x, x) for x in P.coords), P.matrix.xreplace(ren)) if ren else P
    phis = [f.xreplace(ren) for f in phis]
    for f in phis:
        extra = f.free_symbols - set(Pw.coords) - params
        if extra:
            raise InputError(f"map component {f} uses unknown symbols {sorted(map(str, extra))}")
    Jmat = jacobian_bracket(Pw, phis)

    def finish(mat: sp.Matrix, method: str, rels=()) -> PushForward:
        leftovers = set().union(*(e.free_symbols for e in mat)) & set(Pw.coords)
        if leftovers:
            raise PushForwardError(
                f"push-forward still depends on old coordinates {sorted(map(str, leftovers))}; "
                "the bracket may not descend to the new coordinates, or pass inverse=")
        mat = mat.applyfunc(_simplify_entry)
        return PushForward(Bivector(ys, mat), tuple(rels), method)

    if inverse is not None:
        sub = {}
        for k, v in inverse.items():
            key = ren.get(P.symbol(str(k)), P.symbol(str(k))) if str(k) in P.names else None
            if key is None:
                raise InputError(f"inverse gives unknown old coordinate {k}")
            sub[key] = _expr(v, "inverse component")
        return finish(Jmat.subs(sub), "inverse")

    # 2. kept coordinates and sympy.solve for the rest
    sub = {}
    for y, f in zip(ys, phis):
        if f in set(Pw.coords) and f not in sub:
            sub[f] = y
    rest = [x for x in Pw.coords if x not in sub]
    eqs = [sp.expand(y - f.subs(sub)) for y, f in zip(ys, phis) if f not in sub]
    if rest:
        sols = sp.solve(eqs, rest, dict=True) if eqs else []
        if len(sols) == 1 and set(sols[0]) == set(rest) and not any(
                v.free_symbols & set(rest) for v in sols[0].values()):
            full = dict(sub)
            full.update({x: v for x, v in sols[0].items()})
            mat = Jmat.subs(full)
            if not (set().union(*(e.free_symbols for e in mat)) & set(Pw.coords)):
                return finish(mat, "solve")
    else:
        return finish(Jmat.subs(sub), "solve")

    # 3. elimination (graph ideal), after the kept coordinates have been renamed
    mat, rels = _eliminate(Jmat.subs(sub), eqs, rest, ys, params)
    return finish(mat, "groebner", rels)


def _eliminate(mat: sp.Matrix, eqs: list[sp.Expr], rest: list[sp.Symbol],
               ys: Sequence[sp.Symbol], params: set) -> tuple[sp.Matrix, tuple[sp.Expr, ...]]:
    """Step 3 of :func:`push_forward`: the entries of ``mat`` (kept coordinates renamed) reduced
    modulo a lex Groebner basis of the graph ideal ``eqs``, eliminating the old coordinates
    ``rest``; with the equations of the image (the basis elements free of ``rest``)."""
    at = _Atomizer()
    ents = [at(e) for e in mat]
    graph = [sp.fraction(sp.together(at(e)))[0] for e in eqs]
    atoms = sorted(at.back, key=str)
    bad_atoms = [a for a in atoms if a.free_symbols & set(rest)
                 or at.back[a].free_symbols & set(rest)]
    if bad_atoms or at.relations:
        raise PushForwardError("elimination needs polynomial dependence on the eliminated "
                               "coordinates; pass inverse=")
    gens = list(rest) + sorted(set(ys) | (set(atoms)) | params, key=str)
    G = sp.groebner(graph, *gens, order="lex")
    image = tuple(g for g in G.exprs if not (g.free_symbols & set(rest)))
    out = []
    for e in ents:
        num, den = sp.fraction(sp.together(e))
        nn = G.reduce(sp.expand(num))[1]
        dd = G.reduce(sp.expand(den))[1]
        out.append(at.restore(nn / dd))
    rels = tuple(sp.factor(at.restore(g)) for g in image)
    return sp.Matrix(len(ys), len(ys), out), rels




def is_poisson_map(phi: Sequence, P: Bivector, Q: Bivector,
                   constraints: Sequence = ()) -> CheckResult:
    """Whether ``phi: (x, P) -> (y, Q)`` is a Poisson map: ``J P J^T = Q o phi``.

    Parameters
    ----------
    phi
        Expressions ``phi_k(x)`` in ``P.coords``, one per coordinate of ``Q`` (same order).
    P, Q
        Source and target bivectors.
    constraints
        Expressions in the *source* coordinates that vanish on the set of interest (e.g. a
        Casimir level ``(gamma, M)``); the identity is then checked modulo them.

    Returns
    -------
    CheckResult
        ``failures`` lists ``("{y_a, y_b}", (J P J^T - Q o phi)_ab)`` for each failing pair.
    """
    if not isinstance(P, Bivector) or not isinstance(Q, Bivector):
        raise InputError("is_poisson_map needs Bivectors P and Q")
    phis = _map_exprs(P, phi)
    if len(phis) != Q.dim:
        raise DimensionError(f"{len(phis)} map components for target dimension {Q.dim}")
    for f in phis:
        extra = f.free_symbols - set(P.coords) - set().union(*(e.free_symbols for e in P.matrix))
        extra -= set().union(*(e.free_symbols for e in Q.matrix)) - set(Q.coords)
        if extra:
            raise InputError(f"map component {f} uses unknown symbols {sorted(map(str, extra))}")
    lhs = jacobian_bracket(P, phis)
    # Q o phi: substitute simultaneously (target names may coincide with source names)
    rhs = Q.matrix.subs(dict(zip(Q.coords, phis)), simultaneous=True)
    labels, diffs = [], []
    for a in range(Q.dim):
        for b in range(a + 1, Q.dim):
            labels.append(f"{{{Q.coords[a]}, {Q.coords[b]}}}")
            diffs.append(lhs[a, b] - rhs[a, b])
    res = _vanishing(diffs, _as_exprs(constraints))
    fails = tuple((lab, r) for lab, r in zip(labels, res) if r != 0)
    return CheckResult(not fails, fails, "Poisson map",
                       "modulo constraints" if constraints else "identically")
