"""Start-up cost of the command line: ``import poissonkit``, ``poissonkit --help``,
``poissonkit scenes`` and a warm ``poissonkit run two_magnets --no-plot`` (issue 32).

Each command runs ``--repeat`` times (default 5) in a fresh interpreter; the table gives the
median and the best wall time, the CPU time (user + system of the child, from
``resource.getrusage(RUSAGE_CHILDREN)``) of the median run, and both as ratios to a bare
``python -c pass`` measured the same way in the same session. On a loaded machine the wall
times grow with the load; the CPU times and the ratios vary much less (they still grow somewhat,
cores being shared): compare those, and re-measure wall times against the targets on an idle
machine.
The warm run is preceded by one untimed run that fills the kernel cache (a temporary folder,
unless ``POISSONKIT_CACHE_DIR`` is set), so it measures a second run of the scene: start-up,
loading the kernels, 0.02 s of integration, writing summary and trajectory. Targets (on an idle
2-core machine): import ≤ 0.5 s, ``--help`` and ``scenes`` ≤ 1 s, warm ``run --no-plot`` ≤ 2 s.

    python benchmarks/bench_cli_startup.py               # the table
    python benchmarks/bench_cli_startup.py --repeat 9 --json startup.json
    python benchmarks/bench_cli_startup.py --builtins-only   # without third-party plugins

``--builtins-only`` sets ``POISSONKIT_DISABLE_PLUGIN_AUTOLOAD=1``: an installed third-party
plugin that imports heavy modules when it loads (the example plugin imports sympy and numba)
adds its own cost to every command that looks at a registry.

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
BASELINE = "python -c pass"
COMMANDS: dict[str, list[str]] = {
    BASELINE: [PY, "-c", "pass"],
    "import poissonkit": [PY, "-c", "import poissonkit"],
    "poissonkit --help": [PY, "-m", "poissonkit", "--help"],
    "poissonkit scenes": [PY, "-m", "poissonkit", "scenes"],
    "run two_magnets --no-plot (warm)": [PY, "-m", "poissonkit", "run", "two_magnets",
                                         "--no-plot", "--no-progress", "--overwrite"],
}
TARGETS: dict[str, float | None] = {
    BASELINE: None, "import poissonkit": 0.5, "poissonkit --help": 1.0, "poissonkit scenes": 1.0,
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
    ap.add_argument("--builtins-only", action="store_true",
                    help="switch third-party plugins off (POISSONKIT_DISABLE_PLUGIN_AUTOLOAD=1)")
    args = ap.parse_args(argv)
    env = dict(os.environ)
    if args.builtins_only:
        env["POISSONKIT_DISABLE_PLUGIN_AUTOLOAD"] = "1"
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
    base = rows[0]
    for r in rows:
        r["wall_ratio"] = r["median_s"] / base["median_s"]
        r["cpu_ratio"] = r["cpu_s"] / base["cpu_s"] if base["cpu_s"] > 0 else float("nan")
    only = " [built-in plugins only]" if args.builtins_only else ""
    print(f"load average before {load[0]:.2f}, after {load_after[0]:.2f} (wall times: compare "
          f"figures measured below 1; CPU times and ratios vary less){only}")
    print("| command | median wall [s] | best [s] | CPU [s] | wall / baseline | CPU / baseline "
          "| target (idle) [s] |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        target = "" if r["target_s"] is None else f"≤ {r['target_s']:g}"
        print(f"| {r['command']} | {r['median_s']:.2f} | {r['best_s']:.2f} | {r['cpu_s']:.2f} "
              f"| {r['wall_ratio']:.1f} | {r['cpu_ratio']:.1f} | {target} |")
    if args.json:
        Path(args.json).write_text(json.dumps({"load": [load[0], load_after[0]], "rows": rows},
                                              indent=2))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
