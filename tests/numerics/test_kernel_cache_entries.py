"""Kernel-cache entries are checked against the key they were stored under before numba loads
them: files holding other kernels' valid entries, truncated or garbage files are cache misses
(compiled again), never a crash or a wrong result. Read-only and unreadable cache folders are
tested as an unprivileged user (the suite may run as root, which ignores permissions)."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest

from poissonkit.numerics import jit as jitmod
from poissonkit.numerics.jit import cache_stats, jit

ROOT = Path(__file__).resolve().parents[2]
NOBODY = 65534


def _scaled(k: float):
    @jit
    def f(x):
        return k * x

    return f


def _pair(k: float):
    @jit
    def f(x, y):
        return k * x + y

    return f


def _data_file(folder: Path, before: set[Path]) -> Path:
    new = set(folder.rglob("*.nbc")) - before
    assert len(new) == 1, new
    return new.pop()


@pytest.fixture
def cache(tmp_path, monkeypatch) -> Path:
    monkeypatch.setenv(jitmod.CACHE_ENV, str(tmp_path))
    return tmp_path


def test_other_kernels_entry_with_the_same_signature_is_a_miss(cache):
    assert _scaled(2.0)(1.5) == 3.0
    first = _data_file(cache, set())
    assert _scaled(3.0)(1.5) == 4.5
    second = _data_file(cache, {first})
    shutil.copyfile(second, first)  # the file of k=2 now holds the valid entry of k=3
    f = _scaled(2.0)
    assert f(1.5) == 3.0  # not 4.5
    assert cache_stats(f) == (0, 1)
    again = _scaled(2.0)  # the entry was rewritten by the recompile
    assert again(1.5) == 3.0 and cache_stats(again) == (1, 0)


def test_other_kernels_entry_with_another_signature_is_a_miss(cache):
    assert _scaled(2.0)(1.5) == 3.0
    first = _data_file(cache, set())
    assert _pair(2.0)(1.5, 1.0) == 4.0
    second = _data_file(cache, {first})
    shutil.copyfile(second, first)  # today: numba TypingError when loaded
    f = _scaled(2.0)
    assert f(1.5) == 3.0
    assert cache_stats(f) == (0, 1)


@pytest.mark.parametrize("damage", ["truncate", "garbage", "empty", "index-garbage"])
def test_damaged_entries_are_misses(cache, damage):
    assert _scaled(5.0)(2.0) == 10.0
    data = _data_file(cache, set())
    index = next(cache.rglob("*.nbi"))
    if damage == "truncate":
        data.write_bytes(data.read_bytes()[: data.stat().st_size // 2])
    elif damage == "garbage":
        data.write_bytes(os.urandom(4096))
    elif damage == "empty":
        data.write_bytes(b"")
    else:
        index.write_bytes(os.urandom(300))
    f = _scaled(5.0)
    assert f(2.0) == 10.0 and cache_stats(f) == (0, 1)


def test_a_mismatch_is_logged_at_debug_level(cache, caplog):
    assert _scaled(2.0)(1.0) == 2.0
    first = _data_file(cache, set())
    assert _scaled(4.0)(1.0) == 4.0
    shutil.copyfile(_data_file(cache, {first}), first)
    with caplog.at_level("DEBUG", logger="poissonkit.numerics.jit"):
        assert _scaled(2.0)(1.0) == 2.0
    assert any("not the entry stored" in r.getMessage() for r in caplog.records)


# ------------------------------------------------------------------ permissions, non-root
# The child starts as the test user and drops to ``uid`` itself, after importing numba and
# compiling once without a cache: the interpreter and site-packages may live where the
# unprivileged user cannot read (``/root/.pyenv``), while everything the kernel cache touches
# happens after the drop.
_CHILD = """
import json, os, sys, warnings
import numba
import numpy
numba.njit(lambda x: x + 1.0)(1.0)
from poissonkit.numerics.jit import cache_stats, jit
uid = int(sys.argv[1])
if uid >= 0:
    os.setgroups([])
    os.setgid(uid)
    os.setuid(uid)
    assert os.geteuid() == uid
warnings.simplefilter("always")
with warnings.catch_warnings(record=True) as caught:

    def scaled(k):
        @jit
        def f(x):
            return k * x
        return f

    values, stats = [], []
    for k in (2.0, 3.0, 2.0):
        f = scaled(k)
        values.append(f(1.5))
        stats.append(cache_stats(f))
print(json.dumps({"values": values, "stats": stats,
                  "warnings": [str(w.message) for w in caught]}))
