"""First-run compile time of every shipped and registered scene (issue 28).

For each scene that ``poissonkit scenes --json`` lists, runs ``poissonkit run NAME --no-plot
--no-progress`` (a short duration) twice in fresh processes sharing one kernel cache folder:
first with the folder EMPTY (cold: every kernel is compiled), then again (warm: every kernel is
loaded from the disk cache). cold − warm is the time spent compiling. Wall-clock and CPU time
(user + system of the child process; steadier on a shared machine) are both reported, with the
number of compiled functions the cold run stored (index files in the cache).

    python benchmarks/bench_scene_compile.py                 # every scene
    python benchmarks/bench_scene_compile.py --only levitron # scenes whose name contains this
    python benchmarks/bench_scene_compile.py --json out.json # also write the figures

The project under test is the one ``python -m poissonkit`` imports (``PYTHONPATH`` decides).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from dataclasses import asdict, dataclass
from pathlib import Path

#: Run options that keep a scene short (its compile time is what is measured); scenes not named
#: here run with their own duration, all of which are short.
SHORT = {
    "seed000": ["--periods", "1"],  # default 20 periods
    "levitron": ["--duration", "0.05"],  # default 2 s
}


@dataclass
class Timing:
    """Seconds of one scene's cold and warm runs."""

    scene: str
    kind: str
    exit_cold: int
    exit_warm: int
    cold_wall: float
    warm_wall: float
    cold_cpu: float
    warm_cpu: float
    kernels: int

    @property
    def compile_wall(self) -> float:
        return self.cold_wall - self.warm_wall

    @property
    def compile_cpu(self) -> float:
        return self.cold_cpu - self.warm_cpu


def scenes() -> list[tuple[str, str]]:
    """``(name, kind)`` of every scene ``poissonkit scenes --json`` lists."""
    out = subprocess.run([sys.executable, "-m", "poissonkit", "scenes", "--json"],
                         capture_output=True, text=True, check=True).stdout
    data = json.loads(out)
    listing = data["scenes"] if isinstance(data, dict) else data
    return [(e["name"], e.get("kind", "")) for e in listing]


def _children_cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run_once(name: str, cache: Path, out: Path) -> tuple[int, float, float, str]:
    """One ``poissonkit run`` of ``name``: exit code, wall and CPU seconds, stderr tail."""
    # numba's own cache=True functions save beside their source unless NUMBA_CACHE_DIR says
    # otherwise: both caches start empty, or "cold" would hide their compile time
    env = {**os.environ, "POISSONKIT_CACHE_DIR": str(cache), "NUMBA_CACHE_DIR": str(cache)}
    cmd = [sys.executable, "-m", "poissonkit", "run", name, "--out", str(out), "--no-plot",
           "--no-progress", *SHORT.get(name, [])]
    cpu0, wall0 = _children_cpu(), time.perf_counter()
    p = subprocess.run(cmd, env=env, capture_output=True, text=True, check=False)
    wall, cpu = time.perf_counter() - wall0, _children_cpu() - cpu0
    return p.returncode, wall, cpu, p.stderr.strip()[-300:]


def measure(name: str, kind: str) -> Timing:
    """Cold then warm run of one scene in a temporary folder with its own empty cache."""
    with tempfile.TemporaryDirectory(prefix="pk-compile-") as tmp:
        cache = Path(tmp) / "cache"
        cache.mkdir()
        ec, cw, cc, err_c = run_once(name, cache, Path(tmp) / "cold")
        kernels = sum(1 for _ in cache.rglob("*.nbi"))
        ew, ww, wc, err_w = run_once(name, cache, Path(tmp) / "warm")
    for code, err in ((ec, err_c), (ew, err_w)):
        if code not in (0, 3) and err:  # 3: the run finished but warned (energy tolerance)
            print(f"  {name}: exit {code}: {err}", file=sys.stderr)
    return Timing(name, kind, ec, ew, cw, ww, cc, wc, kernels)


def table(rows: list[Timing]) -> str:
    """The figures as a Markdown table (seconds)."""
    head = ("| scene | kind | exit | cold wall | warm wall | cold − warm wall | cold CPU | warm CPU "
            "| cold − warm CPU | functions compiled |\n|---|---|---|---:|---:|---:|---:|---:|---:|---:|")
    lines = [head]
    for r in rows:
        lines.append(f"| {r.scene} | {r.kind} | {r.exit_cold}/{r.exit_warm} | {r.cold_wall:.1f} "
                     f"| {r.warm_wall:.1f} | {r.compile_wall:.1f} | {r.cold_cpu:.1f} "
                     f"| {r.warm_cpu:.1f} | {r.compile_cpu:.1f} | {r.kernels} |")
    total = [sum(getattr(r, a) for r in rows) for a in ("cold_wall", "warm_wall", "cold_cpu",
                                                           "warm_cpu", "kernels")]
    lines.append(f"| **total** | | | {total[0]:.1f} | {total[1]:.1f} | {total[0] - total[1]:.1f} "
                 f"| {total[2]:.1f} | {total[3]:.1f} | {total[2] - total[3]:.1f} | {total[4]} |")
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", help="measure the scenes whose name contains this")
    ap.add_argument("--json", type=Path, help="also write the figures to this file")
    a = ap.parse_args()
    rows = []
    for name, kind in scenes():
        if a.only and a.only not in name:
            continue
        rows.append(measure(name, kind))
        r = rows[-1]
        print(f"{name}: cold {r.cold_wall:.1f} s, warm {r.warm_wall:.1f} s "
              f"(CPU {r.cold_cpu:.1f} / {r.warm_cpu:.1f} s), {r.kernels} functions compiled",
              file=sys.stderr, flush=True)
    print(table(rows))
    if a.json:
        a.json.write_text(json.dumps([asdict(r) | {"compile_wall": r.compile_wall,
                                                   "compile_cpu": r.compile_cpu} for r in rows],
                                     indent=1))


if __name__ == "__main__":
    main()
