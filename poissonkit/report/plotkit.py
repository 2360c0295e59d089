"""Shared figure plumbing: a styled figure, thinning, atomic saving, and honest axes.

Honest axes: a quantity constant to round-off is drawn as a constant on a fixed axis
(:func:`plot_quantity`) rather than autoscaled into noise that looks like drift; samples too
far apart for the motion (:func:`samples_per_turn` below :data:`COARSE`) are drawn as points,
not joined by chords, and the figure's caption (:func:`caption`) says so.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np


def pyplot():
    """``matplotlib.pyplot`` on the Agg backend unless a backend is already chosen (pyplot
    already imported, or ``MPLBACKEND`` set: a notebook's inline backend stays)."""
    import os
    import sys

    import matplotlib

    if "matplotlib.pyplot" not in sys.modules and not os.environ.get("MPLBACKEND"):
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def figure(title: str, *, nrows: int = 1, ncols: int = 1, size: tuple[float, float] = (6.4, 4.2)):
    """A figure with a title and light grids (MATLAB's "grid on"); returns ``(fig, axes)``."""
    plt = pyplot()
    fig, axes = plt.subplots(nrows, ncols, figsize=size, dpi=100, squeeze=False)
    for ax in axes.flat:
        ax.grid(True, color="0.85", linewidth=0.6)
    if nrows * ncols == 1:
        axes[0, 0].set_title(title, fontsize=10)
        return fig, axes[0, 0]
    fig.suptitle(title, fontsize=10)
    return fig, axes


def save(fig, path: Path) -> Path:
    """Write ``fig`` atomically (a killed run never leaves half a PNG) and close it."""
    from poissonkit.files.atomic import atomic_path

    layout(fig)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format=path.suffix.lstrip(".") or "png")
    pyplot().close(fig)
    return path


def layout(fig) -> None:
    """Lay ``fig`` out tightly, leaving a strip at the bottom for its caption if it has one."""
    low = [t for t in fig.texts if t.get_gid() == _CAPTION]
    lines = sum(t.get_text().count("\n") + 1 for t in low)
    fig.tight_layout(rect=(0, 0.01 + 0.035 * lines, 1, 1) if low else None)


def thin(*arrays: np.ndarray, limit: int = 20000) -> list[np.ndarray]:
    """Every k-th sample so that a plot has at most ``limit`` points (files stay small)."""
    n = len(arrays[0])
    k = max(1, int(np.ceil(n / limit)))
    return [a[::k] for a in arrays]


#: Relative range below which a quantity is constant to round-off.
ROUNDOFF = 1e-9
#: Fewer samples than this per turn (orbit, precession) are too few to join by lines.
COARSE = 12
_CAPTION = "caption"


def constant_to_roundoff(values: np.ndarray, rel: float = ROUNDOFF,
                         magnitude: float = 0.0) -> bool:
    """True when ``values`` vary by at most ``rel`` of their magnitude (the larger of their
    largest absolute value and ``magnitude``: give it for a difference ``q(t) − q(0)``)."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    if v.size == 0:
        return False
    return bool(np.ptp(v) <= rel * max(float(np.max(np.abs(v))), abs(magnitude)))


def plot_quantity(ax, t: np.ndarray, values: np.ndarray, *, coarse: bool = False,
                  magnitude: float = 0.0, **style) -> bool:
    """Draw ``values`` against ``t``; a quantity constant to round-off goes on a fixed axis
    around its value (no offset, no autoscaled noise) and "constant to round-off" is added to
    the title; ``coarse`` draws points instead of lines; ``magnitude`` as in
    :func:`constant_to_roundoff`. Returns whether it was constant."""
    v = np.asarray(values, dtype=float)
    if coarse:
        style = {**style, "linestyle": "none", "marker": ".", "markersize": 3}
    flat = constant_to_roundoff(v, magnitude=magnitude)
    if flat:
        value = float(np.nanmean(v))
        ax.plot(t, np.full_like(v, value), **style)
        size = max(abs(value), abs(magnitude))
        half = 0.05 * size if size else 1.0
        ax.set_ylim(value - half, value + half)
        ax.ticklabel_format(axis="y", useOffset=False, style="sci", scilimits=(-3, 4))
        title = ax.get_title()
        if "constant to round-off" not in title:
            ax.set_title(f"{title} — constant to round-off" if title
                         else "constant to round-off", fontsize=ax.title.get_fontsize())
    else:
        ax.plot(t, v, **style)
    return flat


def samples_per_turn(vectors: np.ndarray) -> float:
    """Median number of samples per full turn of ``vectors`` ``(n, 3)`` about the origin
    (``inf`` when they do not turn, or there are fewer than three)."""
    v = np.asarray(vectors, dtype=float).reshape(-1, 3)
    if len(v) < 3:
        return float("inf")
    a, b = v[:-1], v[1:]
    cross = np.linalg.norm(np.cross(a, b), axis=1)
    dot = np.einsum("ij,ij->i", a, b)
    step = np.arctan2(cross, dot)
    step = step[np.isfinite(step)]
    med = float(np.median(step)) if step.size else 0.0
    return 2 * np.pi / med if med > 1e-12 else float("inf")


def caption(fig, text: str) -> None:
    """Add (or extend) the caption under the figure."""
    import textwrap

    wrapped = textwrap.fill(text, 110)
    for t in fig.texts:
        if t.get_gid() == _CAPTION:
            t.set_text(t.get_text() + "\n" + wrapped)
            return
    fig.text(0.01, 0.01, wrapped, fontsize=7, ha="left", va="bottom", gid=_CAPTION)


def caption_of(fig) -> str:
    """The figure's caption ("" without one)."""
    return "\n".join(t.get_text() for t in fig.texts if t.get_gid() == _CAPTION)
