"""Symbolic layer (sympy): bivectors, blocks, direct sums, deformed brackets, Schouten bracket,
Jacobi checks, Casimirs, Hamiltonian vector fields, Poisson maps.

Conventions: :mod:`poissonkit.conventions`. User guide: ``docs/structure.md``.
"""

from poissonkit.structure.bivector import Bivector, direct_sum
from poissonkit.structure.blocks import (canonical, e3, eps_matrix, lie_poisson, se3, so3,
                                         symmetric_top)

# casimirs, checks and poisson_map are re-exported eagerly: ~40 ms once sympy is loaded.
from poissonkit.structure.casimirs import (Casimirs, RankResult, SingularSet, find_casimirs,
                                           is_casimir, rank, singular_set)
from poissonkit.structure.checks import (CheckResult, check_vanishing, divergence, in_involution,
                                         is_conformally_hamiltonian, is_first_integral,
                                         is_invariant_measure, vanishes)
from poissonkit.structure.deformed import (canonical_deformation, chaplygin_ball,
                                           chaplygin_ball_system, chaplygin_gyrostat, deform, p_gf,
                                           veselova, veselova_gyrostat)
from poissonkit.structure.jacobi import JacobiResult, check_jacobi
from poissonkit.structure.parsing import parse_expression
from poissonkit.structure.poisson_map import (PushForward, PushForwardError, is_poisson_map,
                                              jacobian_bracket, push_forward)
from poissonkit.structure.randompoints import RandomPoints, sphere_parametrization
from poissonkit.structure.schouten import (Multivector, are_compatible, is_poisson_vector_field,
                                           jacobiator, lichnerowicz, schouten_bracket)
from poissonkit.structure.system import HamiltonianSystem

__all__ = [
    "Bivector",
    "Casimirs",
    "CheckResult",
    "HamiltonianSystem",
    "JacobiResult",
    "Multivector",
    "PushForward",
    "PushForwardError",
    "RandomPoints",
    "RankResult",
    "SingularSet",
    "are_compatible",
    "canonical",
    "canonical_deformation",
    "chaplygin_ball",
    "chaplygin_ball_system",
    "chaplygin_gyrostat",
    "check_jacobi",
    "check_vanishing",
    "deform",
    "direct_sum",
    "divergence",
    "e3",
    "eps_matrix",
    "find_casimirs",
    "in_involution",
    "is_casimir",
    "is_conformally_hamiltonian",
    "is_first_integral",
    "is_invariant_measure",
    "is_poisson_map",
    "is_poisson_vector_field",
    "jacobian_bracket",
    "jacobiator",
    "lichnerowicz",
    "lie_poisson",
    "p_gf",
    "parse_expression",
    "push_forward",
    "rank",
    "schouten_bracket",
    "se3",
    "singular_set",
    "so3",
    "sphere_parametrization",
    "symmetric_top",
    "vanishes",
    "veselova",
    "veselova_gyrostat",
]
