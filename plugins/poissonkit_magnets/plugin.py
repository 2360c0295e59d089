"""pluggy hook implementations of the magnets plugin.

Contributes the pair potentials of :mod:`poissonkit_magnets.models` (names and parameters as in
docs/architecture.md, "Magnet potential names and parameters"; the extra models are documented in
docs/magnets.md).
"""

from __future__ import annotations

from functools import partial

from poissonkit.plugin.contributions import PairPotential
from poissonkit.plugin.hookspecs import hookimpl
from poissonkit_magnets.models import MODELS, kernel


# Built once per process: compiled kernels are cached per entry, so handing out the same
# entries after every plugin-manager rebuild avoids recompiling them.
_ENTRIES: tuple[PairPotential, ...] = tuple(
    PairPotential(name=m.name, doc=m.doc, params=m.params, expr=m.expr,
                  kernel=partial(kernel, m.name), orientation="both")
    for m in MODELS
)


@hookimpl
def poissonkit_potentials() -> list[PairPotential]:
    """The magnet pair potentials (SI units)."""
    return list(_ENTRIES)
