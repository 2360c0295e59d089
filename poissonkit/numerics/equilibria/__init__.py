"""Relative equilibria on Poisson manifolds and their linear stability.

* :func:`~poissonkit.numerics.equilibria.relative.relative_equilibrium` finds a critical point
  of ``H − Σ ω_k J_k + Σ λ_i C_i`` on a symplectic leaf;
* :func:`~poissonkit.numerics.equilibria.stability.linear_stability` gives the spectrum on the
  leaf (modulo the symmetry orbit) and the energy–Casimir verdict.

Both work on any numerics system that declares its bracket and Casimirs (compiled symbolic
systems, systems of bodies, scenes).
"""

from __future__ import annotations

from poissonkit.numerics.equilibria.errors import (EquilibriumError, NoConvergenceError,
                                                   NotAnEquilibriumError, SingularPointError)
from poissonkit.numerics.equilibria.relative import RelativeEquilibrium, relative_equilibrium
from poissonkit.numerics.equilibria.stability import LinearStability, linear_stability

__all__ = ["EquilibriumError", "LinearStability", "NoConvergenceError", "NotAnEquilibriumError",
           "RelativeEquilibrium", "SingularPointError", "linear_stability",
           "relative_equilibrium"]
