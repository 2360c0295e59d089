"""Running a sweep on Dask distributed: batches, a per-worker cache, retries, progress, resume.

* With no client or address, a :class:`distributed.LocalCluster` on this machine (worker
  *processes*, one thread each, on the loopback interface); with ``scheduler="tcp://host:port"``
  or a :class:`distributed.Client` the same sweep runs on an existing cluster unchanged.
* Points are grouped in batches (one task each) so per-task overhead stays small.
* :func:`run_batch` builds the scene's system and compiled kernels once per worker process and
  keeps them in a module-level cache keyed by the scene (:attr:`key`), so later tasks reuse them.
* A run that raises becomes a failed point with its message. Tasks lost with a dying worker are
  rescheduled by the Dask scheduler; tasks that raise (e.g. the scene cannot be built on a
  worker) are retried ``retries`` times by Dask (``Client.submit(retries=...)``); only then are
  their points recorded as failed.
"""

from __future__ import annotations

import math
import os
import uuid
from collections.abc import Callable, Iterable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from poissonkit.contracts import SweepScene
from poissonkit.errors import InputError, MissingDependencyError
from poissonkit.plugin.contributions import OutcomeEntry

if TYPE_CHECKING:  # dask is imported where used
    from distributed import Client

#: One point's result: ``(flat index, outcome values by name or None if the run failed, error
#: message: the run's, or one ``outcome NAME: ...`` line per failed outcome, "" if none)``.
PointResult = tuple[int, dict[str, object] | None, str]

#: What each worker process has built, by scene key (see :func:`run_batch`).
_PREPARED: dict[str, Mapping[str, object]] = {}
#: How many times this process built a scene (read by tests through ``Client.run``).
_BUILDS: dict[str, int] = {}


def builds() -> dict[str, int]:
    """Number of scene builds in this process, by scene key."""
    return dict(_BUILDS)


def _prepared(scene: SweepScene) -> Mapping[str, object]:
    key = scene.key
    if key not in _PREPARED:
        _PREPARED[key] = scene.prepare()
        _BUILDS[key] = _BUILDS.get(key, 0) + 1
    return _PREPARED[key]


def run_batch(scene: SweepScene, points: Sequence[tuple[int, Mapping[str, float]]],
              outcomes: Sequence[str | OutcomeEntry]
              ) -> list[PointResult]:
    """Run a batch of points on a worker: ``[(flat index, outcomes or None, error message)]``.

    ``outcomes`` are registry names or the entries themselves (the client sends entries, so
    a plugin's outcome needs no plugin on the workers). An exception inside one run is that
    point's failure (outcomes ``None``, message kept); it does not stop the batch. An outcome
    that raises gets its fill value and a line ``outcome NAME: Type: message`` in the point's
    message, the other outcomes kept (:mod:`poissonkit.sweeps.failures`).
    """
    from poissonkit.sweeps.compiles import count_compilations
    from poissonkit.sweeps.failures import outcome_error_text
    from poissonkit.sweeps.outcomes import reduce_run_kept

    count_compilations()  # a worker reports its compilations (compiles.compilations)
    prep = _prepared(scene)
    out: list[PointResult] = []
    for idx, values in points:
        try:
            rec = scene.run(prep, values)
        except Exception as exc:  # noqa: BLE001 - any failure of one run is recorded, not fatal
            out.append((idx, None, f"{type(exc).__name__}: {exc}"))
            continue
        # an outcome that fails keeps the others (the fate): its message names it
        found, errors = reduce_run_kept(rec, outcomes)
        out.append((idx, found, outcome_error_text(errors)))
    return out


def _require_dask() -> None:
    try:
        import distributed  # noqa: F401
        import xarray  # noqa: F401
        import zarr  # noqa: F401
    except ImportError as exc:  # pragma: no cover - they are core dependencies
        raise MissingDependencyError(
            f"sweeps need dask[distributed], xarray and zarr ({exc}); "
            "install them with: pip install 'dask[distributed]' xarray zarr") from None


