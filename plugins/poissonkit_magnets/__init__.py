"""Built-in poissonkit plugin: magnets.

Pair potentials of axisymmetric magnetic bodies (dipoles, dumbbells, octupole-corrected
dumbbells, exact cylinders, bodies given by their scalar potential, current loops and
superconducting rings) and the model-fidelity estimates in :mod:`poissonkit_magnets.fidelity`.
"""
