"""A magnetised top in the field of magpylib sources, from Python (docs/fields.md).

1. A magpylib Collection (a cylinder magnet and a coil) passed directly as a field, with
   gravity: the field is tabulated to the tolerance and the run keeps the energy of the
   interpolated field at round-off.
2. The same top above a current loop, once in the loop's exact field (elliptic integrals) and
   once in magpylib's Circle tabulated to 1e-6: the two runs agree to about the tolerance.
"""

from __future__ import annotations

import magpylib as magpy
import numpy as np

import poissonkit as pk
from poissonkit.numerics.nbody import Body, NBodySystem

GRAVITY = pk.field("gravity", g=(0.0, 0.0, -9.81))


def top(moment: float) -> Body:
    """A 20 g top with transverse inertia 2e-6 kg m² carrying ``moment`` [A m²]."""
    return Body("top", 0.02, alpha=1 / 2e-6, attributes={"moment": moment})


def collection_run() -> None:
    base = magpy.Collection(
        magpy.magnet.Cylinder(polarization=(0, 0, 1.0), dimension=(0.05, 0.01)),
        magpy.current.Circle(current=50.0, diameter=0.04, position=(0, 0, 0.005)))
    # mode="table": tabulated, to show the interpolation error (the default is exact)
    field = pk.field(base, tol=1e-5, region=(-0.01, -0.01, 0.025, 0.01, 0.01, 0.045),
                     mode="table").compile()
    system = NBodySystem([top(0.1)], fields=[field, GRAVITY])
    y0 = system.pack([[0.001, 0.0, 0.036]], [[0.0005, 0.0, 0.0]], [[0.05, 0.0, -1.0]],
                     [[0.0, 0.0, -2e-4]], normalize=True)
    sol = pk.solve(system, y0, 0.05, method="splitting6", step=2e-4)
    info = field.info
    print(f"collection: grid {info['grid']}, interpolation error of B {info['field_error']:.1e},"
          f" of its gradient {info['gradient_error']:.1e} (tol {info['tol']:g})")
    print(f"  energy error {sol.summary()['max_rel_energy_error']:.1e}, final height "
          f"{sol.y[-1][2] * 1e3:.3f} mm")


def loop_runs() -> None:
    loop = dict(current=1500.0, radius=0.03)
    exact = NBodySystem([top(0.05)], fields=[pk.field("current_loop", **loop), GRAVITY])
    circle = magpy.current.Circle(current=loop["current"], diameter=2 * loop["radius"])
    table = pk.field(circle, tol=1e-6, region=(-0.006, -0.006, 0.008, 0.006, 0.006, 0.022),
                     mode="table")
    tabulated = NBodySystem([top(0.05)], fields=[table, GRAVITY])
    y0 = exact.pack([[0.001, 0.0005, 0.015]], [[0.0004, 0.0, 0.0]], [[0.05, 0.0, -1.0]],
                    [[0.0, 0.0, -2e-4]], normalize=True)
    a = pk.solve(exact, y0, 0.04, method="splitting6", step=1e-4)
    b = pk.solve(tabulated, y0, 0.04, method="splitting6", step=1e-4)
    gap = np.max(np.linalg.norm(a.y[:, :3] - b.y[:, :3], axis=1))
    print(f"loop: exact vs tabulated (tol 1e-6) largest position difference {gap * 1e9:.2f} nm "
          f"over a {np.ptp(a.y[:, 2]) * 1e3:.3f} mm motion")


if __name__ == "__main__":
    collection_run()
    loop_runs()
