"""``check_outcome``: a sweep outcome against :class:`~poissonkit.plugin.OutcomeEntry`.

Its ``dtype`` is a numpy dtype, its ``fill`` fits it, a unit is declared, and ``compute``
reduces a real finished run (:func:`sample_record`: two tops on a circular orbit under
gravity, with their spins) to one value of that dtype, the same value twice (deterministic),
and survives pickling for Dask workers.
"""

from __future__ import annotations

import math
import pickle
from typing import Any

import numpy as np

from poissonkit.plugin.contributions import OutcomeEntry
from poissonkit.testing.lookup import findings_for

_RECORD: list[Any] = []


def sample_record() -> Any:
    """A :class:`~poissonkit.sweeps.targets.RunRecord` of a short, bounded run (SI = internal
    units: two tops of mass 1 orbiting at distance 1 under gravity with G = 1)."""
    if _RECORD:
        return _RECORD[0]
    from poissonkit.numerics import AllPairs, Body, NBodySystem, solve
    from poissonkit.sweeps.targets import RunRecord

    system = NBodySystem([Body("a", 1.0, alpha=1.0), Body("b", 1.0, alpha=1.0)],
                         [AllPairs("gravity", {"G": 1.0})])
    v = math.sqrt(0.5)  # circular: each at 0.5 from the centre, m v²/0.5 = G m²/1²
    y0 = system.pack([[-0.5, 0, 0], [0.5, 0, 0]], [[0, -v, 0], [0, v, 0]],
                     axes=[[0, 0, 1.0], [1.0, 0, 0]], angular_momenta=[[0.3, 0, 1], [0, 0.2, 1]])
    sol = solve(system, y0, 2.0, "splitting4", step=0.01)
    r = np.asarray(system.unpack(np.asarray(sol.y))["r"])
    dist = np.linalg.norm(r[:, 1] - r[:, 0], axis=-1)
    _RECORD.append(RunRecord(sol, "bounded", math.nan, dist, 1.0, 1.0, 1.0,
                             (system, y0, float(sol.t[-1]), "splitting4", 0.01)))
    return _RECORD[0]


def check_outcome(outcome: OutcomeEntry | str, *, record: Any = None) -> None:
    """Check a sweep outcome; raise :class:`CheckFailed` listing every defect.

    Parameters
    ----------
    outcome
        The :class:`~poissonkit.plugin.OutcomeEntry` or its registered name.
    record
        The :class:`~poissonkit.sweeps.targets.RunRecord` to reduce (default
        :func:`sample_record`).

    Raises
    ------
    CheckFailed
    """
    import cloudpickle

    entry, out = findings_for(outcome, "outcome", OutcomeEntry)
    try:
        dtype = np.dtype(entry.dtype)
    except TypeError as exc:
        out.add("dtype", f"{entry.dtype!r} is not a numpy dtype: {exc}")
        out.raise_if_any()
        return
    if not entry.unit:
        out.add("unit", "declares no unit ('1' for a dimensionless value)")
    with out.guard("fill"), np.errstate(invalid="ignore"):
        if np.asarray(entry.fill).astype(dtype).tolist() != np.asarray(entry.fill).tolist() \
                and not (isinstance(entry.fill, float) and math.isnan(entry.fill)
                         and dtype.kind == "f"):
            out.add("fill", f"fill {entry.fill!r} does not fit dtype {dtype}")
    rec = record if record is not None else sample_record()
    with out.guard("compute"):
        first, second = entry.compute(rec), entry.compute(rec)
        value = np.asarray(first)
        if value.shape != ():
            out.add("compute", f"returns shape {value.shape}, not one value")
        elif value.astype(dtype).tolist() != value.tolist() and not (
                dtype.kind == "f" and value.dtype.kind in "fiu"):
            out.add("compute", f"returns {first!r}, which dtype {dtype} does not hold")
        if not _equal(first, second):
            out.add("compute", f"two calls on the same run differ: {first!r}, {second!r}")
    with out.guard("pickle"):
        copy = pickle.loads(cloudpickle.dumps(entry))
        if not _equal(copy.compute(rec), entry.compute(rec)):
            out.add("pickle", "the unpickled copy computes another value")
    out.raise_if_any()


def _equal(a: Any, b: Any) -> bool:
    x, y = np.asarray(a), np.asarray(b)
    return bool(np.array_equal(x, y, equal_nan=x.dtype.kind == "f" and y.dtype.kind == "f"))