"""


def _can_drop_privileges() -> bool:
    return hasattr(os, "setuid") and os.geteuid() == 0


def _run_as(uid: int | None, cache: Path, tmp: Path) -> dict:
    env = dict(os.environ, **{jitmod.CACHE_ENV: str(cache), "HOME": str(tmp),
                              "NUMBA_CACHE_DIR": str(tmp / "numba"),
                              "PYTHONPATH": os.pathsep.join([str(ROOT), str(ROOT / "plugins")]),
                              "PYTHONDONTWRITEBYTECODE": "1"})

    out = subprocess.run([sys.executable, "-c", _CHILD, str(-1 if uid is None else uid)],
                         env=env, capture_output=True, text=True, timeout=300, cwd=tmp)
    assert out.returncode == 0, out.stderr[-3000:]
    assert "Traceback" not in out.stderr, out.stderr[-3000:]
    return json.loads(out.stdout.strip().splitlines()[-1])


@pytest.fixture
def shared_tmp():
    """A temporary folder other users can enter (pytest's own is private to its user)."""
    path = Path(tempfile.mkdtemp(prefix="poissonkit-cache-perm-"))
    path.chmod(0o755)
    yield path
    for p in [path, *path.rglob("*")]:
        if p.is_dir():
            p.chmod(0o755)
    shutil.rmtree(path, ignore_errors=True)


@pytest.fixture
def unprivileged(shared_tmp) -> tuple[int | None, Path]:
    """The uid to run the child as (``None``: already unprivileged) and a folder it owns."""
    home = shared_tmp / "home"
    home.mkdir()
    if os.geteuid() != 0:
        return None, home
    if not _can_drop_privileges():
        pytest.skip("cannot switch to an unprivileged user")
    os.chown(home, NOBODY, NOBODY)
    for parent in shared_tmp.parents:  # the child must reach the folders
        if not (parent.stat().st_mode & 0o001):
            pytest.skip(f"{parent} is not reachable by uid {NOBODY}")
    for d in (ROOT, ROOT / "plugins"):
        if not os.access(d, os.R_OK) or not (d.stat().st_mode & 0o005 == 0o005):
            pytest.skip(f"{d} is not readable by uid {NOBODY}")
    return NOBODY, home


def _filled_cache(cache: Path, tmp: Path) -> Path:
    """A cache folder holding the child's entries of k=2 and k=3, written by the test user."""
    got = _run_as(None, cache, tmp)
    assert got["values"] == [3.0, 4.5, 3.0] and got["stats"][2] == [1, 0]
    folders = [p.parent for p in cache.rglob("*.nbi")]
    assert folders
    return folders[0]


def test_read_only_cache_is_used_for_reading(unprivileged, shared_tmp):
    uid, home = unprivileged
    cache = shared_tmp / "ro"
    folder = _filled_cache(cache, home)
    for p in [cache, *cache.rglob("*")]:
        p.chmod(0o555 if p.is_dir() else 0o444)
    if uid is None and os.access(folder, os.W_OK):  # pragma: no cover - odd file systems
        pytest.skip("permissions are not enforced for this user")
    got = _run_as(uid, cache, home)
    assert got["values"] == [3.0, 4.5, 3.0]
    # the entries of k=2 and k=3 are loaded, nothing is written
    assert [s[0] for s in got["stats"]] == [1, 1, 1]
    assert len(got["warnings"]) <= 1


@pytest.mark.parametrize("mode", [0o000, 0o311])  # unreadable folder; listable-not
def test_unreadable_cache_runs_without_caching(unprivileged, shared_tmp, mode):
    uid, home = unprivileged
    cache = shared_tmp / "locked"
    folder = _filled_cache(cache, home)
    for p in [cache, folder]:
        p.chmod(mode)
    if mode == 0o311:
        for f in folder.iterdir():
            f.chmod(0o000)
    try:
        got = _run_as(uid, cache, home)
    finally:
        for p in [cache, folder]:
            p.chmod(0o755)
    assert got["values"] == [3.0, 4.5, 3.0]
    assert all(s == [0, 1] for s in got["stats"][:2])
    assert len(got["warnings"]) <= 1


_FLIP_CHILD = """
import os, sys, tempfile
from pathlib import Path
from poissonkit.numerics.jit import cache_stats, jit

def scaled(k):
    @jit
    def f(x):
        return k * x
    return f

for frac in (0.2, 0.35, 0.5, 0.65, 0.8):
    with tempfile.TemporaryDirectory() as d:
        os.environ["POISSONKIT_CACHE_DIR"] = d
        assert scaled(2.0)(1.5) == 3.0
        data = next(Path(d).rglob("*.nbc"))
        raw = bytearray(data.read_bytes())
        for i in range(int(frac * len(raw)), int(frac * len(raw)) + 64, 8):
            raw[i] ^= 0xFF
        data.write_bytes(bytes(raw))
        f = scaled(2.0)
        assert f(1.5) == 3.0 and cache_stats(f) == (0, 1), (frac, cache_stats(f))
print("ok")
"""


def test_flipped_bytes_inside_an_entry_are_a_miss_not_an_abort(tmp_path):
    # a flipped byte in the object code still unpickles; LLVM then aborted the process
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT), str(ROOT / "plugins")]))
    out = subprocess.run([sys.executable, "-c", _FLIP_CHILD], env=env, capture_output=True,
                         text=True, timeout=300, cwd=tmp_path)
    assert out.returncode == 0 and out.stdout.strip() == "ok", out.stderr[-3000:]
