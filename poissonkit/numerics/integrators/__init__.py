"""Time integrators, one module per family.

Contract: :class:`poissonkit.contracts.Integrator` — an object with ``name``, ``order``,
``capabilities`` (:class:`~poissonkit.plugin.contributions.Capabilities`, declared once per
family in :mod:`~poissonkit.numerics.integrators.capabilities`) and
``integrate(system, y0, t_end, *, step, tol, events, progress, save_every, t0, control)
-> RawResult``; :func:`poissonkit.numerics.solve` checks the capabilities and wraps the result
into a :class:`~poissonkit.numerics.Solution`. The compiled loops share
:func:`~poissonkit.numerics.integrators.driver.drive` (events, checkpoints, streaming, stop).
Registry entries (name, doc, typed parameters, capabilities) live in
:mod:`poissonkit.numerics.hooks`.
"""

from poissonkit.numerics.integrators.base import RawResult

__all__ = ["RawResult"]
