"""What went wrong in a sweep, point by point: failed runs and failed outcomes, by kind.

A point's ``error`` variable holds either the message of a run that raised (``failed`` is true,
every outcome its fill value) or, for a run that finished, one line
``outcome NAME: Type: message`` per outcome that raised (``failed`` is false, the other outcomes
and the fate kept). :func:`failure_kinds` groups both by kind -- the exception type of a failed
run, ``outcome NAME (Type)`` for a failed outcome -- with a count and the first example;
:func:`failure_table` and :func:`point_table` print them for ``poissonkit sweep``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    import xarray as xr

#: Start of the line recording one failed outcome in a point's ``error``.
OUTCOME_PREFIX = "outcome "

#: Largest grid printed point by point at the end of ``poissonkit sweep`` (a summary beyond).
POINT_TABLE_LIMIT = 50


def outcome_error_text(errors: Mapping[str, str]) -> str:
    """The ``error`` text of a finished run whose outcomes ``errors`` (name -> message) raised:
    one ``outcome NAME: message`` line each ("" for none)."""
    return "\n".join(f"{OUTCOME_PREFIX}{name}: {msg}" for name, msg in errors.items())


def _exception_type(message: str) -> str:
    """``"InputError"`` of ``"InputError: ..."`` (the first word before a colon)."""
    head = message.split(":", 1)[0].strip()
    return head if head and " " not in head else "error"


def kinds_of(failed: bool, error: str) -> list[str]:
    """The failure kinds of one point (none for a clean point).

    A failed run is one kind, its exception type (``"run InputError"``); a finished run has
    one kind per failed outcome (``"outcome megno (InputError)"``).
    """
    if failed:
        return [f"run {_exception_type(error)}"]
    out = []
    for line in error.splitlines():
        if line.startswith(OUTCOME_PREFIX) and ": " in line:
            name, msg = line[len(OUTCOME_PREFIX):].split(": ", 1)
            out.append(f"outcome {name} ({_exception_type(msg)})")
    return out


@dataclass(frozen=True)
class FailureKind:
    """One kind of failure in a sweep: how many points, and the first of them."""

    kind: str
    count: int
    example: str  # the message of the first point of this kind (its first line)
    values: dict[str, float]  # the parameter values of that point


def _flat(ds: xr.Dataset, name: str) -> np.ndarray:
    return np.asarray(ds[name].values).reshape(-1)


def point_values(ds: xr.Dataset, k: int) -> dict[str, float]:
    """The swept parameter values of flat point ``k`` (grid axes or random samples)."""
    dims = tuple(ds["completed"].dims)
    shape = tuple(int(ds.sizes[d]) for d in dims)
    index = np.unravel_index(k, shape)
    out: dict[str, float] = {}
    for name, coord in ds.coords.items():
        if name == "sample" or not coord.dims:
            continue
        pos = tuple(index[dims.index(d)] for d in coord.dims)
        out[str(name)] = float(np.asarray(coord.values)[pos])
    return out


def failure_kinds(ds: xr.Dataset) -> list[FailureKind]:
    """Every kind of failure in the sweep's completed points, most frequent first."""
    failed = _flat(ds, "failed").astype(bool)
    completed = _flat(ds, "completed").astype(bool)
    errors = _flat(ds, "error")
    counts: dict[str, int] = {}
    first: dict[str, int] = {}
    for j in np.nonzero(completed)[0]:
        msg = str(errors[j] or "")
        for kind in kinds_of(bool(failed[j]), msg):
            counts[kind] = counts.get(kind, 0) + 1
            first.setdefault(kind, int(j))
    out = []
    for kind, n in counts.items():
        k = first[kind]
        lines = str(errors[k]).splitlines() or [""]
        line = next((x for x in lines if kind.startswith("run")
                     or x.startswith(OUTCOME_PREFIX + kind.split()[1] + ":")), lines[0])
        out.append(FailureKind(kind, n, line, point_values(ds, k)))
    return sorted(out, key=lambda f: (-f.count, f.kind))


def _fmt(v: float) -> str:
    return f"{v:.6g}"


def _values_text(values: Mapping[str, float]) -> str:
    return ", ".join(f"{k}={_fmt(v)}" for k, v in values.items())


def _columns(rows: Sequence[Sequence[str]], header: Sequence[str]) -> str:
    widths = [max(len(str(r[i])) for r in [header, *rows]) for i in range(len(header))]
    lines = ["  ".join(str(c).ljust(w) for c, w in zip(r, widths)).rstrip()
             for r in [header, *rows]]
    return "\n".join(lines)


def failure_table(ds: xr.Dataset, width: int = 160) -> str:
    """The failures by kind (kind, count, first example with its parameter values), "" if
    none."""
    found = failure_kinds(ds)
    if not found:
        return ""
    rows = []
    for f in found:
        example = f"{_values_text(f.values)}: {f.example}"
        if len(example) > width:
            example = example[:width - 1] + "…"
        rows.append((f.kind, str(f.count), example))
    return _columns(rows, ("kind", "count", "first example"))


def point_table(ds: xr.Dataset, fates: Sequence[str], limit: int = POINT_TABLE_LIMIT) -> str:
    """One line per point (parameters, fate, the other outcomes, status) for a sweep of at
    most ``limit`` points; beyond, a count of points per fate and status."""
    fate = _flat(ds, "fate").astype(int)
    failed = _flat(ds, "failed").astype(bool)
    completed = _flat(ds, "completed").astype(bool)
    errors = _flat(ds, "error")
    names = [str(n) for n in ds.data_vars
             if n not in ("fate", "completed", "failed", "error")]

    def status(k: int) -> str:
        if not completed[k]:
            return "not run"
        kinds = kinds_of(bool(failed[k]), str(errors[k] or ""))
        return "failed: " + ", ".join(kinds) if kinds else "ok"

    def fate_name(k: int) -> str:
        return fates[fate[k]] if 0 <= fate[k] < len(fates) else "-"

    n = fate.size
    if n > limit:
        tally: dict[tuple[str, str], int] = {}
        for k in range(n):
            key = (fate_name(k), status(k))
            tally[key] = tally.get(key, 0) + 1
        counted = [(f, s, str(c)) for (f, s), c in sorted(tally.items())]
        return (f"{n} points (more than {limit}: counts per fate and status)\n"
                + _columns(counted, ("fate", "status", "points")))
    params = list(point_values(ds, 0)) if n else []
    rows = []
    for k in range(n):
        vals = point_values(ds, k)
        rows.append([_fmt(vals[p]) for p in params] + [fate_name(k)]
                    + [_fmt(float(_flat(ds, m)[k])) for m in names] + [status(k)])

    def head(name: str) -> str:  # the name with its SI unit ("1": none)
        unit = str(ds[name].attrs.get("units", "1"))
        return name if unit in ("1", "") else f"{name} [{unit}]"

    return _columns(rows, [*(head(p) for p in params), "fate", *(head(m) for m in names),
                           "status"])


def outcome_failure_count(ds: xr.Dataset) -> int:
    """Points whose run finished but at least one outcome failed."""
    failed = _flat(ds, "failed").astype(bool)
    errors = _flat(ds, "error")
    return sum(1 for f, e in zip(failed, errors) if not f and kinds_of(False, str(e or "")))


def any_failure(ds: xr.Dataset) -> bool:
    """True when a completed point's run or one of its outcomes failed."""
    return bool(failure_kinds(ds))
