"""Symbolic layer (sympy): bivectors, blocks, direct sums, deformed brackets, Schouten bracket,
Jacobi checks, Casimirs, Hamiltonian vector fields, Poisson maps.

Conventions: :mod:`poissonkit.conventions`.
"""

from poissonkit.structure.bivector import Bivector, direct_sum
from poissonkit.structure.blocks import canonical, e3, eps_matrix, lie_poisson, so3, symmetric_top
from poissonkit.structure.parsing import parse_expression
from poissonkit.structure.system import HamiltonianSystem

__all__ = [
    "Bivector", "HamiltonianSystem", "canonical", "direct_sum", "e3", "eps_matrix",
    "lie_poisson", "parse_expression", "so3", "symmetric_top",
]
