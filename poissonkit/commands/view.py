"""``poissonkit view OUT``: open the interactive 3D view of a run in the web browser.

``OUT`` is a run's output folder (or its ``trajectory.html`` / ``trajectory.nc``). The page is
the run's ``trajectory.html``; when it is missing (a run with ``--no-plot``) it is built from
``trajectory.nc`` first. Without a browser (a headless machine) the path is printed instead;
``--no-open`` only prints it.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING

from poissonkit.errors import InputError

if TYPE_CHECKING:
    import xarray as xr

HTML = "trajectory.html"
DATASET = "trajectory.nc"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``poissonkit view``."""
    parser.add_argument("out", nargs="?", default="poissonkit-output",
                        help="output folder of `poissonkit run` (default: poissonkit-output)")
    parser.add_argument("--no-open", action="store_true",
                        help="only build the page if needed and print its path")


def page_of(target: Path) -> Path:
    """The view page of a run folder, building it from the trajectory dataset if needed.

    Raises
    ------
    InputError
        Neither a view page nor a trajectory dataset is there, or what is there is damaged
        (a truncated or all-NaN dataset, a page that is a folder): one line naming the file.
    """
    folder = target.parent if target.suffix in (".html", ".nc") else target
    page = folder / HTML
    if page.is_file():
        return page
    if page.exists() or page.is_symlink():
        raise InputError(f"{page} is not a file (a folder, or a broken link); remove it to "
                         f"build the view again from {DATASET}")
    dataset = folder / DATASET
    if not dataset.is_file():
        raise InputError(f"{folder} has no {HTML} and no {DATASET}: run `poissonkit run --out "
                         f"{folder}` first")
    from poissonkit.report.view import write_view

    ds = _read_dataset(dataset)
    _check_dataset(ds, dataset)
    try:
        write_view(page, ds, title=str(ds.attrs.get("scene", "")))
    except (ValueError, IndexError, KeyError, TypeError) as exc:  # plotly's, numpy's
        raise InputError(f"{dataset} cannot be shown ({type(exc).__name__}: "
                         f"{str(exc).splitlines()[0] if str(exc) else 'damaged'}); is it a "
                         "trajectory written by `poissonkit run`?") from None
    return page


def _read_dataset(path: Path) -> xr.Dataset:
    """The dataset at ``path``; a damaged file is one line of :class:`InputError`."""
    import struct

    from poissonkit.report.trajectory import open_trajectory

    try:
        return open_trajectory(path)
    except InputError as exc:  # xarray's messages may run over several lines
        raise InputError(str(exc).strip().splitlines()[0]) from None
    except (IndexError, KeyError, EOFError, OverflowError, MemoryError, struct.error) as exc:
        # scipy's NetCDF reader on a truncated file reads past its end
        raise InputError(f"cannot read the trajectory dataset {str(path)!r}: it is truncated "
                         f"or damaged ({type(exc).__name__})") from None


def _check_dataset(ds: xr.Dataset, path: Path) -> None:
    """:class:`InputError` unless ``ds`` has saved times and some finite positions."""
    import numpy as np

    if "time" not in ds.dims or ds.sizes["time"] == 0:
        raise InputError(f"{path} holds no saved time; it is not a run's trajectory")
    names = [n for n in ("position", "relative_position") if n in ds.data_vars]
    if not names:
        raise InputError(f"{path} has no position variable; it is not a run's trajectory")
    values = [np.asarray(ds[n].values, dtype=float) for n in names]
    if not any(np.isfinite(v).any() for v in values):
        raise InputError(f"{path}: every position is NaN or infinite; nothing to show (the "
                         "file is damaged, or the run failed at its first step)")


def main(args: argparse.Namespace) -> int:
    """Open (or print) the run's view page."""
    page = page_of(Path(args.out)).resolve()
    if args.no_open:
        print(page)
        return 0
    import webbrowser

    if not webbrowser.open(page.as_uri()):
        print(f"no web browser found; open {page} in one")
        return 0
    print(f"opened {page}")
    return 0
