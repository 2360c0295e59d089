"""Warm start: compiled kernels and generated sources are reused across processes.

The probe (warm_start_probe.py) builds a scene in a fresh interpreter and reports how many
functions numba compiled; a second process with the same cache folder must compile none and
give bit-identical results. A corrupt, unwritable or disabled cache only costs time.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from numba.core import caching

from poissonkit.numerics import jit as jitmod
from poissonkit.numerics.jit import cache_dir, cache_stats, jit, load_sources, store_sources

PROBE = Path(__file__).with_name("warm_start_probe.py")


def probe(case: str, cache: Path | str) -> dict:
    env = {**os.environ, jitmod.CACHE_ENV: str(cache)}
    out = subprocess.run([sys.executable, str(PROBE), case], env=env, capture_output=True,
                         text=True, timeout=600, check=False)
    assert out.returncode == 0, out.stderr[-3000:]
    return json.loads(out.stdout.strip().splitlines()[-1])


@pytest.fixture(scope="module")
def seed_cache(tmp_path_factory):
    """A cache folder filled by one seed-scene process, and that process's report."""
    folder = tmp_path_factory.mktemp("kernels")
    return folder, probe("seed", folder)


def test_second_seed_process_compiles_nothing(seed_cache):
    folder, first = seed_cache
    assert first["compiles"] >= 5  # the pair kernel, kick, drift, time loop, ...
    second = probe("seed", folder)
    assert second["compiles"] == 0, second["compiled"]
    assert second["values"] == first["values"]


def test_second_compile_system_process_compiles_nothing(tmp_path):
    first = probe("chaplygin", tmp_path)
    assert first["compiles"] >= 5
    # sympy's work is stored too: the generated sources are on disk
    assert list((next(tmp_path.iterdir()) / "sources").glob("*.json"))
    second = probe("chaplygin", tmp_path)
    assert second["compiles"] == 0, second["compiled"]
    assert second["values"] == first["values"]
    # the cached right-hand side is the system's field: compare with sympy at the same state
    from poissonkit_nonholonomic.ball import chaplygin_ball
    import sympy as sp

    hs = chaplygin_ball(1, 2, 3, 1)
    y = [0.1, 0.2, 0.3, 0.0, 0.6, 0.8]
    point = dict(zip(hs.coords, y))
    P, H = hs.structure.matrix, sp.sympify(hs.hamiltonian)
    dH = [sp.diff(H, x) for x in hs.coords]
    N = sp.sympify(hs.multiplier)
    field = [float((N * sum(P[i, j] * dH[j] for j in range(6))).subs(point).subs(hs.params))
             for i in range(6)]
    got = [float.fromhex(v) for v in second["values"][:6]]
    np.testing.assert_allclose(got, field, rtol=1e-13, atol=1e-15)


@pytest.mark.slow
def test_second_cluster_process_compiles_nothing(tmp_path):
    first = probe("cluster", tmp_path)
    assert first["compiles"] >= 5
    second = probe("cluster", tmp_path)
    assert second["compiles"] == 0, second["compiled"]
    assert second["values"] == first["values"]


def test_corrupt_cache_is_recompiled_and_repaired(seed_cache, tmp_path):
    folder, first = seed_cache
    broken = tmp_path / "broken"
    import shutil

    shutil.copytree(folder, broken)
    files = [f for f in broken.rglob("*") if f.is_file()]
    assert files
    for k, f in enumerate(files):  # truncated, garbage and empty entries
        f.write_bytes([b"", b"\x80garbage", f.read_bytes()[:7]][k % 3])
    again = probe("seed", broken)
    assert again["values"] == first["values"]
    assert again["compiles"] > 0
    repaired = probe("seed", broken)
    assert repaired["compiles"] == 0, repaired["compiled"]
    assert repaired["values"] == first["values"]


def _scaled(k: float):
    @jit
    def f(x):
        return k * x

    return f


def test_closures_are_told_apart_by_their_values(tmp_path, monkeypatch):
    monkeypatch.setenv(jitmod.CACHE_ENV, str(tmp_path))
    assert _scaled(2.0)(1.5) == 3.0 and _scaled(3.0)(1.5) == 4.5
    g = _scaled(3.0)  # a new dispatcher: nothing in memory, one entry on disk
    assert g(1.5) == 4.5
    assert cache_stats(g) == (1, 0)
    h = _scaled(5.0)
    assert h(1.5) == 7.5
    assert cache_stats(h) == (0, 1)


