"""Built-in poissonkit plugin: N-body assemblies from networkx graphs.

The plugin contributes the graph builders (:mod:`poissonkit_nbody.graphs`) and point-mass
gravity. Turning a graph into a system is the core's job (:mod:`poissonkit.scene.assembly`,
:mod:`poissonkit.scene.bodies`); those names are re-exported here for convenience.
"""

from poissonkit.scene.assembly import (EdgeSpec, PairSpec, auto_scales, bodies_of, edges_of,
                                       from_graph, initial_state, pairs_of, resolve, state_arrays,
                                       state_of, system_of)
from poissonkit.scene.assembly import complete
from poissonkit.scene.bodies import BodyModel, pair_params
from poissonkit_nbody.graphs import chain, lattice, random_cluster, ring

__all__ = [
    "BodyModel", "EdgeSpec", "PairSpec", "auto_scales", "bodies_of", "chain", "complete",
    "edges_of", "from_graph", "initial_state",
    "lattice", "pair_params", "pairs_of", "random_cluster", "resolve", "ring", "state_arrays",
    "state_of", "system_of",
]
