"""Start-up cost of the command line: ``import poissonkit``, ``poissonkit --help``,
``poissonkit scenes`` and a warm ``poissonkit run two_magnets --no-plot`` (issue 32).

Each command runs ``--repeat`` times (default 5) in a fresh interpreter; the table gives the
median and the best wall time, and the CPU time (user + system of the child) of the median run.
The warm run is preceded by one untimed run that fills the kernel cache (a temporary folder,
unless ``POISSONKIT_CACHE_DIR`` is set), so it measures a second run of the scene: start-up,
loading the kernels, 0.02 s of integration, writing summary and trajectory. Targets (on an idle
2-core machine): import ≤ 0.5 s, ``--help`` and ``scenes`` ≤ 1 s, warm ``run --no-plot`` ≤ 2 s.

    python benchmarks/bench_cli_startup.py               # the table
    python benchmarks/bench_cli_startup.py --repeat 9 --json startup.json

Wall times on a shared machine grow with its load: the script prints the load average before
and after; compare figures measured at a load below 1 only. ``python -X importtime -c "import
poissonkit"`` shows what an import loads.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

PY = sys.executable
COMMANDS: dict[str, list[str]] = {
    "import poissonkit": [PY, "-c", "import poissonkit"],
    "poissonkit --help": [PY, "-m", "poissonkit", "--help"],
    "poissonkit scenes": [PY, "-m", "poissonkit", "scenes"],
    "run two_magnets --no-plot (warm)": [PY, "-m", "poissonkit", "run", "two_magnets",
                                         "--no-plot", "--no-progress", "--overwrite"],
}
TARGETS = {"import poissonkit": 0.5, "poissonkit --help": 1.0, "poissonkit scenes": 1.0,
           "run two_magnets --no-plot (warm)": 2.0}


def _timed(cmd: list[str], env: dict[str, str], cwd: Path) -> tuple[float, float]:
    """Wall and CPU (children's user + system) seconds of one run of ``cmd``."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    done = subprocess.run(cmd, env=env, cwd=cwd, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed ({done.returncode}):\n{done.stderr}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu


def main(argv: list[str] | None = None) -> int:
    """Run every command, print the table (and write ``--json``)."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5, help="runs per command (median shown)")
    ap.add_argument("--json", default=None, help="also write the figures to this file")
    args = ap.parse_args(argv)
    env = dict(os.environ)
    with tempfile.TemporaryDirectory(prefix="pk-startup-") as tmp:
        env.setdefault("POISSONKIT_CACHE_DIR", str(Path(tmp) / "cache"))
        cwd = Path(tmp)
        load = os.getloadavg()
        _timed(COMMANDS["run two_magnets --no-plot (warm)"], env, cwd)  # fills the cache
        rows = []
        for name, cmd in COMMANDS.items():
            runs = sorted(_timed(cmd, env, cwd) for _ in range(args.repeat))
            median = runs[len(runs) // 2]
            rows.append({"command": name, "median_s": median[0], "best_s": runs[0][0],
                         "cpu_s": median[1], "target_s": TARGETS[name],
                         "spread_s": statistics.pstdev(r[0] for r in runs)})
        load_after = os.getloadavg()
    print(f"load average before {load[0]:.2f}, after {load_after[0]:.2f} (compare figures "
          "measured below 1)")
    print("| command | median wall [s] | best [s] | CPU [s] | target [s] |")
    print("|---|---:|---:|---:|---:|")
    for r in rows:
        print(f"| {r['command']} | {r['median_s']:.2f} | {r['best_s']:.2f} | {r['cpu_s']:.2f} "
              f"| ≤ {r['target_s']:g} |")
    if args.json:
        Path(args.json).write_text(json.dumps({"load": [load[0], load_after[0]], "rows": rows},
                                              indent=2))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
