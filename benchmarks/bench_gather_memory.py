"""Peak memory of the final gather of a streamed trajectory into ``trajectory.npz``.

Usage: ``python benchmarks/bench_gather_memory.py [ROWS]`` (default 10**6 rows of 18 values,
the state of two tops). Writes the parts once (``TrajectoryStream``, 65 536 rows a part), then
gathers them in a fresh process each way and prints the peak: the whole-array writer
(``read_trajectory`` + ``write_trajectory``, what ``poissonkit run`` did before) and the streamed
one (:func:`poissonkit.report.gather.gather_trajectory`). Peak = the process's largest resident
set (``ru_maxrss``) minus its resident set just before the gather, and tracemalloc's peak of
Python allocations during the gather.
"""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

CHILD = r"""
import json, resource, sys, tracemalloc
from pathlib import Path
import numpy as np
from poissonkit.numerics.checkpoint import read_trajectory
from poissonkit.report.gather import gather_trajectory
from poissonkit.report.summary import write_trajectory

mode, folder, out = sys.argv[1], Path(sys.argv[2]), Path(sys.argv[3])
def rss_mb():
    with open("/proc/self/status") as fh:
        for line in fh:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
base = rss_mb()
tracemalloc.start()
if mode == "whole":
    t, y = read_trajectory(folder)
    write_trajectory(out, t, y, layout=("y",) * y.shape[1], time_unit=2.0,
                     r_rel_si=y[:, :3] * 3.0)
else:
    gather_trajectory(out, folder, layout=("y",) * 18, time_unit=2.0,
                      row_maps={"r_rel_si": lambda b: b[:, :3] * 3.0})
traced = tracemalloc.get_traced_memory()[1] / 2**20
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
print(json.dumps({"mode": mode, "rss_before_mb": base, "rss_peak_mb": peak,
                  "rss_added_mb": peak - base, "tracemalloc_peak_mb": traced}))
"""


def main() -> None:
    from poissonkit.numerics.checkpoint import TrajectoryStream

    rows = int(sys.argv[1]) if len(sys.argv) > 1 else 10**6
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp) / "parts"
        stream = TrajectoryStream(folder)
        rng = np.random.default_rng(0)
        for start in range(0, rows, stream.max_rows):
            n = min(stream.max_rows, rows - start)
            stream.write(np.arange(start, start + n) * 1e-3, rng.standard_normal((n, 18)))
        results = []
        for mode in ("whole", "streamed"):
            out = Path(tmp) / f"{mode}.npz"
            done = subprocess.run([sys.executable, "-c", CHILD, mode, str(folder), str(out)],
                                  capture_output=True, text=True, check=True)
            results.append(json.loads(done.stdout))
        with np.load(Path(tmp) / "whole.npz") as a, np.load(Path(tmp) / "streamed.npz") as b:
            same = a.files == b.files and all(a[k].tobytes() == b[k].tobytes() for k in a.files)
    print(f"{rows} rows x 18, {(rows * 18 * 8) / 2**20:.0f} MiB of y; files identical: {same}")
    for r in results:
        print(f"{r['mode']:>9}: peak RSS {r['rss_peak_mb']:.0f} MB (+{r['rss_added_mb']:.0f} MB "
              f"over {r['rss_before_mb']:.0f} MB before), tracemalloc peak "
              f"{r['tracemalloc_peak_mb']:.1f} MB")


if __name__ == "__main__":
    main()
