"""The trajectory files of ``poissonkit run``: ``trajectory.npz``, the xarray dataset
(``trajectory.nc``, or ``trajectory.zarr`` written part by part) and the 3D view
(``trajectory.html``), each written atomically from the streamed parts of the run.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, cast

import numpy as np

from poissonkit.errors import InputError, MissingDependencyError
from poissonkit.numerics.units import Scales
from poissonkit.report.run_units import layout_of, relative_position, unit_system

if TYPE_CHECKING:
    import xarray as xr

    from poissonkit.numerics.runspec import RunSpec
    from poissonkit.numerics.solution import Solution
    from poissonkit.report.netcdf_writer import DatasetDescription


def write_trajectory_files(out: Path, spec: RunSpec, sol: Solution, parts: Path, y: np.ndarray,
                           t: np.ndarray, *, scales: Scales | None, time_unit: float,
                           dataset_max_rows: int, view: bool) -> tuple[list[str], dict[str, str]]:
    """Write ``trajectory.npz`` (one part in memory at a time), the dataset and, with ``view``,
    the 3D view from the parts in ``parts``; ``(t, y)`` are the thinned rows of the figures.

    Returns the file names written (after ``summary.json``) and the summary's entries naming
    them (``trajectory_dataset``, ``view``).
    """
    from poissonkit.report.gather import gather_trajectory
    from poissonkit.report.trajectory import scale_arrays

    lunit = float(scales.length) if scales is not None else 1.0

    def rel_si(rows: np.ndarray) -> np.ndarray | None:
        r = relative_position(spec, rows)
        return None if r is None else r * lunit

    maps: dict[str, Callable[[np.ndarray], np.ndarray]] = (
        {} if rel_si(y[:1]) is None
        else {"r_rel_si": cast(Callable[[np.ndarray], np.ndarray], rel_si)})
    gather_trajectory(out / "trajectory.npz", parts, layout=layout_of(spec.system),
                      time_unit=time_unit, row_maps=maps,
                      **scale_arrays(scales, time_unit))  # one part at a time
    files = ["summary.json", "trajectory.npz"]
    named: dict[str, str] = {}
    nrows = int(sol.extra.get("streamed_rows", len(sol.t)))
    name = "trajectory.nc" if nrows <= dataset_max_rows else "trajectory.zarr"
    if write_dataset_file(out / name, spec, sol, parts, scales, time_unit):
        files.append(name)
        named["trajectory_dataset"] = name
        # the view shows at most a few hundred frames: the figures' rows are plenty
        ds = run_dataset(spec, sol, t, y, scales, time_unit) if view else None
        if ds is not None and write_view_file(out / "trajectory.html", spec, ds):
            files.append("trajectory.html")
            named["view"] = "trajectory.html"
    return files, named


def run_dataset(spec: RunSpec, sol: Solution, t: np.ndarray, y: np.ndarray,
                scales: Scales | None, time_unit: float) -> xr.Dataset:
    """The trajectory rows ``(t, y)`` as an xarray dataset, with the bodies' sizes."""
    return run_description(spec, sol, t, y, scales, time_unit).to_xarray()


def run_description(spec: RunSpec, sol: Solution, t: np.ndarray, y: np.ndarray,
                    scales: Scales | None, time_unit: float) -> DatasetDescription:
    """The dataset of :func:`run_dataset` as plain data (no xarray needed)."""
    from poissonkit.numerics.events import Contact
    from poissonkit.report.trajectory import trajectory_description

    length = float(scales.length) if scales is not None else 1.0
    shapes = {s.name: (s.radius * length, s.half_length * length)
              for e in spec.events if isinstance(e, Contact) for s in e.shapes}
    return trajectory_description(spec.system, t, y, scales=scales, time_unit=time_unit,
                                  attrs={"scene": spec.name, "method": sol.method},
                                  shapes=shapes, units=unit_system(spec))


def write_view_file(path: Path, spec: RunSpec, dataset: xr.Dataset) -> bool:
    """Write the interactive 3D view (``trajectory.html``); ``False`` (with a note) when the
    run has no bodies to show or plotly is missing."""
    from poissonkit.report.view import write_view

    try:
        write_view(path, dataset, title=spec.name)
    except (MissingDependencyError, InputError) as exc:
        print(f"note: no trajectory.html ({exc})", file=sys.stderr)
        return False
    return True


def write_dataset_file(path: Path, spec: RunSpec, sol: Solution, parts: Path,
                       scales: Scales | None, time_unit: float) -> bool:
    """Write the trajectory as a NetCDF dataset (``.nc``, built whole, written by scipy without
    importing xarray: the same bytes as xarray's scipy engine) or a Zarr store written part by
    part (``.zarr``; ``False`` with a note without xarray)."""
    from poissonkit.numerics.checkpoint import read_trajectory
    from poissonkit.report.trajectory import write_description

    if path.suffix != ".zarr":
        write_description(path, run_description(spec, sol, *read_trajectory(parts), scales,
                                                time_unit))
        return True
    from poissonkit.report.gather import gather_dataset

    def build(t: np.ndarray, y: np.ndarray) -> xr.Dataset:
        return run_dataset(spec, sol, t, y, scales, time_unit)

    try:
        gather_dataset(path, parts, build)
    except MissingDependencyError as exc:
        print(f"note: no {path.name} ({exc})", file=sys.stderr)
        return False
    return True
