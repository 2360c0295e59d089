"""Seed 000's claim as a map: where is the two-magnet orbit stable?

The seed ends: "the example demonstrates stability of the orbital motion of magnets with certain
relations between their parameters". This script maps those relations with two sweeps of the
seed orbit (both axes tilted, 20 orbital periods per run, MEGNO as chaos indicator):

* spin ratio ``alpha|m|/omega_orb`` against the radius of the circular orbit relative to the
  magnet length ``h = 20 mm`` (tilt 0.02 rad);
* spin ratio against tilt, at the seed's radius ``R_orb = 10 mm = h/2``.

The seed's own point (spin ratio 20, ``R_orb/h = 0.5``, small tilt) is marked with a star. The
script prints the stability boundary it finds (the smallest spin ratio from which every larger
one stays bounded) and writes the datasets (Zarr) and the figure.

    python examples/seed000_stability_map.py --workers 2 --resolution 20 \\
        --figure docs/img/seed000-stability-map.png
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from poissonkit.sweeps import grid, sweep
from poissonkit.sweeps.execute import make_client
from poissonkit.sweeps.plot import boundary, draw_map

SEED_POINT = {"spin_ratio": 20.0, "orbit_radius": 0.5, "tilt": 0.02}
OUTCOMES = ["fate", "fate_time", "min_distance", "max_rel_energy_error", "megno"]
LABELS = {"spin_ratio": "spin ratio alpha|m|/omega_orb", "orbit_radius": "R_orb / h",
          "tilt": "tilt [rad]"}


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--resolution", type=int, default=20, help="grid points per axis")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--periods", type=float, default=20.0)
    ap.add_argument("--out", default="seed000-stability-map", help="folder of the datasets")
    ap.add_argument("--figure", default=None, help="PNG path (default: OUT/stability_map.png)")
    args = ap.parse_args(argv)
    n = args.resolution
    out = Path(args.out)
    spins = grid("spin_ratio", 0.0, 30.0, n)
    maps = {
        "radius": [spins, grid("orbit_radius", 0.25, 1.5, n)],
        "tilt": [spins, grid("tilt", 0.01, 0.3, n)],  # tilt 0 is an exact equilibrium
    }
    fixed = {"radius": {"tilt": SEED_POINT["tilt"]},
             "tilt": {"orbit_radius": SEED_POINT["orbit_radius"]}}
    start = time.perf_counter()
    client, close = make_client(workers=args.workers)
    try:
        data = {name: sweep("seed000", params, outcomes=OUTCOMES, client=client,
                            store=out / f"{name}.zarr", overwrite=True, periods=args.periods,
                            fixed=fixed[name])
                for name, params in maps.items()}
    finally:
        close()
    wall = time.perf_counter() - start

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(10.5, 8.4))
    for row, (name, ds) in enumerate(data.items()):
        other = "orbit_radius" if name == "radius" else "tilt"
        image = draw_map(axes[row][0], axes[row][1], ds, x="spin_ratio", y=other,
                         mark={"spin_ratio": SEED_POINT["spin_ratio"],
                               other: SEED_POINT[other]}, labels=LABELS)
        fig.colorbar(image, ax=axes[row][1], label="log10 MEGNO")
        edge = boundary(ds, along="spin_ratio")
        print(f"\n{name} map: smallest spin ratio from which the orbit stays bounded "
              f"({args.periods:g} periods):")
        for value, b in zip(ds[other].values, edge.values):
            print(f"  {other} = {value:6.3f}: spin ratio >= {b:5.2f}" if np.isfinite(b) else
                  f"  {other} = {value:6.3f}: never bounded in the range swept")
        bounded = ds["fate"] == 0
        megno = ds["megno"].where(bounded)
        print(f"  bounded runs: {int(bounded.sum())}/{bounded.size}; their MEGNO: median "
              f"{float(megno.median()):.2f}, 90th percentile {float(megno.quantile(0.9)):.2f}; "
              f"max energy error {float(ds['max_rel_energy_error'].where(bounded).max()):.1e}")
    fig.suptitle(f"Seed 000 orbit: fate and MEGNO over {args.periods:g} periods "
                 f"(star: the seed's point)", fontsize=11)
    fig.tight_layout()
    png = Path(args.figure) if args.figure else out / "stability_map.png"
    png.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(png, dpi=80)
    print(f"\n{sum(d.sizes['spin_ratio'] * d.sizes[o] for d, o in zip(data.values(), ('orbit_radius', 'tilt')))} "
          f"runs on {args.workers} workers in {wall:.0f} s (cluster start included); wrote {png}")


if __name__ == "__main__":
    main()
