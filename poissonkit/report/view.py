"""The interactive 3D view of a run: a small HTML page (``trajectory.html``).

Built with plotly's offline HTML writer: bodies drawn to scale as spheres or cylinders along
their symmetry axes, axes of tops as line segments, the paths of the bodies, field sources with
a shape (magnets, rings, loops: :mod:`poissonkit.report.source_shapes`) as translucent meshes,
an animation with a time slider, and body names on hover. The page loads plotly.js from one
file beside it (``plotly.min.js``, written once per folder and shared by every page there), so
it opens without a network and the page itself stays small. Coordinates are in the unit
:mod:`poissonkit.report.axis_units` chooses (mm for magnets, AU for planets), with ticks in
exponent notation, never SI prefixes ("4T" would read as tesla). Input is the run's trajectory dataset (:mod:`poissonkit.report.trajectory`,
SI units), so ``poissonkit view`` can also rebuild the page from a ``trajectory.nc``.

The two-body centre-of-mass form of the seed scene has only the relative position: the view
shows it in the frame of the first body (first body at the origin), and says so in its title.

Large scenes stay bounded: meshes and axes for at most :data:`MESH_BODIES` bodies (markers
beyond), at most :data:`MAX_POINTS` body positions over all frames.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING

import numpy as np

from poissonkit.errors import InputError, MissingDependencyError
from poissonkit.report.axis_units import dataset_units, length_unit_for, time_unit_for
from poissonkit.report.source_shapes import SourceShape, mesh

if TYPE_CHECKING:
    import plotly.graph_objects as go
    import xarray as xr
    from plotly.basedatatypes import BaseTraceType

    from poissonkit.numerics.unitsystem import UnitSystem

#: Bodies drawn as meshes (spheres, cylinders); more are drawn as markers.
MESH_BODIES = 40
#: Most animation frames.
MAX_FRAMES = 150
#: Most body positions over all frames (bounds the file size for large N: about 16 bytes each).
MAX_POINTS = 400_000
#: Mesh resolution: points around a cylinder, latitude × longitude bands of a sphere.
RING = 16
SPHERE = (8, 14)

#: The plotly.js bundle every page of a folder loads (written beside them once).
PLOTLY_JS = "plotly.min.js"

__all__ = ["PLOTLY_JS", "view_figure", "write_view"]


def _plotly() -> ModuleType:
    try:
        import plotly.graph_objects as go
    except ImportError:
        raise MissingDependencyError("the 3D view needs plotly: pip install plotly") from None
    return go


def _sphere_template() -> tuple[np.ndarray, np.ndarray]:
    """Unit-sphere vertices ``(n, 3)`` and triangles ``(m, 3)``."""
    n_lat, n_lon = SPHERE
    theta = np.linspace(0, np.pi, n_lat + 1)[1:-1]
    phi = np.linspace(0, 2 * np.pi, n_lon, endpoint=False)
    ring = np.stack([np.outer(np.sin(theta), np.cos(phi)), np.outer(np.sin(theta), np.sin(phi)),
                     np.outer(np.cos(theta), np.ones_like(phi))], axis=-1).reshape(-1, 3)
    verts = np.vstack([[0, 0, 1], ring, [0, 0, -1]])
    top, bottom = 0, len(verts) - 1
    tris = []
    for j in range(n_lon):
        tris.append((top, 1 + j, 1 + (j + 1) % n_lon))
    for i in range(n_lat - 2):
        for j in range(n_lon):
            a, b = 1 + i * n_lon + j, 1 + i * n_lon + (j + 1) % n_lon
            c, d = a + n_lon, b + n_lon
            tris += [(a, c, b), (b, c, d)]
    last = 1 + (n_lat - 2) * n_lon
    for j in range(n_lon):
        tris.append((bottom, last + (j + 1) % n_lon, last + j))
    return verts, np.array(tris)


def _cylinder_template() -> tuple[np.ndarray, np.ndarray]:
    """Cylinder of radius 1 from z = −1 to z = 1 along z: vertices and triangles."""
    phi = np.linspace(0, 2 * np.pi, RING, endpoint=False)
    circle = np.stack([np.cos(phi), np.sin(phi)], axis=-1)
    lower = np.column_stack([circle, -np.ones(RING)])
    upper = np.column_stack([circle, np.ones(RING)])
    verts = np.vstack([lower, upper, [0, 0, -1], [0, 0, 1]])
    cb, ct = 2 * RING, 2 * RING + 1
    tris = []
    for j in range(RING):
        k = (j + 1) % RING
        tris += [(j, k, RING + j), (k, RING + k, RING + j), (cb, k, j), (ct, RING + j, RING + k)]
    return verts, np.array(tris)


def _unit_axis(axis: np.ndarray) -> np.ndarray | None:
    """``axis`` as a unit vector; ``None`` when it has no direction (zero, NaN or infinite)."""
    if not np.all(np.isfinite(axis)):
        return None
    big = float(np.abs(axis).max())
    if big == 0.0:
        return None
    z = axis / big  # scaled first: the norm of a huge (damaged) axis does not overflow
    return z / np.linalg.norm(z)


def _frame_of(axis: np.ndarray) -> np.ndarray:
    """Rotation matrix whose third column is the unit vector ``axis`` (a unit vector)."""
    z = axis
    helper = np.array([1.0, 0, 0]) if abs(z[0]) < 0.9 else np.array([0, 1.0, 0])
    x = np.cross(helper, z)
    x /= np.linalg.norm(x)
    return np.column_stack([x, np.cross(z, x), z])


def _positions(ds: xr.Dataset) -> tuple[np.ndarray, np.ndarray, list[str], str]:
    """Positions and axes ``(time, body, 3)`` [m] (axis NaN: not a top), names, a frame note."""
    if "body" not in ds.coords:
        raise InputError("the trajectory has no bodies (a system without positions): nothing "
                         "to show in 3D")
    names = [str(b) for b in ds["body"].values]
    n_t = ds.sizes["time"]
    axis = ds["axis"].values if "axis" in ds else np.full((n_t, len(names), 3), np.nan)
    if "position" in ds:
        return ds["position"].values, axis, names, ""
    if "relative_position" in ds:  # two-body centre-of-mass form: the first body's frame
        pos = np.zeros((n_t, len(names), 3))
        pos[:, 1] = ds["relative_position"].values
        return pos, axis, names, f" (frame of {names[0]})"
    raise InputError("the trajectory dataset has neither 'position' nor 'relative_position'")


def _dataset_shapes(ds: xr.Dataset, names: list[str]) -> dict[str, tuple[float, float]]:
    """``{name: (radius, half_length)}`` from the dataset's shape variables (sized bodies)."""
    if "radius" not in ds:
        return {}
    radius = ds["radius"].values
    half = ds["half_length"].values if "half_length" in ds else np.zeros_like(radius)
    return {n: (float(r), float(h)) for n, r, h in zip(names, radius, half)
            if np.isfinite(r) and r > 0}


