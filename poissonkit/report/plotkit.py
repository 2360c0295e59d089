"""Shared figure plumbing: a styled figure, thinning, atomic saving."""

from __future__ import annotations

from pathlib import Path

import numpy as np


def pyplot():
    """``matplotlib.pyplot`` on the Agg backend unless a backend is already chosen."""
    import matplotlib

    matplotlib.use("Agg", force=False)
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

    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format=path.suffix.lstrip(".") or "png")
    pyplot().close(fig)
    return path


def thin(*arrays: np.ndarray, limit: int = 20000) -> list[np.ndarray]:
    """Every k-th sample so that a plot has at most ``limit`` points (files stay small)."""
    n = len(arrays[0])
    k = max(1, int(np.ceil(n / limit)))
    return [a[::k] for a in arrays]
