"""Time integrators, one module per family.

Contract: an integrator object has ``name``, ``order`` and
``integrate(system, y0, t_end, *, step, tol, events, progress, save_every) -> RawResult``;
:func:`poissonkit.numerics.solve` wraps it into a :class:`~poissonkit.numerics.Solution`.
Registry entries (name, doc, typed parameters) live in :mod:`poissonkit.numerics.builtin`.
"""

from poissonkit.numerics.integrators.base import RawResult

__all__ = ["RawResult"]
