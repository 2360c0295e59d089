"""Normal form of found Casimirs: a reduced generating set and the relations among it.

The Casimirs of degree ``<= D`` form a vector space ``V``. :func:`reduced_generators` picks, degree
by degree, generators of the algebra they span up to degree ``D``: at degree ``d``, ``W_d`` is the
span of all products of the generators kept so far of total degree ``<= d``; the new generators are
the reduced echelon basis of the projection of ``V_<=d`` that deletes every leading monomial of
``W_d`` (a canonical complement of ``W_d``: it depends on ``V`` and the monomial order only).

Monomial order: graded lexicographic (``grlex``) with the coordinates in the order of the
bivector's coordinates (``x_1 > x_2 > ...``). Each generator is then scaled to primitive integer
coefficients (over ``Z[parameters]`` when there are parameters) with a positive leading
coefficient.

:func:`relations` finds the polynomial relations among the generators up to weight ``D`` (the
weight of ``C_k`` is its degree), keeping only those that are not consequences of lower ones.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator

import sympy as sp
from sympy.polys.rings import PolyElement

Monom = tuple[int, ...]


def _grlex(m: Monom) -> tuple[int, Monom]:
    return (sum(m), m)


def _reduce(p: PolyElement, ech: dict[Monom, PolyElement],
            combo: dict | None = None, combos: dict | None = None) -> PolyElement:
    """Delete every monomial of ``p`` that leads an element of ``ech`` (elements have LC 1).

    With ``combo``/``combos`` the same operations are applied to the provenance records.
    """
    while True:
        hits = [m for m in p if m in ech]
        if not hits:
            return p
        m = max(hits, key=_grlex)
        c = p[m]
        p = p - ech[m].mul_ground(c)
        if combo is not None:
            for k, v in combos[m].items():
                combo[k] = combo[k] - c * v if k in combo else -(c * v)
                if not combo[k]:
                    del combo[k]


def _lead(p: PolyElement) -> Monom:
    return max(p, key=_grlex)


def _insert(ech: dict[Monom, PolyElement], p: PolyElement) -> bool:
    """Add ``p`` to a reduced echelon basis; False if it was already in the span."""
    p = _reduce(p, ech)
    if not p:
        return False
    m = _lead(p)
    p = p.quo_ground(p[m])
    for k, q in list(ech.items()):
        if m in q:
            ech[k] = q - p.mul_ground(q[m])
    ech[m] = p
    return True


def gen_monomials(degs: list[int], limit: int) -> Iterator[Monom]:
    """Exponent vectors over the generators with weight ``sum e_k deg_k`` in ``1..limit``."""
    r = len(degs)

    def rec(k: int, room: int, acc: list[int]) -> Iterator[Monom]:
        if k == r:
            if any(acc):
                yield tuple(acc)
            return
        e = 0
        while e * degs[k] <= room:
            acc.append(e)
            yield from rec(k + 1, room - e * degs[k], acc)
            acc.pop()
            e += 1
    yield from rec(0, limit, [])


def _weight(e: Monom, degs: list[int]) -> int:
    return sum(a * d for a, d in zip(e, degs))


class _Products:
    """Products of the generators, built from cached smaller ones."""

    def __init__(self, gens: list[PolyElement]) -> None:
        self.gens = gens
        self.cache: dict[Monom, PolyElement] = {}

    def __call__(self, e: Monom) -> PolyElement:
        e = tuple(e) + (0,) * (len(self.gens) - len(e))
        if e in self.cache:
            return self.cache[e]
        k = next(i for i, a in enumerate(e) if a)
        if sum(e) == 1:
            out = self.gens[k]
        else:
            smaller = list(e)
            smaller[k] -= 1
            out = self(tuple(smaller)) * self.gens[k]
        self.cache[e] = out
        return out


def reduced_generators(rows: list[PolyElement], normalise: Callable[[PolyElement], PolyElement]
                       ) -> tuple[list[PolyElement], list[int]]:
    """Reduced generators (module docstring) of the algebra spanned by ``rows``.

    ``rows`` span the Casimirs of degree ``<= D``; ``normalise`` rescales one generator.
    Returns the generators (lowest degree first, then by leading monomial, descending) and their
    degrees.
    """
    by_deg: dict[int, list[PolyElement]] = {}
    for p in rows:
        if p:
            by_deg.setdefault(sum(_lead(p)), []).append(p)
    gens: list[PolyElement] = []
    degs: list[int] = []
    prod = _Products(gens)
    for d in sorted(by_deg):
        W: dict[Monom, PolyElement] = {}
        for e in gen_monomials(degs, d):
            _insert(W, prod(e))
        new: dict[Monom, PolyElement] = {}
        for c in by_deg[d]:
            r = _reduce(c, W)
            if r:
                _insert(new, r)
        for m in sorted(new, key=_grlex, reverse=True):
            gens.append(normalise(new[m]))
            degs.append(d)
    return gens, degs


def relations(gens: list[PolyElement], degs: list[int], limit: int
              ) -> list[dict[Monom, object]]:
    """Generating relations ``sum_e c_e C^e = 0`` among ``gens`` of weight ``<= limit``.

    Each relation is ``{exponent vector over the generators: coefficient}``; relations implied by
    lower-weight ones (``C_k * R``) are left out.
    """
    if not gens:
        return []
    K = gens[0].ring.domain
    prod = _Products(gens)
    ech: dict[Monom, PolyElement] = {}
    combos: dict[Monom, dict] = {}
    found: list[tuple[int, dict]] = []
    for e in sorted(gen_monomials(degs, limit), key=lambda e: (_weight(e, degs), e)):
        combo = {e: K.one}
        p = _reduce(prod(e), ech, combo, combos)
        if not p:
            found.append((_weight(e, degs), combo))
            continue
        m = _lead(p)
        c = p[m]
        ech[m] = p.quo_ground(c)
        combos[m] = {k: v / c for k, v in combo.items()}
    if not found:
        return []
    syms = sp.symbols(f"_c0:{len(gens)}")
    S = sp.polys.rings.PolyRing(syms, K, sp.polys.orderings.grlex)
    kept: list[tuple[int, PolyElement]] = []
    ideal: dict[Monom, PolyElement] = {}
    done: set[tuple[int, Monom]] = set()
    for w, combo in found:
        # multiples of the kept relations up to weight w
        for j, (wj, Rj) in enumerate(kept):
            for e in [()] + list(gen_monomials(degs, w - wj)):
                if (j, e) not in done:
                    done.add((j, e))
                    mono = S({tuple(e) + (0,) * (len(gens) - len(e)): K.one}) if e else S.one
                    _insert(ideal, Rj * mono)
        R = S({k: K.convert(v) for k, v in combo.items()})
        if _reduce(R, ideal):
            kept.append((w, R))
    return [dict(R.items()) for _w, R in kept]
