"""Builds and runs one scene in a fresh process; prints what numba compiled (JSON).

Used by tests/numerics/test_numerics_warm_start.py and benchmarks/bench_warm_start.py::

    python tests/numerics/warm_start_probe.py seed|cluster|chaplygin|discrete_gradient

Output: ``{"case", "compiles", "compiled", "seconds", "numba_init", "plugins", "values"}`` —
the number of numba compilations (cache loads do not count), the functions compiled, the wall
time of building the system and its first short run (imports, numba's once-per-process target
initialisation and plugin loading excluded and reported apart), and the final state.
"""

from __future__ import annotations

import json
import sys
import time

from numba.core import event

COMPILED: list[str] = []


class _Count(event.Listener):
    def on_start(self, ev: event.Event) -> None:
        COMPILED.append(ev.data["dispatcher"].py_func.__qualname__)

    def on_end(self, ev: event.Event) -> None:
        pass


def seed():
    """``poissonkit run`` of the default scene (a short, tilted version), as a user runs it."""
    import tempfile

    import numpy as np

    from poissonkit.cli import main

    with tempfile.TemporaryDirectory() as out:
        code = main(["run", "--periods", "0.05", "--tilt", "0.02", "--no-plots", "--no-progress",
                     "--out", out + "/run"])
        if code not in (0, None):
            raise SystemExit(code)
        return np.load(out + "/run/trajectory.npz")["y"][-1]


def cluster():
    import numpy as np
    import sympy as sp

    from poissonkit.numerics import AllPairs, Body, NBodySystem
    from poissonkit.numerics.solver import solve

    r, c1, c2, c3 = sp.symbols("r c1 c2 c3", real=True)
    rng = np.random.default_rng(7)
    n = 100
    side = (n / 0.05) ** (1 / 3)
    nu = rng.normal(size=(n, 3))
    nu /= np.linalg.norm(nu, axis=1)[:, None]
    system = NBodySystem([Body(f"m{k}", 1.0, 1.0) for k in range(n)],
                         [AllPairs((c3 - 3 * c1 * c2) / r**3)], cutoff=4.0)
    y0 = system.pack(rng.uniform(0, side, size=(n, 3)), 0.01 * rng.normal(size=(n, 3)), nu,
                     0.01 * rng.normal(size=(n, 3)))
    return solve(system, y0, 0.01, method="splitting4", step=0.005).y[-1]


def chaplygin():
    import numpy as np
    from poissonkit_nonholonomic.ball import chaplygin_ball

    from poissonkit.numerics.system import compile_system

    cs = compile_system(chaplygin_ball(1, 2, 3, 1))
    y = np.array([0.1, 0.2, 0.3, 0.0, 0.6, 0.8])
    return np.concatenate([cs.rhs(0.0, y), cs.jacobian(0.0, y).ravel(), cs.casimirs(y),
                           cs.integrals(y), [cs.energy(y)]])


def discrete_gradient():
    """A short discrete-gradient run of the Chaplygin ball (its own kernels and time loop)."""
    import numpy as np

    from poissonkit.numerics.solver import solve
    from poissonkit.numerics.system import compile_system
    from poissonkit.plugin import system

    cs = compile_system(system("nh.chaplygin_ball").build(I1=1, I2=2, I3=3, d=1))
    y0 = np.array([0.0, 0.6, 0.8, 1.0, -0.5, 0.2])
    return solve(cs, y0, 0.2, "discrete_gradient", step=0.01).y[-1]


CASES = {"seed": seed, "cluster": cluster, "chaplygin": chaplygin,
         "discrete_gradient": discrete_gradient}


def main() -> None:
    case = sys.argv[1]
    # imports are not compilation: load every module the cases use before the clock starts
    import poissonkit_magnets.seed000  # noqa: F401
    import poissonkit_nonholonomic.ball  # noqa: F401

    import poissonkit.cli  # noqa: F401
    import poissonkit.commands.run  # noqa: F401
    import poissonkit.numerics.solver  # noqa: F401
    import poissonkit.numerics.system  # noqa: F401

    import numpy as np

    from poissonkit.numerics.kernels import all_finite
    from poissonkit.plugin.manager import plugin_reports

    event.register("numba:compile", _Count())
    # numba initialises its compiler target once per process, on the first compilation or
    # cache load of any function, whatever it is: timed apart from the scene
    start = time.perf_counter()
    all_finite(np.zeros(1))
    numba_init = time.perf_counter() - start
    start = time.perf_counter()
    plugin_reports()
    plugins = time.perf_counter() - start
    COMPILED.clear()
    start = time.perf_counter()
    values = CASES[case]()
    seconds = time.perf_counter() - start
    print(json.dumps({"case": case, "compiles": len(COMPILED), "compiled": sorted(set(COMPILED)),
                      "seconds": seconds, "numba_init": numba_init, "plugins": plugins,
                      "values": [float(v).hex() for v in values]}))


if __name__ == "__main__":
    main()
