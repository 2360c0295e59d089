"""Sweeps and ensembles: a scene over a grid or random sample of parameters, on Dask.

``poissonkit.sweep(scene, params, outcomes=..., client=None, store=...)`` runs every point on a
Dask cluster (a local one by default), reduces each run to outcomes from a typed registry
(:data:`OUTCOMES`), and returns an :class:`xarray.Dataset` that is also written to Zarr batch by
batch, so an interrupted sweep resumes where it stopped. Guide: ``docs/sweeps.md``.

Modules: :mod:`~poissonkit.sweeps.params` (design), :mod:`~poissonkit.sweeps.paths` (parameter
paths of a scene file), :mod:`~poissonkit.sweeps.targets` (what one run is),
:mod:`~poissonkit.sweeps.outcomes` (registry), :mod:`~poissonkit.sweeps.chaos` (MEGNO),
:mod:`~poissonkit.sweeps.execute` (Dask), :mod:`~poissonkit.sweeps.store` (Zarr),
:mod:`~poissonkit.sweeps.integrity` (chunk ownership, completion records, verified resume),
:mod:`~poissonkit.sweeps.plot` (stability maps).
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING

from poissonkit.sweeps.api import sweep
from poissonkit.sweeps.chaos import megno
from poissonkit.sweeps.integrity import StoreRepairWarning
from poissonkit.sweeps.outcomes import DEFAULT_OUTCOMES, OUTCOMES, Outcome
from poissonkit.sweeps.params import Axis, Design, Range, grid, parse_param
from poissonkit.sweeps.paths import SweepPathError
from poissonkit.sweeps.targets import FATES, TomlScene, sweep_scene

if TYPE_CHECKING:
    import xarray as xr


def stability_map(ds: xr.Dataset, path: str | Path, *, x: str | None = None,
                  y: str | None = None, mark: Mapping[str, float] | None = None,
                  chaos: str | None = "megno", title: str | None = None,
                  labels: Mapping[str, str] | None = None, dpi: int = 110) -> Path:
    """Draw a stability map to PNG (see :func:`poissonkit.sweeps.plot.stability_map`); matplotlib
    is imported only here."""
    from poissonkit.sweeps.plot import stability_map as draw

    return draw(ds, path, x=x, y=y, mark=mark, chaos=chaos, title=title, labels=labels, dpi=dpi)


__all__ = [
    "DEFAULT_OUTCOMES", "FATES", "OUTCOMES", "Axis", "Design", "Outcome", "Range",
    "StoreRepairWarning", "SweepPathError", "TomlScene", "grid", "megno", "parse_param",
    "stability_map", "sweep",
    "sweep_scene",
]
