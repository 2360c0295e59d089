"""A long run with checkpoints, killed and resumed by test_checkpoint_resume.py.

Usage: ``python resumable_run.py FOLDER METHOD [--resume]``. Writes ``FOLDER/final.npy`` (the
final state, atomically) when the run completes.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from reliability_helpers import KILL_RUNS, bound_pair, orbit_state  # noqa: E402

from poissonkit.numerics import solve  # noqa: E402
from poissonkit.numerics.checkpoint import Checkpoint  # noqa: E402
from poissonkit.report.atomic import atomic_path  # noqa: E402


def main() -> None:
    folder, method = Path(sys.argv[1]), sys.argv[2]
    resume = "--resume" in sys.argv[3:]
    run = KILL_RUNS[method]
    sol = solve(bound_pair(), orbit_state(), run["t_end"], method, step=run["step"],
                save_every=run["save_every"],
                checkpoint=Checkpoint(folder / "checkpoints", run["every"]), resume=resume,
                stream=folder / "parts")
    with atomic_path(folder / "final.npy") as tmp:
        np.save(tmp, sol.y[-1])
    print(sol.extra.get("resumed_from", "fresh"), flush=True)


if __name__ == "__main__":
    main()