def make_client(client: Client | None = None, scheduler: str | None = None,
                workers: int | None = None) -> tuple[Client, Callable[[], None]]:
    """The client to use and a function closing whatever was started here.

    Parameters
    ----------
    client
        An existing :class:`distributed.Client` (used as is, not closed).
    scheduler
        Address of a running scheduler, e.g. ``"tcp://SCHEDULER-HOST:8786"``.
    workers
        Worker processes of a new local cluster (default: the number of CPUs, at most 4).
    """
    _require_dask()
    from distributed import Client, LocalCluster

    if client is not None:
        if scheduler is not None or workers is not None:
            raise InputError("give a client, or a scheduler address, or a number of workers")
        return client, lambda: None
    if scheduler is not None:
        if workers is not None:
            raise InputError("--workers starts a local cluster; with --scheduler the cluster "
                             "decides (leave --workers out)")
        if not isinstance(scheduler, str) or "://" not in scheduler:
            raise InputError(f"scheduler must be an address like tcp://host:8786, got "
                             f"{scheduler!r}")
        try:
            c = Client(scheduler, timeout="20s")
        except OSError as exc:
            raise InputError(f"cannot reach the scheduler at {scheduler}: {exc}") from None
        return c, c.close
    n = workers if workers is not None else min(4, os.cpu_count() or 1)
    if not isinstance(n, (int, np.integer)) or n < 1:
        raise InputError(f"workers must be a positive integer, got {workers!r}")
    # loopback only; the diagnostics page on a free port (a fixed one clashes with other
    # clusters on the machine)
    cluster = LocalCluster(n_workers=int(n), threads_per_worker=1, processes=True,
                           host="127.0.0.1", dashboard_address="127.0.0.1:0")
    c = Client(cluster)

    def close() -> None:
        import logging

        # the nanny logs a warning when a worker process takes a few seconds to exit at the
        # end (interpreter and LLVM teardown); nothing is lost then, so keep it quiet
        log = logging.getLogger("distributed.nanny")
        level = log.level
        log.setLevel(logging.ERROR)
        try:
            c.close()
            cluster.close()
        finally:
            log.setLevel(level)

    return c, close


def worker_count(client: Client) -> int:
    """Number of workers the client's cluster has now (at least 1)."""
    return max(1, len(client.scheduler_info(n_workers=-1).get("workers", {})) or 1)


def batch_size_for(n_points: int, n_workers: int, batch_size: int | None) -> int:
    """Runs per batch: ``batch_size`` checked, or by default about 8 batches per worker, at
    most 64 runs each (small enough to balance and to lose little with a dying worker)."""
    if batch_size is None:
        return max(1, min(64, math.ceil(n_points / (8 * max(1, n_workers)))))
    if (isinstance(batch_size, bool) or not isinstance(batch_size, (int, np.integer))
            or batch_size < 1):
        raise InputError(f"batch_size must be a positive integer, got {batch_size!r}")
    return int(batch_size)


def batches(todo: Sequence[tuple[int, dict[str, float]]], n_workers: int,
            batch_size: int | None) -> list[list[tuple[int, dict[str, float]]]]:
    """Split the points into consecutive batches (size from :func:`batch_size_for`)."""
    size = batch_size_for(len(todo), n_workers, batch_size)
    return [list(todo[k:k + size]) for k in range(0, len(todo), size)]


def execute(scene: SweepScene, todo: Sequence[tuple[int, dict[str, float]]],
            outcomes: Sequence[str | OutcomeEntry],
            client: Client, *, on_results: Callable[[list[PointResult]], None],
            batch_size: int | None = None, retries: int = 2,
            progress: bool = True, total: int | None = None, done: int = 0,
            failures: int = 0,
            parts: Sequence[Sequence[tuple[int, dict[str, float]]]] | None = None) -> None:
    """Submit the batches, hand each finished batch to ``on_results`` as it completes.

    ``parts``: the batches already formed (a sweep store's chunks); otherwise ``todo`` is split
    by :func:`batches`. A batch whose task fails for good (after Dask's retries, or because its
    workers kept dying) is handed over as failed points with the task's error.
    """
    from distributed import as_completed
    from tqdm.auto import tqdm

    if parts is None:
        parts = batches(todo, worker_count(client), batch_size)
    tag = uuid.uuid4().hex[:8]
    futures = {client.submit(run_batch, scene, part, tuple(outcomes), retries=retries,
                             pure=False, key=f"sweep-{tag}-{k}"): part
               for k, part in enumerate(parts)}
    bar = tqdm(total=total if total is not None else len(todo), initial=done, unit="run",
               desc="sweep", disable=not progress, dynamic_ncols=True)
    bar.set_postfix(failures=failures)
    try:
        for fut in as_completed(futures):
            part = futures[fut]
            try:
                res = fut.result()
            except Exception as exc:  # noqa: BLE001 - the batch failed for good: its points
                msg = f"{type(exc).__name__}: {exc}"
                res = [(idx, None, msg) for idx, _ in part]
            on_results(res)
            failures += sum(1 for _, r, _e in res if r is None)
            bar.update(len(res))
            bar.set_postfix(failures=failures)
            fut.release()
    except BaseException:
        client.cancel(list(futures))
        raise
    finally:
        bar.close()


def resolve_units(scene: SweepScene, paths: Iterable[str]) -> dict[str, str]:
    """Units of each swept parameter (validates the paths first)."""
    out = {}
    for p in paths:
        scene.check(p)
        out[p] = scene.units(p)
    return out


def default_store(out: str | Path) -> Path:
    """The Zarr store inside an output folder."""
    return Path(out) / "sweep.zarr"
