"""Independent blocks of a bivector, the first step of the rank, singular set and Casimirs.

The blocks are the connected components of the graph "``P[i, j] != 0``", merged where an entry
of one component depends on a coordinate of another. For a direct sum this recovers its
summands (and splits ``canonical(3)`` into its three ``(q_i, p_i)`` pairs).
"""

from __future__ import annotations



from poissonkit.structure._expr import as_bivector
from poissonkit.structure.bivector import Bivector

__all__: list[str] = []


def _blocks(P: Bivector) -> list[list[int]]:
    """Index sets of independent blocks (see the module docstring)."""
    n = P.dim
    parent = list(range(n))

    def find(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    def union(i: int, j: int) -> None:
        ri, rj = find(i), find(j)
        if ri != rj:
            parent[max(ri, rj)] = min(ri, rj)

    index = {c: k for k, c in enumerate(P.coords)}
    M = P.matrix
    for i in range(n):
        for j in range(i + 1, n):
            if M[i, j] != 0:
                union(i, j)
                # an entry depending on a coordinate elsewhere couples the blocks
                for s in M[i, j].free_symbols:
                    if s in index:
                        union(i, index[s])
    groups: dict[int, list[int]] = {}
    for i in range(n):
        groups.setdefault(find(i), []).append(i)
    return sorted(groups.values())


def _sub(P: Bivector, idx: list[int]) -> Bivector:
    return Bivector(tuple(P.coords[i] for i in idx), P.matrix.extract(idx, idx))


_bivector = as_bivector
