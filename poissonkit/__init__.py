"""poissonkit — Hamiltonian mechanics on Poisson manifolds.

Declare a bracket, prove it is Poisson, find its Casimirs, then integrate the dynamics fast and
accurately. Conventions: :mod:`poissonkit.conventions`.
"""

from __future__ import annotations

import importlib
from importlib.metadata import PackageNotFoundError, version

from poissonkit.errors import PoissonkitError
from poissonkit.structure import (
    Bivector,
    HamiltonianSystem,
    canonical,
    direct_sum,
    e3,
    lie_poisson,
    so3,
    symmetric_top,
)

try:
    __version__ = version("poissonkit")
except PackageNotFoundError:  # running from a source tree without installation
    __version__ = "0.0.0"

# Heavier parts are imported on first use so `import poissonkit` stays fast.
_LAZY: dict[str, str] = {
    "pair_interaction": "poissonkit.interaction",
    "check_jacobi": "poissonkit.structure.jacobi",
    "schouten_bracket": "poissonkit.structure.schouten",
    "find_casimirs": "poissonkit.structure.casimirs",
    "se3": "poissonkit.structure.blocks",
    "p_gf": "poissonkit.structure.deformed",
    "chaplygin_ball": "poissonkit.structure.deformed",
    "solve": "poissonkit.numerics.solver",
    "load_scene": "poissonkit.scene",
    "build_run": "poissonkit.scene",
    "PairInteraction": "poissonkit.interaction",
    "sweep": "poissonkit.sweep",
}


def __getattr__(name: str):
    if name in _LAZY:
        module = importlib.import_module(_LAZY[name])
        return getattr(module, name)
    raise AttributeError(f"module 'poissonkit' has no attribute {name!r}")


__all__ = [
    "Bivector", "HamiltonianSystem", "PoissonkitError", "__version__", "canonical",
    "direct_sum", "e3", "lie_poisson", "so3", "symmetric_top", *_LAZY,
]