def _in_si(ds: xr.Dataset, pos: np.ndarray, names: list[str]
           ) -> tuple[UnitSystem, np.ndarray, np.ndarray, dict[str, tuple[float, float]]]:
    """The dataset's units (a scene's own: AU, yr), and its positions, times and shapes back
    in SI (the figure then shows them in those units)."""
    units = dataset_units(ds.attrs)
    length = units.si_per_unit("length")
    times = np.asarray(ds["time"].values, dtype=float) * units.si_per_unit("time")
    shapes = {n: (r * length, h * length) for n, (r, h) in _dataset_shapes(ds, names).items()}
    return units, pos * length, times, shapes


#: Largest coordinate the page can hold: it stores single precision.
_FLOAT32_MAX = float(np.finfo(np.float32).max)


def _scaled(shapes: Mapping[str, tuple[float, float]], factor: float
            ) -> dict[str, tuple[float, float]]:
    """``{body: (radius, half_length)}`` times ``factor``."""
    return {n: (r * factor, h * factor) for n, (r, h) in shapes.items()}


def _check_drawable(pos: np.ndarray, shapes: Mapping[str, tuple[float, float]],
                    unit: str) -> None:
    """:class:`InputError` for positions or sizes beyond single precision in the axis unit (a
    damaged dataset: a real scene gets a unit in which its extent is a few thousand at most)."""
    for what, values in (("positions", pos),
                         ("sizes", np.array([v for rh in shapes.values() for v in rh]))):
        finite = np.abs(values[np.isfinite(values)])
        if finite.size and float(finite.max()) > _FLOAT32_MAX / 1e3:
            raise InputError(f"trajectory dataset: {what} up to {float(finite.max()):.3g} "
                             f"{unit} are beyond what the 3D view can draw (the file is "
                             "damaged?)")


