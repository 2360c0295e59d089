"""Shared test fixtures, and the kernel cache one test session shares between its processes."""

from __future__ import annotations

import os
import sys
from collections import Counter
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: The seeds and the verified reference live beside the project root.
SHARED = ROOT.parent / "shared"

#: Environment variable of the on-disk kernel cache (``poissonkit.numerics.jit.CACHE_ENV``; not
#: imported here so that setting it precedes every poissonkit import).
CACHE_ENV = "POISSONKIT_CACHE_DIR"
#: Sub-folder of pytest's cache folder (``.pytest_cache/d/``, git-ignored) holding the kernels.
KERNEL_CACHE = "poissonkit-kernels"


def kernel_cache_folder(config: pytest.Config) -> Path:
    """The kernel cache of a test run whose user did not choose one.

    pytest's own cache folder of the checkout: every xdist worker and every subprocess a test
    starts computes the same path, so a kernel compiled once is loaded everywhere after (the
    cache is safe for concurrent writers: entries are replaced atomically and each data file is
    checked against its key). A second run of the suite is warm; a fresh clone, or
    ``pytest --cache-clear``, starts empty. Tests never fill the user's ``~/.cache``.
    """
    cache = getattr(config, "cache", None)
    if cache is not None:
        return cache.mkdir(KERNEL_CACHE)
    # -p no:cacheprovider: the same place, made by hand
    folder = Path(config.rootpath) / ".pytest_cache" / "d" / KERNEL_CACHE
    folder.mkdir(parents=True, exist_ok=True)
    return folder


def pytest_configure(config: pytest.Config) -> None:
    if not os.environ.get(CACHE_ENV):  # the user's choice (a folder, or "off") wins
        os.environ[CACHE_ENV] = str(kernel_cache_folder(config))


# ------------------------------------------------------------ fuzz counts across xdist workers
#: Counts sent by xdist workers (``{target: Counter}``), summed in the controlling process.
_WORKER_FUZZ_COUNTS: dict[str, Counter] = {}


def _local_fuzz_counts() -> dict[str, Counter]:
    fuzzkit = sys.modules.get("fuzzkit")  # imported only when fuzz tests ran in this process
    return getattr(fuzzkit, "COUNTS", {})


def pytest_sessionfinish(session: pytest.Session) -> None:
    workeroutput = getattr(session.config, "workeroutput", None)
    if workeroutput is not None:  # an xdist worker: hand the counts to the controller
        workeroutput["fuzz_counts"] = {t: dict(c) for t, c in _local_fuzz_counts().items()}


@pytest.hookimpl(optionalhook=True)
def pytest_testnodedown(node, error) -> None:  # xdist's hook: a worker has finished
    for target, counts in getattr(node, "workeroutput", {}).get("fuzz_counts", {}).items():
        _WORKER_FUZZ_COUNTS.setdefault(target, Counter()).update(counts)


def pytest_terminal_summary(terminalreporter, exitstatus, config) -> None:
    """How many inputs each fuzz target tried and how they ended (see ``tests/fuzz/fuzzkit``)."""
    totals: dict[str, Counter] = {}
    for source in (_local_fuzz_counts(), _WORKER_FUZZ_COUNTS):
        for target, counts in source.items():
            totals.setdefault(target, Counter()).update(counts)
    if totals:
        terminalreporter.section("fuzz counts")
        for target, c in sorted(totals.items()):
            terminalreporter.write_line(
                f"{target:<22} tried {c['tried']:>7}  worked {c['ok']:>7}  "
                f"typed errors {c['typed_error']:>7}  anything else {c['other']:>3}")


@pytest.fixture(autouse=True)
def _fresh_plugin_manager(monkeypatch):
    """Each test sees a plugin manager built from the current environment."""
    from poissonkit.plugin import reset

    reset()
    yield
    reset()


os.environ.setdefault("MPLBACKEND", "Agg")