def test_compiled_callees_are_part_of_the_key(tmp_path, monkeypatch):
    monkeypatch.setenv(jitmod.CACHE_ENV, str(tmp_path))

    def outer(inner):
        @jit
        def f(x):
            return inner(x) + 1.0

        return f

    assert outer(_scaled(2.0))(1.0) == 3.0
    assert outer(_scaled(10.0))(1.0) == 11.0  # same outer code, other callee: no stale hit
    again = outer(_scaled(10.0))
    assert again(1.0) == 11.0 and cache_stats(again) == (1, 0)


def test_unwritable_cache_folder_only_costs_time(tmp_path, monkeypatch):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    monkeypatch.setenv(jitmod.CACHE_ENV, str(blocker / "cache"))
    f = _scaled(7.0)
    assert f(2.0) == 14.0
    assert cache_stats(f) == (0, 1)
    store_sources("k", {"source": "x"})  # silently not stored
    assert load_sources("k") is None


def test_failing_writes_only_cost_time(tmp_path, monkeypatch):
    monkeypatch.setenv(jitmod.CACHE_ENV, str(tmp_path))

    def refuse(self, path):
        raise PermissionError(13, "read-only", path)

    monkeypatch.setattr(caching.IndexDataCacheFile, "_open_for_write", refuse)
    f = _scaled(11.0)
    assert f(2.0) == 22.0
    assert not list(tmp_path.rglob("*.nbi"))


def test_cache_can_be_switched_off(tmp_path, monkeypatch):
    monkeypatch.setenv(jitmod.CACHE_ENV, "off")
    assert cache_dir() is None
    f = _scaled(13.0)
    assert f(1.0) == 13.0 and cache_stats(f) == (0, 1)
    monkeypatch.setenv(jitmod.CACHE_ENV, str(tmp_path))
    assert cache_dir().parent == tmp_path
    assert "numba" in cache_dir().name


def test_stored_sources_round_trip_and_reject_corruption(tmp_path, monkeypatch):
    monkeypatch.setenv(jitmod.CACHE_ENV, str(tmp_path))
    key = jitmod.source_key("test", "sources")
    store_sources(key, {"rhs_gen": "def rhs_gen(y, out):\n    return out"})
    assert load_sources(key) == {"rhs_gen": "def rhs_gen(y, out):\n    return out"}
    path = cache_dir() / "sources" / f"{key}.json"
    path.write_text(json.dumps({"key": "other", "sources": {}}))
    assert load_sources(key) is None and not path.exists()
    path.write_text("{not json")
    assert load_sources(key) is None and not path.exists()


def test_jit_refuses_numba_cache_option():
    with pytest.raises(TypeError, match="cache"):
        jit(cache=True)


def test_unidentifiable_callees_make_callers_uncacheable(tmp_path, monkeypatch):
    import numba

    from poissonkit.numerics.jit import compile_generated, dispatcher_token

    monkeypatch.setenv(jitmod.CACHE_ENV, str(tmp_path))

    def foreign(k):
        @numba.njit
        def g(x):
            return k * x

        return g

    calls = [compile_generated("def w(x):\n    return base(x)", "w", {"base": foreign(k)})
             for k in (2.0, 3.0)]
    assert [w(1.0) for w in calls] == [2.0, 3.0]
    assert [dispatcher_token(w) for w in calls] == [None, None]


def test_symbols_of_different_processes_differ(tmp_path):
    # machine code loaded from the cache must never share a symbol name with code compiled in
    # the loading process (numba links callees by name): ids start at random in each process
    script = ("from poissonkit.numerics.jit import jit\n"
              "f = jit(lambda x: x + 1.0)\n"
              "f(1.0)\n"
              "print(next(iter(f.overloads.values())).fndesc.mangled_name)\n")
    env = {**os.environ, jitmod.CACHE_ENV: "off"}
    names = {subprocess.run([sys.executable, "-c", script], env=env, capture_output=True,
                            text=True, check=True).stdout.strip() for _ in range(2)}
    assert len(names) == 2
