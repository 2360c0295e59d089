"""Warm start: compile time of a scene in a first and a second process.

For each case (`poissonkit run` of the seed scene, a 100-magnet cluster, the Chaplygin ball's ``compile_system``)
a fresh interpreter runs ``tests/numerics/warm_start_probe.py`` twice against an empty kernel
cache folder: the first process generates and compiles everything, the second loads it. Printed
per process: the time to build the system and take its first short run (imports excluded),
numba's once-per-process target initialisation (paid by any numba program on its first compiled
call, cached or not), and the number of functions numba compiled.

Run::

    python benchmarks/bench_warm_start.py
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

PROBE = Path(__file__).resolve().parents[1] / "tests" / "numerics" / "warm_start_probe.py"
CASES = {"seed": "seed scene (poissonkit run)", "cluster": "100-magnet cluster",
         "chaplygin": "Chaplygin ball compile_system"}
TARGET = 0.5


def run(case: str, cache: str) -> dict:
    env = {**os.environ, "POISSONKIT_CACHE_DIR": cache}
    out = subprocess.run([sys.executable, str(PROBE), case], env=env, capture_output=True,
                         text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    print(f"{'case':32s} {'1st process':>12s} {'2nd process':>12s} {'2nd compiles':>13s} "
          f"{'numba init':>11s}  target ≤ {TARGET} s")
    for case, label in CASES.items():
        with tempfile.TemporaryDirectory() as cache:
            first = run(case, cache)
            second = run(case, cache)
        same = "same result" if first["values"] == second["values"] else "RESULTS DIFFER"
        ok = "met" if second["seconds"] <= TARGET and second["compiles"] == 0 else "MISSED"
        print(f"{label:32s} {first['seconds']:11.2f}s {second['seconds']:11.3f}s "
              f"{second['compiles']:13d} {second['numba_init']:10.2f}s  {ok}, {same}")


if __name__ == "__main__":
    main()