def _frames_index(n_t: int, n_bodies: int, max_frames: int) -> np.ndarray:
    n = int(min(max_frames, max(2, MAX_POINTS // max(n_bodies, 1)), n_t))
    return np.unique(np.linspace(0, n_t - 1, n).round().astype(int))


def view_figure(dataset: xr.Dataset, shapes: Mapping[str, tuple[float, float]] | None = None,
                *, title: str = "", max_frames: int = MAX_FRAMES,
                sources: Sequence[SourceShape] = ()) -> go.Figure:
    """The animated 3D figure of a trajectory dataset.

    Parameters
    ----------
    dataset
        A trajectory dataset (:func:`poissonkit.report.trajectory.trajectory_dataset`): SI, or
        a scene's own units (its ``units_*`` attributes), which the axes and slider then show.
    shapes
        ``{body name: (radius, half_length)}`` in metres: a body with a half-length and an axis
        is a cylinder, otherwise a sphere; bodies without a shape get a marker-sized sphere
        (1 % of the scene's extent; the hover text says it is not to scale). Default: the
        dataset's ``radius`` and ``half_length`` variables.
    title
        Title of the page (the scene name).
    max_frames
        Most animation frames (evenly spaced saved states, first and last included).
    sources
        Field sources to draw (:func:`poissonkit.report.source_shapes.source_shapes` of the
        run's system), translucent and fixed.

    Returns
    -------
    plotly.graph_objects.Figure

    Raises
    ------
    InputError
        The dataset has no bodies.
    MissingDependencyError
        plotly is not installed.
    """
    go = _plotly()
    pos, axis, names, frame_note = _positions(dataset)
    units, pos, times, own_shapes = _in_si(dataset, pos, names)
    unit = length_unit_for(float(np.nanmax(np.abs(pos))) if pos.size else 0.0, units)
    pos = pos / unit.size
    shapes = _scaled(own_shapes if shapes is None else shapes, 1 / unit.size)
    _check_drawable(pos, shapes, unit.name)
    tunit = time_unit_for(float(times[-1]) if times.size else 0.0, units)
    source_meshes = [(src.label, (mesh(src)[0] / unit.size).astype(np.float32),
                      mesh(src)[1].astype(np.int32)) for src in sources]
    pick = _frames_index(len(times), len(names), max_frames)
    pos, axis, times = pos[pick], axis[pick], times[pick]
    # what is drawn needs no more than single precision; it halves the file
    shown = pos.astype(np.float32)
    lo, hi = np.nanmin(pos, axis=(0, 1)), np.nanmax(pos, axis=(0, 1))
    for _, v, _ in source_meshes:  # the sources are in the box too
        lo, hi = np.minimum(lo, v.min(axis=0)), np.maximum(hi, v.max(axis=0))
    extent = float(np.max(hi - lo)) or max((max(s) for s in shapes.values()), default=1.0)
    default_radius = 0.01 * extent
    size = {n: shapes.get(n, (default_radius, 0.0)) for n in names}
    reach = max(max(r, h) for r, h in size.values())
    pad = 1.5 * reach + 0.02 * extent
    lo, hi = lo - pad, hi + pad
    # equal scales on the three axes (spheres stay round); a flat scene is widened to 30 % of
    # its largest extent so that it is not a sliver
    widest = float(np.max(hi - lo))
    grow = np.maximum(0.3 * widest - (hi - lo), 0.0) / 2
    lo, hi = lo - grow, hi + grow
    ranges = [[float(lo[k]), float(hi[k])] for k in range(3)]
    ratio = {c: float((hi[k] - lo[k]) / widest) for k, c in enumerate("xyz")}
    meshes = len(names) <= MESH_BODIES
    fixed = {n for n, f in zip(names, dataset["fixed"].values) if f} if "fixed" in dataset \
        else set()
    sphere, cylinder = _sphere_template(), _cylinder_template()
    sphere = (sphere[0], sphere[1].astype(np.int32))
    cylinder = (cylinder[0], cylinder[1].astype(np.int32))

    def body_mesh(k: int, f: int) -> np.ndarray:
        radius, half = size[names[k]]
        a = _unit_axis(axis[f, k])
        if half > 0 and a is not None:
            verts = cylinder[0] * np.array([radius, radius, half])
            verts = verts @ _frame_of(a).T
        else:
            verts = sphere[0] * radius
        return (verts + pos[f, k]).astype(np.float32)  # single precision: half the page

    def axes_segments(f: int) -> np.ndarray:
        seg = []
        if not meshes:  # markers only: an axis per body would triple the file for nothing
            return np.empty((0, 3))
        for k, n in enumerate(names):
            a = _unit_axis(axis[f, k])
            if a is not None:
                length = 1.8 * max(size[n])
                seg += [pos[f, k], pos[f, k] + length * a, [np.nan] * 3]
        return np.array(seg, dtype=np.float32).reshape(-1, 3)

    notes = [n + (" (fixed)" if n in fixed else "")
             + ("" if n in shapes else " (size not to scale)") for n in names]

    def frame_traces(f: int, full: bool) -> list[BaseTraceType]:
        """The moving traces at frame ``f``; ``full``: with everything that does not move
        (the first frame), else coordinates only (plotly merges a frame into the traces)."""
        traces: list[BaseTraceType] = []
        if meshes:
            for k, n in enumerate(names):
                v = body_mesh(k, f)
                if not full:
                    traces.append(go.Mesh3d(x=v[:, 0], y=v[:, 1], z=v[:, 2]))
                    continue
                tris = cylinder[1] if len(v) == len(cylinder[0]) else sphere[1]
                traces.append(go.Mesh3d(
                    x=v[:, 0], y=v[:, 1], z=v[:, 2], i=tris[:, 0], j=tris[:, 1], k=tris[:, 2],
                    name=n, showlegend=True, flatshading=True, opacity=0.9,
                    color=_COLORS[k % len(_COLORS)], hoverinfo="name"))
        seg = axes_segments(f)
        traces.append(go.Scatter3d(x=seg[:, 0], y=seg[:, 1], z=seg[:, 2]) if not full else
                      go.Scatter3d(x=seg[:, 0], y=seg[:, 1], z=seg[:, 2], mode="lines",
                                   name="axes", line={"color": "black", "width": 4},
                                   hoverinfo="skip", showlegend=bool(len(seg))))
        if not full:
            traces.append(go.Scatter3d(x=shown[f, :, 0], y=shown[f, :, 1], z=shown[f, :, 2]))
            return traces
        traces.append(go.Scatter3d(
            x=shown[f, :, 0], y=shown[f, :, 1], z=shown[f, :, 2], mode="markers", name="bodies",
            text=notes, hovertemplate=f"%{{text}}<br>x=%{{x:.4g}} {unit.name}<br>"
                                      f"y=%{{y:.4g}} {unit.name}<br>"
                                      f"z=%{{z:.4g}} {unit.name}<extra></extra>",
            marker={"size": 3 if meshes else 2, "color": "black" if meshes else "steelblue"},
            showlegend=not meshes))
        return traces

    paths = []
    if meshes:
        for k, n in enumerate(names):
            paths.append(go.Scatter3d(x=shown[:, k, 0], y=shown[:, k, 1], z=shown[:, k, 2],
                                      mode="lines", name=f"path of {n}", showlegend=False,
                                      line={"color": _COLORS[k % len(_COLORS)], "width": 2},
                                      hoverinfo="skip", opacity=0.5))
    first = frame_traces(0, full=True)
    moving = list(range(len(paths), len(paths) + len(first)))
    frames = [go.Frame(data=frame_traces(f, full=False), traces=moving, name=str(f))
              for f in range(len(times))]
    slider, play = _controls([f"{t / tunit.size:.4g} {tunit.name}" for t in times])
    # exponent ticks ("1e+12"), never SI prefixes: "4T" would read as tesla
    axis_titles = {f"{c}axis": {"title": f"{c} [{unit.name}]", "range": ranges[i],
                                "exponentformat": "e"}
                   for i, c in enumerate("xyz")}
    # sources after the moving traces: the frames address those by index
    fig = go.Figure(data=[*paths, *first, *_source_traces(go, source_meshes)], frames=frames)
    count = f"{len(names)} bod{'y' if len(names) == 1 else 'ies'}"
    fig.update_layout(title=f"{title or 'poissonkit run'}: {count}{frame_note}",
                      scene={**axis_titles, "aspectmode": "manual", "aspectratio": ratio},
                      sliders=[slider], updatemenus=[play], margin={"l": 0, "r": 0, "b": 0})
    return fig


def _source_traces(go: ModuleType, meshes: list[tuple[str, np.ndarray, np.ndarray]]
                   ) -> list[BaseTraceType]:
    """Translucent, fixed meshes of the field sources."""
    return [go.Mesh3d(x=v[:, 0], y=v[:, 1], z=v[:, 2], i=tris[:, 0], j=tris[:, 1], k=tris[:, 2],
                      name=f"source: {what}", showlegend=True, opacity=0.35, color="sienna",
                      flatshading=True, hoverinfo="name")
            for what, v, tris in meshes]


def _controls(labels: list[str]) -> tuple[dict, dict]:
    """The time slider (one step per frame, labelled) and the play/pause buttons."""
    slider = {"active": 0, "currentvalue": {"prefix": "t = "}, "pad": {"t": 30},
              "steps": [{"label": label, "method": "animate",
                         "args": [[str(f)], {"mode": "immediate", "frame": {"duration": 0,
                                  "redraw": True}, "transition": {"duration": 0}}]}
                        for f, label in enumerate(labels)]}
    play = {"type": "buttons", "showactive": False, "x": 0.05, "y": 0.05,
            "buttons": [{"label": "play", "method": "animate",
                         "args": [None, {"frame": {"duration": 60, "redraw": True},
                                         "fromcurrent": True, "transition": {"duration": 0}}]},
                        {"label": "pause", "method": "animate",
                         "args": [[None], {"mode": "immediate",
                                           "frame": {"duration": 0, "redraw": False}}]}]}
    return slider, play


#: Body colours (plotly's default qualitative palette).
_COLORS = ("#636efa", "#ef553b", "#00cc96", "#ab63fa", "#ffa15a", "#19d3f3", "#ff6692",
           "#b6e880", "#ff97ff", "#fecb52")


def write_view(path: str | Path, dataset: xr.Dataset,
               shapes: Mapping[str, tuple[float, float]] | None = None, *,
               title: str = "", sources: Sequence[SourceShape] = ()) -> Path:
    """Write the 3D view of ``dataset`` as an HTML page, atomically, with plotly.js beside it.

    Parameters
    ----------
    path
        Output file (``trajectory.html``).
    dataset, shapes, title, sources
        As in :func:`view_figure`.

    Returns
    -------
    pathlib.Path
        ``path``; :data:`PLOTLY_JS` is in the same folder (written if missing or different).
    """
    from poissonkit.files.atomic import atomic_path

    fig = view_figure(dataset, shapes, title=title, sources=sources)
    path = Path(path)
    _write_plotly_js(path.parent)
    with atomic_path(path) as tmp:
        # plotly.js from the file beside the page: no network (no CDN), one copy per folder
        fig.write_html(str(tmp), include_plotlyjs=PLOTLY_JS, full_html=True, auto_play=False)
    return path


def _write_plotly_js(folder: Path) -> Path:
    """:data:`PLOTLY_JS` in ``folder``: kept when it is this plotly's bundle, else a hard link
    to the bundle plotly installs (no second copy on disk; a copy across file systems)."""
    import os
    import shutil

    import plotly

    from poissonkit.files.atomic import atomic_path

    bundle = Path(plotly.__file__).parent / "package_data" / PLOTLY_JS
    target = folder / PLOTLY_JS
    if target.is_file() and (target.samefile(bundle) or (
            target.stat().st_size == bundle.stat().st_size
            and target.read_bytes() == bundle.read_bytes())):
        return target
    with atomic_path(target) as tmp:
        try:
            os.unlink(tmp)
            os.link(bundle, tmp)
        except OSError:  # another file system, or links not allowed: a copy
            shutil.copyfile(bundle, tmp)
    return target
