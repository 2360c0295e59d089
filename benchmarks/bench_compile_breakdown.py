"""Where the first-run compile time of one scene goes: numba functions and their CPU seconds.

Runs ``poissonkit run SCENE --no-plot --no-progress`` IN THIS PROCESS with empty kernel caches
(``POISSONKIT_CACHE_DIR`` and ``NUMBA_CACHE_DIR``, so that functions decorated with numba's own
``cache=True`` are compiled too instead of loaded from ``__pycache__``) and listens to numba's ``numba:compile`` events (fired once per compiled specialisation, only on
a cache miss). Each compilation's CPU time (``time.process_time``) is split into *self* time and
the time of the callees compiled inside it (numba compiles a called dispatcher while typing its
caller), so the self column sums to the total. The CPU seconds are steadier than wall seconds on
a shared machine; their shares are the load-independent figure.

    python benchmarks/bench_compile_breakdown.py levitron --duration 0.05
    python benchmarks/bench_compile_breakdown.py outer_solar_system
    python benchmarks/bench_compile_breakdown.py levitron --passes   # also per compiler pass

Columns: ``self`` CPU seconds of that specialisation alone, ``incl`` with the callees it
compiled, ``share`` of the summed self time. Rows of the same function with several
signatures or several closures (``dispatchers`` > 1) are compiled more than once.
The project under test is the one ``import poissonkit`` finds (``PYTHONPATH`` decides).
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from collections import defaultdict
from dataclasses import dataclass, field
from pathlib import Path


@dataclass
class Compiled:
    """One compiled specialisation of one dispatcher."""

    qualname: str
    module: str
    dispatcher: int
    signature: str
    #: the function whose compilation compiled this one, or the Python caller (file:line)
    parent: str = ""
    incl: float = 0.0
    children: float = 0.0
    passes: dict[str, float] = field(default_factory=dict)

    @property
    def self_time(self) -> float:
        return self.incl - self.children


def _listener_class():  # imported lazily: numba only once the cache folder is set
    from numba.core import event as ev

    class CompileRecorder(ev.Listener):
        """Nested ``numba:compile`` events -> :class:`Compiled` rows with self CPU time."""

        def __init__(self) -> None:
            self.rows: list[Compiled] = []
            self._stack: list[tuple[Compiled, float]] = []
            #: open compiler passes ``[name, start, nested compile time]`` (PassRecorder)
            self.passes: list[list] = []

        def on_start(self, event) -> None:
            d = event.data
            disp = d["dispatcher"]
            fn = disp.py_func
            sig = ", ".join(str(a) for a in d["args"])
            parent = self._stack[-1][0].qualname if self._stack else _python_caller()
            row = Compiled(fn.__qualname__, fn.__module__, id(disp), sig, parent)
            self._stack.append((row, time.process_time()))

        def on_end(self, event) -> None:
            row, t0 = self._stack.pop()
            row.incl = time.process_time() - t0
            if self._stack:
                self._stack[-1][0].children += row.incl
            if self.passes:  # a callee compiled while typing: not the open pass's own time
                self.passes[-1][2] += row.incl
            self.rows.append(row)

    class PassRecorder(ev.Listener):
        """Self CPU time of every compiler pass, by pass name, attributed to the open row."""

        def __init__(self, compiles: CompileRecorder) -> None:
            self.compiles = compiles

        def on_start(self, event) -> None:
            name = event.data["name"].split(" [")[0]
            self.compiles.passes.append([name, time.process_time(), 0.0])

        def on_end(self, event) -> None:
            name, t0, nested = self.compiles.passes.pop()
            if self.compiles._stack:
                row = self.compiles._stack[-1][0]
                own = time.process_time() - t0 - nested
                row.passes[name] = row.passes.get(name, 0.0) + own

    return ev, CompileRecorder, PassRecorder


def _python_caller() -> str:
    """``file:line`` of the innermost frame outside numba that called a dispatcher."""
    import traceback

    for fr in reversed(traceback.extract_stack()):
        if "/numba/" not in fr.filename and not fr.filename.endswith(__file__.rsplit("/", 1)[-1]):
            parts = fr.filename.split("/")
            return f"{'/'.join(parts[-2:])}:{fr.lineno}"
    return "?"


def _short(sig: str, width: int = 70) -> str:
    return sig if len(sig) <= width else sig[: width - 1] + "…"


def report(rows: list[Compiled], total_cpu: float, passes: bool) -> str:
    """Markdown tables: per specialisation (by self time), then per function."""
    total_self = sum(r.self_time for r in rows) or 1.0
    n_fn = len({(r.module, r.qualname) for r in rows})
    out = [(f"compile CPU (sum of self times): {total_self:.1f} s of {total_cpu:.1f} s CPU in "
            f"the whole run; {len(rows)} specialisations of {n_fn} functions\n"),
           "| function | module | signature | compiled by | self s | incl s | share |",
           "|---|---|---|---|---:|---:|---:|"]
    for r in sorted(rows, key=lambda r: -r.self_time):
        out.append(f"| `{r.qualname}` | {r.module.removeprefix('poissonkit.')} | "
                   f"{_short(r.signature, 40)} | {r.parent} | {r.self_time:.2f} | {r.incl:.2f} | "
                   f"{100 * r.self_time / total_self:.1f} % |")
    by_fn: dict[tuple[str, str], list[Compiled]] = defaultdict(list)
    for r in rows:
        by_fn[(r.module, r.qualname)].append(r)
    out += ["", "| function | specialisations | dispatchers | self s | share |",
            "|---|---:|---:|---:|---:|"]
    for (mod, qn), rs in sorted(by_fn.items(), key=lambda kv: -sum(r.self_time for r in kv[1])):
        s = sum(r.self_time for r in rs)
        out.append(f"| `{qn}` | {len(rs)} | {len({r.dispatcher for r in rs})} | {s:.2f} | "
                   f"{100 * s / total_self:.1f} % |")
    if passes:
        agg: dict[str, float] = defaultdict(float)
        for r in rows:
            for k, v in r.passes.items():
                agg[k] += v
        out += ["", "| compiler pass | self CPU s (all functions) |", "|---|---:|"]
        out += [f"| {k} | {v:.2f} |" for k, v in sorted(agg.items(), key=lambda kv: -kv[1])[:12]]
    return "\n".join(out)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scene")
    ap.add_argument("--passes", action="store_true", help="also CPU time per compiler pass")
    a, extra = ap.parse_known_args()
    with tempfile.TemporaryDirectory(prefix="pk-breakdown-") as tmp:
        os.environ["POISSONKIT_CACHE_DIR"] = str(Path(tmp) / "cache")  # empty: every kernel cold
        # kernels decorated with numba's own ``cache=True`` (kernels.py, celllists.py, the
        # Wisdom–Holman modules, the magnets plugin) cache beside their source unless
        # NUMBA_CACHE_DIR is set: point it at the empty folder too (read when numba is imported)
        os.environ["NUMBA_CACHE_DIR"] = str(Path(tmp) / "numba")
        ev, CompileRecorder, PassRecorder = _listener_class()
        from poissonkit.cli import main as cli_main

        rec = CompileRecorder()
        ev.register("numba:compile", rec)
        if a.passes:
            ev.register("numba:run_pass", PassRecorder(rec))
        cpu0 = time.process_time()
        code = cli_main(["run", a.scene, "--no-plot", "--no-progress", "--out",
                         str(Path(tmp) / "out"), *extra])
        total = time.process_time() - cpu0
    print(f"poissonkit run {a.scene} {' '.join(extra)}: exit {code}", file=sys.stderr)
    print(report(rec.rows, total, a.passes))


if __name__ == "__main__":
    main()
