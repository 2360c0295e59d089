"""Built-in poissonkit plugin: N-body assemblies from networkx graphs.

Nodes carry body models (:mod:`poissonkit_nbody.bodies`), edges carry potential names and
parameters; :func:`from_graph` turns a graph into a numerics ``NBodySystem`` and
:func:`initial_state` gives its state at t = 0.
"""

from poissonkit_nbody.assemble import (
    EdgeSpec,
    PairSpec,
    auto_scales,
    bodies_of,
    edges_of,
    from_graph,
    initial_state,
    pairs_of,
    resolve,
    state_arrays,
    state_of,
    system_of,
)
from poissonkit_nbody.bodies import BodyModel, pair_params
from poissonkit_nbody.graphs import chain, complete, lattice, random_cluster, ring

__all__ = [
    "BodyModel", "EdgeSpec", "PairSpec", "auto_scales", "bodies_of", "chain", "complete",
    "edges_of", "from_graph", "initial_state",
    "lattice", "pair_params", "pairs_of", "random_cluster", "resolve", "ring", "state_arrays",
    "state_of", "system_of",
]
