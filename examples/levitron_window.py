"""The Levitron's stability window: sweeps of the registered scene next to the linear analysis.

A 22 g magnetised top hovers above a ferrite ring only inside a window of spin rates: too slow
and it flips over (then falls onto the base), too fast and its axis no longer follows the
field's direction and it drifts out of the trap. This script

* computes the window of the linearisation on the Poisson manifold
  (:func:`poissonkit.linear_stability` at the hovering relative equilibrium, bisected in spin)
  for each top mass;
* sweeps the registered ``levitron`` scene over spin and mass (3 s per run, start 0.5 mm off
  the axis and tilted by 0.005 rad) — the same as
  ``poissonkit sweep levitron --param spin_rpm=400:2400:21 --param mass=0.0216:0.0224:5``;
* prints both windows side by side and draws the fate map with the linear edges on it.

    python examples/levitron_window.py --workers 2 --figure docs/img/levitron-window.png
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from poissonkit.errors import InputError
from poissonkit.sweeps import grid, sweep
from poissonkit.sweeps.execute import make_client
from poissonkit.sweeps.plot import draw_map
from poissonkit_magnets import levitron as lev

LABELS = {"spin_rpm": "spin [rpm]", "mass": "mass of the top [kg]"}


def linear_window(mass: float) -> tuple[float, float]:
    """The linear window [rpm] of a top of ``mass`` (nan, nan if none)."""
    try:
        return lev.stability_window(lev.LevitronParameters().with_values(mass=mass),
                                    lo=200.0, hi=6000.0, points=20, resolution=2.0)
    except InputError:
        return float("nan"), float("nan")


def swept_window(spins: np.ndarray, bounded: np.ndarray) -> tuple[float, float]:
    """First and last bounded spin of a row (nan, nan if none)."""
    idx = np.nonzero(bounded)[0]
    return (float(spins[idx[0]]), float(spins[idx[-1]])) if idx.size else (np.nan, np.nan)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--spins", type=int, default=21, help="spin values from 400 to 2400 rpm")
    ap.add_argument("--masses", type=int, default=5, help="mass values from 21.6 to 22.4 g")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--duration", type=float, default=3.0, help="seconds per run")
    ap.add_argument("--out", default="levitron-window", help="folder of the dataset")
    ap.add_argument("--figure", default=None, help="PNG path (default: OUT/levitron-window.png)")
    ap.add_argument("--from-store", action="store_true",
                    help="redraw from OUT/levitron.zarr of an earlier run instead of sweeping")
    args = ap.parse_args(argv)
    out = Path(args.out)
    start = time.perf_counter()
    if args.from_store:
        from poissonkit.sweeps.store import open_store

        ds = open_store(out / "levitron.zarr")
    else:
        params = [grid("spin_rpm", 400.0, 2400.0, args.spins),
                  grid("mass", 0.0216, 0.0224, args.masses)]
        client, close = make_client(workers=args.workers)
        try:
            ds = sweep("levitron", params,
                       outcomes=["fate", "fate_time", "max_rel_energy_error"], client=client,
                       store=out / "levitron.zarr", overwrite=True, periods=args.duration)
        finally:
            close()
    wall = time.perf_counter() - start
    spins = ds["spin_rpm"].values
    masses = ds["mass"].values
    bounded = ((ds["fate"] == 0) & ~ds["failed"]).transpose("mass", "spin_rpm").values
    linear = [linear_window(m) for m in masses]

    print(f"{'mass [g]':>9} | {'linear window [rpm]':>21} | {'bounded in the sweep [rpm]':>27}")
    for m, (lo, hi), row in zip(masses, linear, bounded):
        slo, shi = swept_window(spins, row)
        print(f"{1000 * m:9.2f} | {lo:9.0f} – {hi:9.0f} | {slo:12.0f} – {shi:12.0f}")
    energy = float(ds["max_rel_energy_error"].where(ds["fate"] == 0).max())
    print(f"largest relative energy error of a bounded run: {energy:.1e}")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from matplotlib.patches import Patch

    from poissonkit.sweeps.plot import FATE_COLOURS
    from poissonkit.sweeps.targets import FATES

    fig, ax = plt.subplots(figsize=(7.5, 4.6))
    draw_map(ax, None, ds, x="spin_rpm", y="mass", labels=LABELS)
    lows, highs = np.array(linear).T
    (line,) = ax.plot(lows, masses, "ko--", lw=1.5, ms=4)
    ax.plot(highs, masses, "ko--", lw=1.5, ms=4)
    names = {"bounded": "bounded (levitation)", "collision": "flip or fall onto the base",
             "escape": "escape from the trap"}
    handles = [Patch(color=c, label=names[f]) for c, f in zip(FATE_COLOURS, FATES)]
    ax.legend(handles=[*handles, line], labels=[*(h.get_label() for h in handles),
                                                "linear window (pk.linear_stability)"],
              loc="upper right", fontsize=7, framealpha=0.9)
    ax.set_title(f"Levitron: fate over {args.duration:g} s (bounded = levitation)", fontsize=10)
    fig.tight_layout()
    png = Path(args.figure) if args.figure else out / "levitron-window.png"
    png.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(png, dpi=90)
    print(f"{ds['fate'].size} runs ({'read from the store' if args.from_store else f'on {args.workers} workers'}) "
          f"in {wall:.0f} s; wrote {png}")


if __name__ == "__main__":
    main()
