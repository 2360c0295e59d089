"""Figures of a run in the style of seed 000's MATLAB plots (matplotlib, Agg backend).

The seed shows (i) the z-component of the total angular momentum against time ("Total moment
of momentum conservation law"), (ii) the orbital radius on the background of the x-coordinate
("Change of orbital radius on background of x-coordinate changing"), plus the orbit itself. We
add the invariant drifts on a log scale. Every function writes one PNG and returns its path.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from poissonkit.report.summary import Diagnostics


def _figure(title: str):
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.2), dpi=100)
    ax.set_title(title, fontsize=10)
    ax.grid(True, color="0.85", linewidth=0.6)  # MATLAB's "grid on"
    return fig, ax


def _save(fig, path: Path) -> Path:
    import matplotlib.pyplot as plt

    from poissonkit.report.atomic import atomic_path

    fig.tight_layout()
    with atomic_path(path) as tmp:  # a killed run never leaves half a PNG
        fig.savefig(tmp, format=path.suffix.lstrip(".") or "png")
    plt.close(fig)
    return path


def _thin(*arrays: np.ndarray, limit: int = 20000):
    """Every k-th sample so that a plot has at most ``limit`` points (files stay small)."""
    n = len(arrays[0])
    k = max(1, int(np.ceil(n / limit)))
    return [a[::k] for a in arrays]


def angular_momentum_z(path: str | Path, t: np.ndarray, jz: np.ndarray, *,
                       unit: str = "J s", time_unit: str = "s") -> Path:
    """``j_z(t)`` (seed: total moment of momentum, z-component), with its deviation inset."""
    t, jz = _thin(np.asarray(t), np.asarray(jz))
    fig, ax = _figure("Total angular momentum, z-component")
    ax.plot(t, jz - jz[0], color="tab:blue", linewidth=0.8)
    ax.set_xlabel(f"t [{time_unit}]")
    ax.set_ylabel(f"j_z(t) - j_z(0) [{unit}]   (j_z(0) = {jz[0]:.10g})")
    return _save(fig, Path(path))


def radius_and_x(path: str | Path, t: np.ndarray, r: np.ndarray, *, unit: str = "mm",
                 time_unit: str = "s") -> Path:
    """Orbital radius ``|r|(t)`` on the background of ``x(t)`` (seed's second MATLAB figure)."""
    r = np.asarray(r)
    t, rr = _thin(np.asarray(t), r)
    fig, ax = _figure("Orbital radius on the background of the x-coordinate")
    ax.plot(t, rr[:, 0], color="0.6", linewidth=0.7, label="x")
    ax.plot(t, np.linalg.norm(rr, axis=1), color="tab:blue", linewidth=1.0, label="|r|")
    ax.set_xlabel(f"t [{time_unit}]")
    ax.set_ylabel(f"[{unit}]")
    ax.legend(loc="lower right", fontsize=8)
    return _save(fig, Path(path))


def orbit(path: str | Path, r: np.ndarray, *, unit: str = "mm") -> Path:
    """The relative orbit in the xy-plane."""
    (rr,) = _thin(np.asarray(r))
    fig, ax = _figure("Relative orbit r = r2 - r1")
    ax.plot(rr[:, 0], rr[:, 1], color="tab:blue", linewidth=0.7)
    ax.plot(rr[0, 0], rr[0, 1], "o", color="tab:red", markersize=4, label="start")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel(f"x [{unit}]")
    ax.set_ylabel(f"y [{unit}]")
    ax.legend(loc="upper right", fontsize=8)
    return _save(fig, Path(path))


def drifts(path: str | Path, diag: Diagnostics, *, time_scale: float = 1.0,
           time_unit: str = "s") -> Path:
    """Relative energy error, Casimir drift and angular-momentum drift against time (log)."""
    t = np.asarray(diag.t) * time_scale
    series = [("|ΔH|/|H|", diag.energy_error), ("Casimir drift", diag.casimir_drift),
              ("|Δj|/(Σ|r×p|+Σ|m|)", diag.angular_momentum_drift)]
    fig, ax = _figure("Invariant drifts")
    for (label, y), color in zip(series, ("tab:blue", "tab:orange", "tab:green")):
        tt, yy = _thin(t, np.maximum(np.asarray(y), 1e-17))  # log axis: floor at 1e-17
        ax.semilogy(tt, yy, color=color, linewidth=0.7, label=label)
    ax.set_xlabel(f"t [{time_unit}]")
    ax.set_ylabel("relative error")
    ax.legend(loc="lower right", fontsize=8)
    return _save(fig, Path(path))


def seed_figures(outdir: str | Path, t_si: np.ndarray, r_si: np.ndarray, jz_si: np.ndarray,
                 diag: Diagnostics, time_scale: float) -> Sequence[Path]:
    """All four figures of ``poissonkit run`` into ``outdir`` (lengths plotted in mm)."""
    out = Path(outdir)
    r_mm = np.asarray(r_si) * 1e3
    return [
        angular_momentum_z(out / "angular_momentum_z.png", t_si, jz_si),
        radius_and_x(out / "radius_and_x.png", t_si, r_mm),
        orbit(out / "orbit.png", r_mm),
        drifts(out / "drifts.png", diag, time_scale=time_scale),
    ]
