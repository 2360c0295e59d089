"""Built-in poissonkit plugin: magnets.

Pair potentials of axisymmetric magnetic bodies (dipoles, dumbbells, octupole-corrected
dumbbells, exact cylinders, bodies given by their scalar potential, current loops and
superconducting rings) and the model-fidelity estimates in :mod:`poissonkit_magnets.fidelity`.

The calculator of what a pair of magnets feels, :func:`poissonkit.pair_interaction`, works
for every registered pair potential and so lives in the core; it is re-exported here, where
magnet users look for it.
"""

from poissonkit.pairs import PairInteraction, pair_interaction

__all__ = ["PairInteraction", "pair_interaction"]
