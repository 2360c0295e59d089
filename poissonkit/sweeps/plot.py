"""Stability maps: fate as colours, the chaos indicator as a second panel, written to PNG."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from poissonkit.errors import InputError
from poissonkit.sweeps.targets import FATES

if TYPE_CHECKING:  # matplotlib and xarray are imported where used
    import xarray as xr
    from matplotlib.axes import Axes
    from matplotlib.collections import QuadMesh

#: Colours of the fates (bounded, collision, escape) and of failed / missing points.
FATE_COLOURS = ("#2c7fb8", "#d7301f", "#fdae61")
FAILED_COLOUR = "#bdbdbd"


def _axes_of(ds: xr.Dataset, x: str | None, y: str | None) -> tuple[str, str]:
    dims = [d for d in ds["fate"].dims]
    if len(dims) != 2:
        raise InputError(f"a stability map needs a sweep over two parameters; this one has "
                         f"dimensions {dims}")
    x = x or dims[1]
    y = y or dims[0]
    for name in (x, y):
        if name not in dims:
            raise InputError(f"{name!r} is not a dimension of the sweep; available: "
                             + ", ".join(dims))
    return x, y


def draw_map(ax_fate: Axes, ax_chaos: Axes | None, ds: xr.Dataset, x: str | None = None,
             y: str | None = None, mark: Mapping[str, float] | None = None,
             chaos: str = "megno", labels: Mapping[str, str] | None = None
             ) -> QuadMesh | None:
    """Draw the fate map (and the chaos map) of a two-parameter sweep on given axes.

    Returns the chaos panel's image (for a colour bar), or ``None``.
    """
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Patch

    x, y = _axes_of(ds, x, y)
    labels = dict(labels or {})
    fate = ds["fate"].transpose(y, x).values.astype(float)
    failed = ds["failed"].transpose(y, x).values
    fate[(fate < 0) | failed] = len(FATES)
    xs, ys = ds[x].values, ds[y].values
    cmap = ListedColormap([*FATE_COLOURS, FAILED_COLOUR])
    ax_fate.pcolormesh(xs, ys, fate, cmap=cmap, vmin=-0.5, vmax=len(FATES) + 0.5,
                       shading="nearest")
    handles = [Patch(color=c, label=f) for c, f in zip(FATE_COLOURS, FATES)]
    if np.any(fate == len(FATES)):
        handles.append(Patch(color=FAILED_COLOUR, label="failed / missing"))
    ax_fate.legend(handles=handles, loc="upper right", fontsize=7, framealpha=0.9)

    def label(name: str) -> str:
        unit = ds[name].attrs.get("units", "")
        return labels.get(name, name + (f" [{unit}]" if unit and unit != "1" else ""))

    image = None
    panels = [ax_fate] + ([ax_chaos] if ax_chaos is not None else [])
    if ax_chaos is not None:
        if chaos not in ds:
            raise InputError(f"outcome {chaos!r} was not computed in this sweep; available: "
                             + ", ".join(v for v in ds.data_vars))
        val = ds[chaos].transpose(y, x).values.astype(float)
        val = np.where(fate == 0, val, np.nan)  # the indicator of a finished (bounded) run only
        image = ax_chaos.pcolormesh(xs, ys, np.log10(np.clip(val, 0.1, None)), cmap="viridis",
                                    shading="nearest", vmin=np.log10(0.5), vmax=np.log10(50))
        ax_chaos.set_title(f"log10 {chaos} (bounded runs; 2 = regular)", fontsize=9)
    ax_fate.set_title("fate", fontsize=9)
    for ax in panels:
        ax.set_xlabel(label(x))
        ax.set_ylabel(label(y))
        if mark:
            ax.plot([mark[x]], [mark[y]], marker="*", color="white", markeredgecolor="black",
                    markersize=13, linestyle="none")
    return image


def stability_map(ds: xr.Dataset, path: str | Path, *, x: str | None = None, y: str | None = None,
                  mark: Mapping[str, float] | None = None, chaos: str | None = "megno",
                  title: str | None = None, labels: Mapping[str, str] | None = None,
                  dpi: int = 110) -> Path:
    """Write a stability map of a two-parameter sweep to a PNG file.

    Parameters
    ----------
    ds
        A sweep dataset (:func:`poissonkit.sweeps.sweep`) with a ``fate`` variable.
    path
        Output file (``.png``).
    x, y
        Dimensions on the horizontal / vertical axis (default: last / first).
    mark
        A parameter point to mark with a star, ``{x: value, y: value}``.
    chaos
        Outcome drawn in the second panel (``None``: fate panel only; skipped if not computed).
    title, labels, dpi
        Figure title, axis labels by dimension, resolution.

    Returns
    -------
    pathlib.Path
        The file written.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    panels = 2 if chaos is not None and chaos in ds else 1
    fig, axes = plt.subplots(1, panels, figsize=(5.2 * panels, 4.2), squeeze=False)
    image = draw_map(axes[0][0], axes[0][1] if panels == 2 else None, ds, x, y, mark,
                     chaos or "megno", labels)
    if image is not None:
        fig.colorbar(image, ax=axes[0][1], label=f"log10 {chaos}")
    if title:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    from poissonkit.report.atomic import atomic_path

    out = Path(path)
    with atomic_path(out) as tmp:  # a reader never sees half a PNG
        fig.savefig(tmp, dpi=dpi)
    plt.close(fig)
    return out


def boundary(ds: xr.Dataset, along: str) -> xr.DataArray:
    """For each value of the other dimension, the smallest ``along`` value from which every
    larger value is bounded (``nan`` if none): the stability boundary of a 2-D map."""
    import xarray as xr

    bounded = (ds["fate"] == 0) & ~ds["failed"]
    vals = ds[along].values
    order = np.argsort(vals)
    b = bounded.isel({along: order}).astype(int)
    tail = b.isel({along: slice(None, None, -1)}).cumprod(along).isel(
        {along: slice(None, None, -1)}).astype(bool)  # bounded from here on
    first = tail.argmax(along)
    has = tail.any(along)
    return xr.DataArray(np.where(has.values, vals[order][first.values], np.nan),
                        dims=has.dims, coords=has.coords, attrs={"units": ds[along].attrs.get(
                            "units", "1"), "long_name": f"stability boundary in {along}"})
