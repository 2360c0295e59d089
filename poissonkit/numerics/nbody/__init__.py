"""Compiled N-body dynamics of symmetric tops and point masses (being split into modules)."""

from poissonkit.numerics.nbody.system import (  # noqa: F401
    PARALLEL_MIN_BODIES,
    AllPairs,
    Body,
    Interaction,
    NBodySystem,
    NonUnitAxisError,
    OverlapError,
    _resolve_kernel,
    apply_forces,
    cell_list,
    coincident_pair,
    evaluate_energy,
    evaluate_rhs,
    forward_cells,
)
