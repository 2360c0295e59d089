"""Sweeps and ensembles: a scene over a grid or random sample of parameters, on Dask.

``poissonkit.sweep(scene, params, outcomes=..., client=None, store=...)`` runs every point on a
Dask cluster (a local one by default), reduces each run to outcomes from a typed registry
(:data:`OUTCOMES`), and returns an :class:`xarray.Dataset` that is also written to Zarr batch by
batch, so an interrupted sweep resumes where it stopped. Guide: ``docs/sweeps.md``.

Modules: :mod:`~poissonkit.sweep.params` (design), :mod:`~poissonkit.sweep.scenes` (what one run
is), :mod:`~poissonkit.sweep.outcomes` (registry), :mod:`~poissonkit.sweep.chaos` (MEGNO),
:mod:`~poissonkit.sweep.execute` (Dask), :mod:`~poissonkit.sweep.store` (Zarr),
:mod:`~poissonkit.sweep.plot` (stability maps).
"""

from __future__ import annotations

import sys
import types
from typing import Any

from poissonkit.sweep.api import sweep
from poissonkit.sweep.chaos import megno
from poissonkit.sweep.outcomes import DEFAULT_OUTCOMES, OUTCOMES, Outcome
from poissonkit.sweep.params import Axis, Design, Range, grid, parse_param
from poissonkit.sweep.scenes import FATES, SeedScene, TomlScene, sweep_scene


def stability_map(*args: Any, **kwargs: Any) -> Any:
    """Draw a stability map to PNG (see :func:`poissonkit.sweep.plot.stability_map`)."""
    from poissonkit.sweep.plot import stability_map as draw

    return draw(*args, **kwargs)


class _CallableModule(types.ModuleType):
    """``poissonkit.sweep`` is both this subpackage and the function :func:`sweep`: once the
    subpackage is imported, Python binds the name ``poissonkit.sweep`` to the module, so the
    module forwards calls to the function."""

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        return sweep(*args, **kwargs)


sys.modules[__name__].__class__ = _CallableModule

__all__ = [
    "DEFAULT_OUTCOMES", "FATES", "OUTCOMES", "Axis", "Design", "Outcome", "Range", "SeedScene",
    "TomlScene", "grid", "megno", "parse_param", "stability_map", "sweep", "sweep_scene",
]
