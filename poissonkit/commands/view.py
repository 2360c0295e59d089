"""``poissonkit view OUT``: open the interactive 3D view of a run in the web browser.

``OUT`` is a run's output folder (or its ``trajectory.html`` / ``trajectory.nc``). The page is
the run's ``trajectory.html``; when it is missing (a run with ``--no-plot``) it is built from
``trajectory.nc`` first. Without a browser (a headless machine) the path is printed instead;
``--no-open`` only prints it.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from poissonkit.errors import InputError

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
        Neither a view page nor a trajectory dataset is there.
    """
    folder = target.parent if target.suffix in (".html", ".nc") else target
    page = folder / HTML
    if page.is_file():
        return page
    dataset = folder / DATASET
    if not dataset.is_file():
        raise InputError(f"{folder} has no {HTML} and no {DATASET}: run `poissonkit run --out "
                         f"{folder}` first")
    from poissonkit.report.trajectory import open_trajectory
    from poissonkit.report.view import write_view

    ds = open_trajectory(dataset)
    write_view(page, ds, title=str(ds.attrs.get("scene", "")))
    return page


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
