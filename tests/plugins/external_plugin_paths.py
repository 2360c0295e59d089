"""Run inside a fresh virtual environment where only the example plugin is installed.

Exercises every path a built-in plugin's contributions take — ``pair_interaction`` (named and
``"auto"``), the planner, a scene run by name, a sweep with the plugin's outcome and ``solve`` —
and prints one JSON line of results for the test to check. With
``POISSONKIT_BLOCK_PLUGINS=magnets,nbody,nonholonomic`` in the environment it also proves that
the core works without any built-in plugin.
"""

from __future__ import annotations

import json
import os
import sys
import tempfile

import numpy as np

import poissonkit as pk
from poissonkit.cli import main as cli_main
from poissonkit.numerics.nbody import Body, Interaction, NBodySystem
from poissonkit.plugin import names, plugin_reports
from poissonkit.scene.registered import registered_run

Q, D = 1e-8, 5e-3
nu = (0.0, 0.0, 1.0)


def main() -> None:
    """Run every path and print the results as one JSON line."""
    out: dict[str, object] = {
        "blocked": sorted(r.name for r in plugin_reports() if r.status == "blocked"),
        "potentials": names("potential"),
        "auto_far": pk.pair_interaction("auto", (0.2, 0, 0), nu, nu, charge=Q, dipole_length=D,
                                        tol=1e-2).model,
        "auto_near": pk.pair_interaction("auto", (0.02, 0, 0), nu, nu, charge=Q, dipole_length=D,
                                         tol=1e-2).model,
    }
    spec, _ = registered_run("dipole_pair")
    out["plan"] = spec.metadata["plan"]["models"]
    with tempfile.TemporaryDirectory() as tmp:
        folder = os.path.join(tmp, "run")
        out["run_exit"] = cli_main(["run", "dipole_pair", "--out", folder, "--no-progress",
                                    "--no-plots"])
        with open(os.path.join(folder, "summary.json")) as f:
            out["run_energy_error"] = json.load(f)["max_rel_energy_error"]
    ds = pk.sweep("dipole_pair", {"bodies.b.p.1": [6.0e-5, 6.25e-5]},
                  outcomes=["fate", "max_axis_tilt"], workers=1, progress=False,
                  fixed={"run.duration": 0.5})
    out["sweep_completed"] = bool(ds["completed"].all())
    out["sweep_fate"] = [int(v) for v in ds["fate"].values]
    out["sweep_tilt"] = [float(v) for v in ds["max_axis_tilt"].values]
    params = {"charge1": Q, "charge2": Q, "dipole_length1": D, "dipole_length2": D}
    system = NBodySystem([Body("a", 1e-3, alpha=4.8e8), Body("b", 1e-3, alpha=4.8e8)],
                         [Interaction(0, 1, "point_dipole", params)])
    y0 = system.pack([[0, 0, 0], [0.05, 0, 0]], np.zeros((2, 3)), [nu, nu],
                     [[0, 0, 2.6e-7], [0, 0, 2.6e-7]], si=True)
    sol = pk.solve(system, y0, 0.1, method="splitting4", step=1e-3)
    out["solve_energy_error"] = sol.summary()["max_rel_energy_error"]
    json.dump(out, sys.stdout)
    print()


# Dask's worker processes import this module again: only the main process runs the paths.
if __name__ == "__main__":
    main()
