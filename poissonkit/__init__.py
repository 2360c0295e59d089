"""poissonkit — Hamiltonian mechanics on Poisson manifolds.

Declare a bracket, prove it is Poisson, find its Casimirs, then integrate the dynamics fast and
accurately. ``import poissonkit as pk`` gives the everyday API listed in :data:`__all__`; the
submodules (:mod:`poissonkit.structure`, :mod:`poissonkit.numerics`, :mod:`poissonkit.scene`,
:mod:`poissonkit.plugin`, ...) hold the rest for the specialist. Conventions:
:mod:`poissonkit.conventions`.

The API reference of the documentation is generated from :data:`__all__` (grouped by the
subpackage each name lives in), so a new public name is added in one place: ``_LAZY`` below
(or the eager imports plus ``__all__``).
"""

# No ``from __future__ import annotations`` and no helper imports at module level: tab completion
# on ``pk.`` must offer only the public API (``__dir__`` below lists ``__all__``), and a helper
# left in the namespace is still reachable as ``pk.helper`` by mistake.
from poissonkit.errors import PoissonkitError

# Everything else is imported on first use so that `import poissonkit` loads neither sympy nor
# numpy (the command line starts in a fraction of a second).
# name -> module that defines it (the API reference documents it from there).
_LAZY: dict[str, str] = {
    # symbolic structures (the everyday ones first)
    "Bivector": "poissonkit.structure.bivector",
    "direct_sum": "poissonkit.structure.bivector",
    "HamiltonianSystem": "poissonkit.structure.system",
    "canonical": "poissonkit.structure.blocks",
    "e3": "poissonkit.structure.blocks",
    "so3": "poissonkit.structure.blocks",
    "lie_poisson": "poissonkit.structure.blocks",
    "symmetric_top": "poissonkit.structure.blocks",
    "find_casimirs": "poissonkit.structure.casimirs",
    "is_casimir": "poissonkit.structure.casimirs",
    "in_involution": "poissonkit.structure.checks",
    "is_first_integral": "poissonkit.structure.checks",
    "rank": "poissonkit.structure.rank",
    "se3": "poissonkit.structure.blocks",
    "lie_algebra": "poissonkit.structure.lie_algebras",
    "LieAlgebra": "poissonkit.structure.lie_algebras",
    "p_gf": "poissonkit.structure.deformed",
    "chaplygin_ball": "poissonkit.structure.deformed",
    "check_jacobi": "poissonkit.structure.jacobi",
    "schouten_bracket": "poissonkit.structure.schouten",
    "is_poisson_map": "poissonkit.structure.poisson_map",
    "parse_expression": "poissonkit.structure.parsing",
    "verify": "poissonkit.structure.verification",
    "hamiltonize": "poissonkit.structure.hamiltonize",
    "HamiltonizationProblem": "poissonkit.structure.hamiltonize_problem",
    "HamiltonizeResult": "poissonkit.structure.hamiltonize_result",
    # bi-Hamiltonian structures
    "compatible": "poissonkit.structure.bihamiltonian",
    "recursion_operator": "poissonkit.structure.bihamiltonian",
    "pencil_casimirs": "poissonkit.structure.bihamiltonian",
    "lenard_magri_chain": "poissonkit.structure.bihamiltonian",
    "lenard_magri_chains": "poissonkit.structure.bihamiltonian",
    "LenardMagriChain": "poissonkit.structure.bihamiltonian",
    # Poisson cohomology in low degrees, the modular class
    "poisson_cohomology": "poissonkit.structure.cohomology",
    "PoissonCohomology": "poissonkit.structure.cohomology",
    "modular_class": "poissonkit.structure.cohomology",
    "ModularClass": "poissonkit.structure.cohomology",
    # reduction by symmetry through invariants
    "reduce_by_symmetry": "poissonkit.structure.reduction",
    "ReducedPoissonAlgebra": "poissonkit.structure.reduction",
    # numerics
    "solve": "poissonkit.numerics.solver",
    "Solution": "poissonkit.numerics.solution",
    "compile_system": "poissonkit.numerics.system",
    "NBodySystem": "poissonkit.numerics.nbody",
    "Body": "poissonkit.numerics.nbody",
    "RunSpec": "poissonkit.numerics.runspec",
    "plan_run": "poissonkit.numerics.workload",
    "RunPlan": "poissonkit.numerics.workload",
    # relative equilibria and their stability
    "relative_equilibrium": "poissonkit.numerics.equilibria.relative",
    "RelativeEquilibrium": "poissonkit.numerics.equilibria.relative",
    "linear_stability": "poissonkit.numerics.equilibria.stability",
    "LinearStability": "poissonkit.numerics.equilibria.stability",
    "NoConvergenceError": "poissonkit.numerics.equilibria.errors",
    "SingularPointError": "poissonkit.numerics.equilibria.errors",
    "NotAnEquilibriumError": "poissonkit.numerics.equilibria.errors",
    # external fields (gravity, magnetic fields; docs/fields.md)
    "field": "poissonkit.numerics.fields.base",
    "FieldSpec": "poissonkit.numerics.fields.base",
    "CompiledField": "poissonkit.numerics.fields.base",
    "external_fields": "poissonkit.plugin.registry",
    # magnets
    "pair_interaction": "poissonkit.pairs",
    "PairInteraction": "poissonkit.pairs",
    # scenes
    "load_scene": "poissonkit.scene.loader",
    "build_run": "poissonkit.scene.build",
    # registries (integrators, potentials, ... contributed by plugins)
    "integrators": "poissonkit.plugin.registry",
    "integrator": "poissonkit.plugin.registry",
    "names": "poissonkit.plugin.registry",
    "plugin_reports": "poissonkit.plugin.manager",
    # sweeps (poissonkit.sweeps holds outcomes, designs and plots for the specialist)
    "sweep": "poissonkit.sweeps.api",
}


def __getattr__(name: str) -> object:
    if name == "__version__":  # importlib.metadata is slow to import: only when asked
        from poissonkit._version import __version__

        return __version__
    from poissonkit._lazy import load

    return load(globals(), _LAZY, name)


def __dir__() -> list[str]:
    """The public API only (``__all__``): what tab completion on ``pk.`` offers."""
    return sorted({*__all__, "__version__"})


#: The public names of ``import poissonkit as pk`` (the API reference lists exactly these).
__all__ = ["PoissonkitError", *_LAZY]
