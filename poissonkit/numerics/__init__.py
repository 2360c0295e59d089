"""Numerics: compiled right-hand sides, integrators, diagnostics, work-precision reports.

Public entry points (see ``docs/numerics.md``):

* :class:`~poissonkit.numerics.nbody.NBodySystem`, :class:`~poissonkit.numerics.nbody.Body`,
  :class:`~poissonkit.numerics.nbody.Interaction`, :class:`~poissonkit.numerics.nbody.AllPairs`;
* :class:`~poissonkit.numerics.twobody.TwoBodySystem` (seed 000's 18-variable form);
* :func:`~poissonkit.numerics.system.compile_system` for any symbolic system;
* :func:`~poissonkit.numerics.solver.solve` → :class:`~poissonkit.numerics.solution.Solution`;
* :class:`~poissonkit.numerics.units.Scales`;
* events :class:`~poissonkit.numerics.events.Collision`, :class:`~poissonkit.numerics.events.Escape`.

Submodules are imported lazily so that ``import poissonkit.numerics`` stays cheap.
"""

from __future__ import annotations

from typing import Any

_EXPORTS = {
    "Body": ".nbody", "Interaction": ".nbody", "AllPairs": ".nbody", "NBodySystem": ".nbody",
    "NonUnitAxisError": ".nbody", "OverlapError": ".nbody", "TwoBodySystem": ".twobody", "compile_system": ".system",
    "CompiledSystem": ".system", "solve": ".solver", "Solution": ".solution", "Scales": ".units",
    "Collision": ".events", "Escape": ".events", "compile_potential": ".potentials",
    "RunSpec": ".runspec",
}

__all__ = [
    "AllPairs", "Body", "Collision", "CompiledSystem", "Escape", "Interaction", "NBodySystem",
    "NonUnitAxisError", "OverlapError", "RunSpec", "Scales", "Solution", "TwoBodySystem", "compile_potential",
    "compile_system", "solve",
]


def __getattr__(name: str) -> Any:
    from poissonkit._lazy import load

    return load(globals(), _EXPORTS, name)
