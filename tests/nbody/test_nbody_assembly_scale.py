"""Graph → system in O(N): uniform graphs become one all-pairs interaction, the builders place
and join bodies without comparing every pair.

Truth: the former pair-list build (``system_of(pairs_of(G))``) to the bit, and the former
quadratic rejection sampling and neighbour search of ``random_cluster`` written out here.
"""

from __future__ import annotations

import itertools

import networkx as nx
import numpy as np
import pytest

import poissonkit_nbody as nb
from poissonkit.numerics.nbody import AllPairs, Interaction
from poissonkit.scene.assembly import bodies_of, pairs_of, system_of

MAG = {"mass": 7.658e-4, "alpha": 3.872e7, "moment": 0.15546875}


def _same_system(a, b) -> None:
    assert a.scales == b.scales
    assert repr(a.interactions) == repr(b.interactions)
    _same_data(a.data, b.data)


def _same_data(x, y) -> None:
    """Kernel data equal to the bit, slot by slot (nested named tuples included)."""
    if isinstance(x, tuple):
        assert type(x) is type(y) and len(x) == len(y)
        for u, v in zip(x, y):
            _same_data(u, v)
    elif isinstance(x, np.ndarray):
        assert x.dtype == y.dtype and np.array_equal(x, y)
    else:
        assert x == y


@pytest.mark.parametrize("cutoff", [None, 0.05])
def test_complete_and_edgeless_graphs_build_the_pair_list_system(cutoff):
    G = nb.lattice((3, 3, 2), 0.03, MAG, potential="dipole", axes="checkerboard")
    bodies = bodies_of(G)
    ref = system_of(bodies, pairs_of(G, bodies), cutoff=cutoff)
    system = nb.from_graph(G, cutoff=cutoff)
    assert len(system.interactions) == 1 and isinstance(system.interactions[0], AllPairs)
    _same_system(system, ref)
    bare = G.copy()
    bare.remove_edges_from(list(bare.edges))  # no edges: every pair, never listed
    _same_system(nb.from_graph(bare, cutoff=cutoff), ref)


def test_graphs_that_are_not_uniform_keep_their_pairs():
    G = nb.lattice((3, 3, 2), 0.03, MAG, potential="dipole")
    G.nodes[4]["moment"] = 0.3  # one stronger magnet: pairs differ in moment1/moment2
    system = nb.from_graph(G)
    # the pairs of body 4 are listed (the others, all alike, still form one AllPairs)
    assert sum(isinstance(i, Interaction) for i in system.interactions) == 17
    chain = nb.chain(6, 0.03, MAG, potential="dipole", interactions="neighbours")
    assert len(nb.from_graph(chain).interactions) == 5


def test_uniform_graph_pair_reads_each_body_once(monkeypatch):
    """The test for a uniform graph visits each body a bounded number of times (O(N))."""
    from poissonkit.scene.assembly import uniform_graph_pair
    from poissonkit.scene.bodies import BodyModel

    G = nx.Graph(potential="dipole")
    for k in range(200):
        G.add_node(k, r=(0.03 * k, 0.0, 0.0), nu=(0.0, 0.0, 1.0), **MAG)
    bodies = bodies_of(G)
    calls = []
    original = BodyModel.attr
    monkeypatch.setattr(BodyModel, "attr",
                        lambda self, name: calls.append(1) or original(self, name))
    assert uniform_graph_pair(G, bodies) is not None
    assert len(calls) <= 4 * len(bodies)


def _old_cluster(n, radius, min_distance, seed):
    rng = np.random.default_rng(seed)
    pos = []
    for _k in range(n):
        for _ in range(10000):
            x = rng.uniform(-radius, radius, 3)
            if x @ x <= radius * radius and all(np.linalg.norm(x - y) >= min_distance
                                                for y in pos):
                pos.append(x)
                break
    P = np.array(pos)
    near = [(i, j) for i, j in itertools.combinations(range(n), 2)
            if np.linalg.norm(P[i] - P[j]) < 2 * min_distance]
    return P, near


@pytest.mark.parametrize("seed", [0, 3])
def test_random_cluster_places_and_joins_as_before(seed):
    P, near = _old_cluster(150, 0.04, 0.01, seed)
    G = nb.random_cluster(150, 0.04, {"mass": 1.0}, seed=seed, min_distance=0.01,
                          axes="aligned", interactions="neighbours")
    assert np.array_equal(np.array([G.nodes[k]["r"] for k in G.nodes]), P)
    assert list(G.edges) == near and near
