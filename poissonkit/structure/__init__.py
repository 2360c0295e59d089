"""Symbolic layer (sympy): bivectors, blocks, direct sums, deformed brackets, Schouten bracket,
Jacobi checks, Casimirs, Hamiltonian vector fields, Poisson maps.

Conventions: :mod:`poissonkit.conventions`. User guide: ``docs/structure.md``.
"""

from poissonkit.structure.bivector import Bivector, direct_sum
from poissonkit.structure.blocks import (
    canonical,
    e3,
    eps_matrix,
    lie_poisson,
    se3,
    so3,
    symmetric_top,
)
from poissonkit.structure.deformed import (
    canonical_deformation,
    chaplygin_ball,
    chaplygin_gyrostat,
    deform,
    p_gf,
    veselova,
    veselova_gyrostat,
)
from poissonkit.structure.jacobi import JacobiResult, check_jacobi
from poissonkit.structure.parsing import parse_expression
from poissonkit.structure.schouten import (
    Multivector,
    are_compatible,
    is_poisson_vector_field,
    jacobiator,
    lichnerowicz,
    schouten_bracket,
)
from poissonkit.structure.system import HamiltonianSystem

__all__ = [
    "Bivector", "HamiltonianSystem", "JacobiResult", "Multivector", "are_compatible",
    "canonical", "canonical_deformation", "chaplygin_ball", "chaplygin_gyrostat", "check_jacobi",
    "deform", "direct_sum", "e3", "eps_matrix", "is_poisson_vector_field", "jacobiator",
    "lichnerowicz", "lie_poisson", "p_gf", "parse_expression", "schouten_bracket", "se3", "so3",
    "symmetric_top", "veselova", "veselova_gyrostat",
]
